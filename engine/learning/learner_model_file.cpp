#include "engine/learning/learner_model_file.hpp"

#include "engine/lwpr/lwpr_model_file.hpp"
#include "engine/ssgpr/ssgpr_model_file.hpp"

#include <sstream>
#include <stdexcept>

namespace armfarm {
namespace {

bool starts_with(const std::string& bytes, const char* magic) { return bytes.compare(0, 8, magic, 8) == 0; }

}  // namespace

std::string find_learner_model_kind(const std::string& bytes) {
  if (starts_with(bytes, "AFLWPR\r\n")) return "lwpr";
  if (starts_with(bytes, "AFSSGP\r\n")) return "ssgpr";
  return "";
}

std::string encode_learner_model(const Learner& learner) {
  std::ostringstream out(std::ios::binary);
  if (const auto* lwpr = dynamic_cast<const lwpr::LwprModel*>(&learner)) {
    lwpr::write_lwpr_model(*lwpr, out);
  } else if (const auto* ssgpr = dynamic_cast<const ssgpr::SsgprModel*>(&learner)) {
    ssgpr::write_ssgpr_model(*ssgpr, out);
  } else {
    throw std::invalid_argument("learner model file: this kind of learner has no model file format");
  }
  return out.str();
}

std::unique_ptr<Learner> decode_learner_model(const std::string& bytes) {
  std::istringstream in(bytes, std::ios::binary);
  const std::string kind = find_learner_model_kind(bytes);
  if (kind == "lwpr") return std::make_unique<lwpr::LwprModel>(lwpr::load_lwpr_model(in));
  if (kind == "ssgpr") return std::make_unique<ssgpr::SsgprModel>(ssgpr::load_ssgpr_model(in));
  throw std::runtime_error("learner model file: byte 0: not an armfarm model file (neither an LWPR nor an SSGPR magic)");
}

}  // namespace armfarm
