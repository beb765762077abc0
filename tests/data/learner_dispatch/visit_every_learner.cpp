// Fixture for LearnerDispatch.AMissingCaseDoesNotCompile
// (tests/engine/learner/learner_dispatch_test.cmake): visit_learner (engine/learner/learner.hpp)
// with a case for each concrete learner compiles; with
// ARMFARM_LEAVE_OUT_A_CASE the SsgprFittingLearner case is missing, and it must not compile (the
// copy of the dispatch that had no such case stored no fitted SSGPR model: issue 28).
#include "engine/learner/learner.hpp"
#include "engine/lwpr/lwpr_model.hpp"
#include "engine/ssgpr/ssgpr_fitting_learner.hpp"
#include "engine/ssgpr/ssgpr_model.hpp"

namespace armfarm {

int find_learner_number(const Learner& learner) {
  return visit_learner(
      learner, [](const lwpr::LwprModel&) { return 1; }, [](const ssgpr::SsgprModel&) { return 2; }
#ifndef ARMFARM_LEAVE_OUT_A_CASE
      ,
      [](const ssgpr::SsgprFittingLearner&) { return 3; }
#endif
  );
}

}  // namespace armfarm
