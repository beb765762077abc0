#pragma once
// A trained learner as bytes and back, whatever the learner: the versioned model file of its
// kind (engine/lwpr/lwpr_model_file.hpp "AFLWPR", engine/ssgpr/ssgpr_model_file.hpp "AFSSGP"),
// recognised by its magic when read. This is what a job stores in the results database
// (learning.store_model) and what a job starts from (learning.initial_model); like the factory
// (learner_factory.hpp), it is the one place that knows the concrete learners.
#include "engine/learner/learner.hpp"

#include <memory>
#include <string>

namespace armfarm {

/// The learner's model file (bit-exact: loading it predicts exactly what `learner` predicts).
/// An SSGPR learner that fits its hyperparameters stores its fitted model (an SSGPR file); before
/// its fit it has none, and this throws std::invalid_argument saying so.
std::string encode_learner_model(const Learner& learner);

/// The learner a model file holds. Throws std::runtime_error naming the format and the byte
/// for an unknown magic, a truncated, corrupt or future-version file.
std::unique_ptr<Learner> decode_learner_model(const std::string& bytes);

/// The learner's LWPR model, or null for another learner.
const lwpr::LwprModel* find_lwpr_model(const Learner& learner);

/// The learner's SSGPR model (the one inside an SSGPR learner that fits its hyperparameters, once
/// fitted), or null.
const ssgpr::SsgprModel* find_ssgpr_model(const Learner& learner);

/// "lwpr" or "ssgpr": the kind of learner a model file holds, by its magic; "" if neither.
std::string find_learner_model_kind(const std::string& bytes);

}  // namespace armfarm
