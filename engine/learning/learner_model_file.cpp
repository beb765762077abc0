#include "engine/learning/learner_model_file.hpp"

#include "engine/lwpr/lwpr_model_file.hpp"
#include "engine/ssgpr/ssgpr_fitting_learner.hpp"
#include "engine/ssgpr/ssgpr_model_file.hpp"

#include <sstream>
#include <string>
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
  visit_learner(
      learner, [&](const lwpr::LwprModel& lwpr) { lwpr::write_lwpr_model(lwpr, out); },
      [&](const ssgpr::SsgprModel& ssgpr) { ssgpr::write_ssgpr_model(ssgpr, out); },
      [&](const ssgpr::SsgprFittingLearner& fitting) {
        if (!fitting.fitted()) {
          throw std::invalid_argument("learner model file: the SSGPR hyperparameter fit has not happened (" +
                                      std::to_string(fitting.n_updates()) + " of its " + std::to_string(fitting.fit_samples()) +
                                      " samples given): there is no model yet");
        }
        ssgpr::write_ssgpr_model(fitting.model(), out);
      });
  return out.str();
}

const lwpr::LwprModel* find_lwpr_model(const Learner& learner) {
  return visit_learner(
      learner, [](const lwpr::LwprModel& model) { return &model; },
      [](const ssgpr::SsgprModel&) -> const lwpr::LwprModel* { return nullptr; },
      [](const ssgpr::SsgprFittingLearner&) -> const lwpr::LwprModel* { return nullptr; });
}

const ssgpr::SsgprModel* find_ssgpr_model(const Learner& learner) {
  return visit_learner(
      learner, [](const lwpr::LwprModel&) -> const ssgpr::SsgprModel* { return nullptr; },
      [](const ssgpr::SsgprModel& model) { return &model; },
      [](const ssgpr::SsgprFittingLearner& fitting) { return fitting.fitted() ? &fitting.model() : nullptr; });
}

std::unique_ptr<Learner> decode_learner_model(const std::string& bytes) {
  std::istringstream in(bytes, std::ios::binary);
  const std::string kind = find_learner_model_kind(bytes);
  if (kind == "lwpr") return std::make_unique<lwpr::LwprModel>(lwpr::load_lwpr_model(in));
  if (kind == "ssgpr") return std::make_unique<ssgpr::SsgprModel>(ssgpr::load_ssgpr_model(in));
  throw std::runtime_error("learner model file: byte 0: not an armfarm model file (neither an LWPR nor an SSGPR magic)");
}

}  // namespace armfarm
