#pragma once
// Collection: passes of the plant over a trajectory under PD feedback alone, recording every
// tick's (x, y) sample for batch training or held-out testing. Repeats of a collection are
// different realisations of the run, never identical copies: each repeat after the first
// measures its angles with sensor noise (learning.collect_repeat_noise_q), starts off the
// trajectory when configured (learning.collect_start_spread, default 0), and every pass's
// sensors carry noise when configured (learning.collect_noise_q/_qd).
#include "engine/experiment/control_pass.hpp"

#include <cstdint>
#include <functional>
#include <string_view>
#include <vector>

namespace armfarm {

/// Where the randomness of a collection comes from: `purpose` names its streams
/// ("<purpose>.start_state", "<purpose>.sensor_noise") so training and held-out collections
/// draw independently from one job seed.
struct CollectionPlan {
  const JointTrajectory* trajectory = nullptr;
  int repeats = 1;
  std::string_view purpose = "collection";
};

/// Runs plan.repeats passes under feedback at learning.collect_gain_scale on `plant` and
/// appends their samples (repeat after repeat). Returns the first pass that did not finish.
PassResult collect_samples(JobSetup& setup, ArmSimulation& plant, const CollectionPlan& plan, std::vector<Sample>& samples,
                           const std::function<bool()>& should_stop);

}  // namespace armfarm
