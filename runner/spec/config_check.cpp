#include "runner/spec/config_check.hpp"

#include "base/did_you_mean.hpp"
#include "runner/spec/json_document.hpp"

#include <cmath>

namespace armfarm {
namespace {

const nlohmann::json& number_reference() {
  static const nlohmann::json reference = 0.0;
  return reference;
}

std::string describe_type(const nlohmann::json& reference) {
  switch (reference.type()) {
    case nlohmann::json::value_t::object: return "an object";
    case nlohmann::json::value_t::array: return "an array";
    case nlohmann::json::value_t::string: return "a string";
    case nlohmann::json::value_t::boolean: return "true or false";
    case nlohmann::json::value_t::number_float: return "a number";
    case nlohmann::json::value_t::number_integer:
    case nlohmann::json::value_t::number_unsigned: return "an integer";
    default: return "a value";
  }
}

std::string show(const nlohmann::json& value) {
  std::string text = value.dump();
  return text.size() > 40 ? text.substr(0, 37) + "..." : text;
}

std::string child_path(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }

}  // namespace

nlohmann::json calc_checked_value(const nlohmann::json& value, const nlohmann::json& reference, const std::string& path,
                                  std::vector<CheckedValueProblem>& errors) {
  const std::string where = path.empty() ? std::string("(configuration)") : path;
  auto wrong_type = [&] {
    if (value.is_string() && reference.is_number() && is_non_finite_number_text(value.get<std::string>())) {
      errors.push_back({where, "expected a finite number, got " + show(value) +
                                   " (NaN and infinities are not numbers a job configuration can hold)"});
      return value;
    }
    errors.push_back({where, "expected " + describe_type(reference) + ", got " + show(value)});
    return value;
  };
  switch (reference.type()) {
    case nlohmann::json::value_t::null:
      if (value.is_string() && is_non_finite_number_text(value.get<std::string>())) {
        errors.push_back({where, "got " + show(value) + ", which is not a number a job configuration can hold" +
                                     " (NaN and infinities are refused)"});
      }
      return value;
    case nlohmann::json::value_t::object: {
      if (!value.is_object()) return wrong_type();
      nlohmann::json checked = nlohmann::json::object();
      std::vector<std::string> known;
      for (const auto& item : reference.items()) known.push_back(item.key());
      for (const auto& [key, item] : value.items()) {
        const auto found = reference.find(key);
        if (found == reference.end()) {
          errors.push_back({child_path(path, key), "unknown key" + make_did_you_mean(key, known)});
          continue;
        }
        checked[key] = calc_checked_value(item, *found, child_path(path, key), errors);
      }
      return checked;
    }
    case nlohmann::json::value_t::array: {
      if (!value.is_array()) return wrong_type();
      const nlohmann::json& element = reference.empty() ? number_reference() : reference[0];
      nlohmann::json checked = nlohmann::json::array();
      for (std::size_t i = 0; i < value.size(); ++i) {
        checked.push_back(calc_checked_value(value[i], element, where + "[" + std::to_string(i) + "]", errors));
      }
      return checked;
    }
    case nlohmann::json::value_t::number_float:
      if (!value.is_number()) return wrong_type();
      return value.get<double>();
    case nlohmann::json::value_t::number_integer:
    case nlohmann::json::value_t::number_unsigned:
      if (value.is_number_integer()) return value;
      if (value.is_number_float()) {
        const double x = value.get<double>();
        if (std::isfinite(x) && x == std::floor(x) && std::fabs(x) < 9.0e15) return static_cast<std::int64_t>(x);
      }
      return wrong_type();
    case nlohmann::json::value_t::string:
      if (!value.is_string()) return wrong_type();
      return value;
    case nlohmann::json::value_t::boolean:
      if (!value.is_boolean()) return wrong_type();
      return value;
    default:
      return value;
  }
}

const nlohmann::json* find_schema_reference(const nlohmann::json& defaults, const ConfigPath& segments,
                                            std::string& problem) {
  const nlohmann::json* node = &defaults;
  for (std::size_t i = 0; i < segments.size(); ++i) {
    if (node->is_null()) return node;  // free-form below this point
    const PathSegment& segment = segments[i];
    if (segment.index) {
      if (!node->is_array()) {
        problem = "'" + segments.to_string(i) + "' is not an array";
        return nullptr;
      }
      node = node->empty() ? &number_reference() : &(*node)[0];
      continue;
    }
    if (!node->is_object()) {
      problem = i == 0 ? "the configuration is not an object" : "'" + segments.to_string(i) + "' is not an object";
      return nullptr;
    }
    const auto found = node->find(segment.key);
    if (found == node->end()) {
      std::vector<std::string> keys;
      for (const auto& item : node->items()) keys.push_back(item.key());
      problem = "no key '" + segment.key + "' in " +
                (i == 0 ? std::string("the configuration") : "'" + segments.to_string(i) + "'") +
                make_did_you_mean(segment.key, keys);
      return nullptr;
    }
    node = &*found;
  }
  return node;
}

void merge_config_into(nlohmann::json& target, const nlohmann::json& overrides) {
  if (!target.is_object() || !overrides.is_object()) {
    target = overrides;
    return;
  }
  for (const auto& [key, value] : overrides.items()) {
    if (value.is_object() && target.contains(key) && target[key].is_object()) {
      merge_config_into(target[key], value);
    } else {
      target[key] = value;
    }
  }
}

}  // namespace armfarm
