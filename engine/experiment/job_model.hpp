#pragma once
// The arm one job runs on: the file's model (load_arm_model_file) with the job configuration's
// choices applied, the end effector (end_effector.link / .offset) and the start posture
// (start_posture). The one place a configuration is applied to a model: the runner's
// expansion check, its job-cost estimate and its executor (so `armfarm run`, `expand`, `slurm`
// and `job`), and the `model` commands all call make_job_model, and run_experiment() checks
// that it was.
#include "engine/experiment/job_config.hpp"
#include "engine/model/arm_model.hpp"

namespace armfarm {

/// `file_model` with the end effector chosen from config.end_effector (choose_end_effector:
/// the named link, else the file's choice, else its single leaf) and, when config.start_posture
/// is not empty, every movable joint's start_position set from it (one value per movable joint,
/// in joint-number order). Throws ModelError naming file_model.source_file when the end
/// effector cannot be chosen (an unknown link; several leaves and no choice: the message lists
/// them and names end_effector.link), std::invalid_argument ("start_posture: ...") when the
/// posture has the wrong size. Its limits are validate()'s (job_config_validation.hpp: a
/// start_posture outside a joint's range names the joint and the range).
ArmModel make_job_model(const ArmModel& file_model, const JobConfig& config);

/// "" when `model` is what make_job_model gives for `config` in the choices the job reads (an
/// end effector is chosen; the start posture, when configured, is the model's), else what differs.
std::string check_job_model(const ArmModel& model, const JobConfig& config);

}  // namespace armfarm
