// Suggestions for misspelt keys.
#include "runner/spec/did_you_mean.hpp"

#include <gtest/gtest.h>

namespace armfarm {
namespace {

TEST(DidYouMean, SuggestsCloseNamesOnly) {
  const std::vector<std::string> keys = {"grid", "zip", "random", "repeat"};
  EXPECT_EQ(calc_closest_name("gird", keys), "grid");
  EXPECT_EQ(calc_closest_name("repeats", keys), "repeat");
  EXPECT_FALSE(calc_closest_name("temperature", keys).has_value());
  EXPECT_EQ(make_did_you_mean("init_d", {"init_D", "init_alpha"}), " (did you mean 'init_D'?)");
  EXPECT_EQ(make_did_you_mean("xyzzy", {"init_D"}), "");
}

}  // namespace
}  // namespace armfarm
