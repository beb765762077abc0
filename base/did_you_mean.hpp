#pragma once
// "Did you mean" for a misspelt name (a spec key, an LWPR parameter, a table column, a URDF
// element): the project's one edit distance and the one search for the closest candidate. Each
// caller says how far a typo may go and words its own message. Standard library only, so that
// every layer may use it (base/README.md).
#include <algorithm>
#include <cctype>
#include <cstddef>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace armfarm {

/// Levenshtein distance: the fewest insertions, deletions and substitutions (each 1) that turn
/// `a` into `b`. With `ignore_case`, ASCII letters that differ only in case are equal; without,
/// a case change counts 1.
inline std::size_t calc_edit_distance(std::string_view a, std::string_view b, bool ignore_case = false) {
  const auto same = [ignore_case](char x, char y) {
    if (!ignore_case) return x == y;
    return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
  };
  std::vector<std::size_t> row(b.size() + 1);  // row[j]: distance of a[0, i) to b[0, j)
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];  // distance of a[0, i-1) to b[0, j-1)
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (same(a[i - 1], b[j - 1]) ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

/// How many edits a typo of `name` may have by default: max(2, |name| / 3).
inline std::size_t calc_typo_limit(std::string_view name) { return std::max<std::size_t>(2, name.size() / 3); }

/// How find_closest_name compares a name with a candidate.
struct NameMatch {
  std::size_t max_distance = 2;  ///< the most edits a candidate may be away
  bool ignore_case = false;      ///< letters compare case-insensitively
  bool last_segment_too = false; ///< a dotted candidate also matches by its last segment ("gain_scale" for "control.gain_scale")
};

/// The candidate nearest to `name` (the first of equally near ones, in the order of
/// `candidates`, any range of strings) when it is at most match.max_distance edits away; else
/// nullopt.
template <typename Names = std::initializer_list<std::string_view>>
std::optional<std::string> find_closest_name(std::string_view name, const Names& candidates, const NameMatch& match) {
  std::optional<std::string> best;
  std::size_t best_distance = match.max_distance + 1;
  for (const auto& entry : candidates) {
    const std::string_view candidate(entry);
    std::size_t distance = calc_edit_distance(name, candidate, match.ignore_case);
    if (match.last_segment_too) {
      const std::size_t dot = candidate.rfind('.');
      if (dot != std::string_view::npos) distance = std::min(distance, calc_edit_distance(name, candidate.substr(dot + 1), match.ignore_case));
    }
    if (distance < best_distance) {
      best_distance = distance;
      best = std::string(candidate);
    }
  }
  return best;
}

/// find_closest_name within the default limit (calc_typo_limit(name)), case-sensitive.
inline std::optional<std::string> find_closest_name(std::string_view name, const std::vector<std::string>& candidates) {
  return find_closest_name(name, candidates, NameMatch{calc_typo_limit(name)});
}

/// " (did you mean 'x'?)" for the closest candidate x, or "" when none is close.
template <typename Names>
std::string make_did_you_mean(std::string_view name, const Names& candidates, const NameMatch& match) {
  const std::optional<std::string> closest = find_closest_name(name, candidates, match);
  return closest ? " (did you mean '" + *closest + "'?)" : "";
}

/// make_did_you_mean within the default limit, case-sensitive.
inline std::string make_did_you_mean(std::string_view name, const std::vector<std::string>& candidates) {
  return make_did_you_mean(name, candidates, NameMatch{calc_typo_limit(name)});
}

}  // namespace armfarm
