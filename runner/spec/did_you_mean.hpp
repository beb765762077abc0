#pragma once
// "Did you mean" suggestions for misspelt keys.
#include <optional>
#include <string>
#include <vector>

namespace armfarm {

/// The candidate closest to `name` by edit distance (Levenshtein, a case change counting 1), if
/// it is close enough to be a plausible typo (distance ≤ max(2, |name|/3)).
std::optional<std::string> calc_closest_name(const std::string& name, const std::vector<std::string>& candidates);

/// " (did you mean 'x'?)" or "" when nothing is close.
std::string make_did_you_mean(const std::string& name, const std::vector<std::string>& candidates);

}  // namespace armfarm
