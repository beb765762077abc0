// The long-form export's signal names: per-joint columns (j1, j2, ...) give the joint, other
// columns their name after the series'.
#include "runner/io/sweep_export.hpp"

#include <gtest/gtest.h>

namespace armfarm {
namespace {

TEST(LongFormSignal, PerJointColumnsGiveTheJointOthersTheirName) {
  EXPECT_EQ(make_long_form_signal("PHI", "j3").joint, 3);
  EXPECT_EQ(make_long_form_signal("PHI", "j3").signal, "PHI");
  EXPECT_EQ(make_long_form_signal("PHI", "j12").joint, 12);
  EXPECT_FALSE(make_long_form_signal("POS", "x").joint);
  EXPECT_EQ(make_long_form_signal("POS", "x").signal, "POS.x");
  EXPECT_EQ(make_long_form_signal("TRIAL", "fb_abs_avg").signal, "TRIAL.fb_abs_avg");
  EXPECT_FALSE(make_long_form_signal("X", "j0").joint);
  EXPECT_FALSE(make_long_form_signal("X", "j").joint);
  EXPECT_FALSE(make_long_form_signal("X", "jx1").joint);
}

}  // namespace
}  // namespace armfarm
