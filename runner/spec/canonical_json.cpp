#include "runner/spec/canonical_json.hpp"

#include "runner/spec/input_files.hpp"

#include <xxhash.h>

#include <cmath>
#include <cstdio>

namespace armfarm {
namespace {

constexpr double kExactIntegerLimit = 9007199254740992.0;  // 2^53

void write_canonical(const nlohmann::json& value, std::string& out) {
  switch (value.type()) {
    case nlohmann::json::value_t::object: {
      out += '{';
      bool first = true;
      for (const auto& [key, item] : value.items()) {  // std::map: keys in byte order
        if (!first) out += ',';
        first = false;
        out += nlohmann::json(key).dump();
        out += ':';
        write_canonical(item, out);
      }
      out += '}';
      return;
    }
    case nlohmann::json::value_t::array: {
      out += '[';
      for (std::size_t i = 0; i < value.size(); ++i) {
        if (i > 0) out += ',';
        write_canonical(value[i], out);
      }
      out += ']';
      return;
    }
    case nlohmann::json::value_t::number_float: {
      const double x = value.get<double>();
      if (std::isfinite(x) && x == std::floor(x) && std::fabs(x) < kExactIntegerLimit) {
        out += std::to_string(static_cast<long long>(x));  // also turns -0 into 0
      } else {
        out += value.dump();  // shortest text that reads back to the same double
      }
      return;
    }
    default:
      out += value.dump();  // null, booleans, integers, strings
  }
}

}  // namespace

std::string calc_canonical_json(const nlohmann::json& value) {
  std::string out;
  write_canonical(value, out);
  return out;
}

std::string calc_text_hash(const std::string& text) {
  const XXH128_hash_t hash = XXH3_128bits(text.data(), text.size());
  char hex[33];
  std::snprintf(hex, sizeof hex, "%016llx%016llx", static_cast<unsigned long long>(hash.high64),
                static_cast<unsigned long long>(hash.low64));
  return hex;
}

std::string calc_job_key(const nlohmann::json& config) {
  return calc_text_hash(calc_canonical_json(make_job_key_document(config)));
}

}  // namespace armfarm
