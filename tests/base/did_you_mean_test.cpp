// The one edit distance and did-you-mean: distances against hand-counted edits, the typo limit,
// first-of-equals, case rules and the dotted-name rule the tables use.
#include "base/did_you_mean.hpp"

#include <gtest/gtest.h>

#include <set>

namespace armfarm {
namespace {

TEST(DidYouMean, EditDistanceCountsInsertionsDeletionsAndSubstitutions) {
  EXPECT_EQ(calc_edit_distance("", ""), 0u);
  EXPECT_EQ(calc_edit_distance("", "abc"), 3u);
  EXPECT_EQ(calc_edit_distance("abc", ""), 3u);
  EXPECT_EQ(calc_edit_distance("kitten", "sitting"), 3u);  // k→s, e→i, +g
  EXPECT_EQ(calc_edit_distance("gird", "grid"), 2u);       // a transposition is two edits
  EXPECT_EQ(calc_edit_distance("flaw", "lawn"), 2u);
  EXPECT_EQ(calc_edit_distance("init_d", "init_D"), 1u);
  EXPECT_EQ(calc_edit_distance("init_d", "init_D", true), 0u);
  EXPECT_EQ(calc_edit_distance("INIT_DX", "init_d", true), 1u);
  for (const char* a : {"axsi", "collision", "w_gen"}) {
    for (const char* b : {"axis", "collison", "w_prune"}) EXPECT_EQ(calc_edit_distance(a, b), calc_edit_distance(b, a)) << a << b;
  }
}

TEST(DidYouMean, SuggestsCloseNamesOnly) {
  const std::vector<std::string> keys = {"grid", "zip", "random", "repeat"};
  EXPECT_EQ(find_closest_name("gird", keys), "grid");
  EXPECT_EQ(find_closest_name("repeats", keys), "repeat");
  EXPECT_FALSE(find_closest_name("temperature", keys).has_value());
  EXPECT_EQ(make_did_you_mean("init_d", {"init_D", "init_alpha"}), " (did you mean 'init_D'?)");
  EXPECT_EQ(make_did_you_mean("xyzzy", {"init_D"}), "");
  EXPECT_EQ(calc_typo_limit("abc"), 2u);
  EXPECT_EQ(calc_typo_limit("learning.lwpr.init_D"), 6u);  // 20 characters / 3
}

TEST(DidYouMean, TheFirstOfEquallyCloseCandidatesWinsAndTheLimitIsInclusive) {
  EXPECT_EQ(find_closest_name("cat", {"bat", "cut", "hat"}, NameMatch{1}), "bat");
  EXPECT_EQ(find_closest_name("cat", {"dog", "cart"}, NameMatch{1}), "cart");
  EXPECT_FALSE(find_closest_name("cat", {"dog", "carts"}, NameMatch{1}).has_value());
  const std::set<std::string> urdf_children = {"origin", "parent", "child", "axis", "limit"};
  EXPECT_EQ(find_closest_name("axsi", urdf_children, NameMatch{2}), "axis");
  EXPECT_EQ(make_did_you_mean("INIT_DX", std::vector<std::string>{"init_D", "w_gen"}, NameMatch{3, true}), " (did you mean 'init_D'?)");
  EXPECT_EQ(make_did_you_mean("INIT_DX", std::vector<std::string>{"init_D", "w_gen"}, NameMatch{3}), "");
}

TEST(DidYouMean, ADottedNameAlsoMatchesByItsLastSegmentWhenAsked) {
  const std::vector<std::string> paths = {"learning.mode", "control.gain_scale"};
  EXPECT_FALSE(find_closest_name("gain_scal", paths).has_value());
  EXPECT_EQ(find_closest_name("gain_scal", paths, NameMatch{3, false, true}), "control.gain_scale");
}

}  // namespace
}  // namespace armfarm
