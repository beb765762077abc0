#pragma once
// The path of one element of a job configuration, typed: its segments (an object key or an array
// index) and the one parser and printer of its text form, "learning.lwpr.init_D",
// "control.kp[1]", "trajectory.waypoints[2][0]". The spec reader, the config reader, the store's
// views and the analysis tables all read paths through parse_config_path (base/README.md).
//
// Indices: the text form's "[i]" is the JSON array index, 0-based as in every JSON tool (jq,
// JSON pointers), because a spec path addresses an element of a JSON tree; the joints a user
// sees (tables, --joint, metric columns "_j1") are 1-based, and a list indexed by joint is
// element joint − 1 here (sweeps/README.md, "Keys").
//
// Standard library only, so that every layer may use it: the lookups into a JSON tree live with
// the JSON (runner/spec/config_path.hpp, analysis/sweep_data.cpp).
#include <charconv>
#include <cstddef>
#include <initializer_list>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

namespace armfarm {

/// One step of a path: an object key, or (when `index` is set) an array element.
struct PathSegment {
  std::string key;                   ///< used when `index` is empty
  std::optional<std::size_t> index;  ///< 0-based array element
  friend bool operator==(const PathSegment& a, const PathSegment& b) { return a.key == b.key && a.index == b.index; }
  friend bool operator!=(const PathSegment& a, const PathSegment& b) { return !(a == b); }
};

/// A parsed path: a sequence of segments, the first of which is a key (or none: the root).
class ConfigPath {
 public:
  using const_iterator = std::vector<PathSegment>::const_iterator;

  ConfigPath() = default;
  ConfigPath(std::initializer_list<PathSegment> segments) : segments_(segments) {}
  explicit ConfigPath(std::vector<PathSegment> segments) : segments_(std::move(segments)) {}

  std::size_t size() const { return segments_.size(); }
  bool empty() const { return segments_.empty(); }
  const PathSegment& operator[](std::size_t i) const { return segments_[i]; }
  const PathSegment& front() const { return segments_.front(); }
  const PathSegment& back() const { return segments_.back(); }
  const_iterator begin() const { return segments_.begin(); }
  const_iterator end() const { return segments_.end(); }
  const std::vector<PathSegment>& segments() const { return segments_; }

  /// The path of the first `count` segments (the whole path when count ≥ size()).
  ConfigPath prefix(std::size_t count) const {
    return ConfigPath(std::vector<PathSegment>(segments_.begin(), segments_.begin() + static_cast<std::ptrdiff_t>(
                                                                                         count < size() ? count : size())));
  }
  /// True when this path is `other` or lies inside it ("control.kp[1]" is within "control").
  bool is_within(const ConfigPath& other) const {
    if (other.size() > size()) return false;
    for (std::size_t i = 0; i < other.size(); ++i) {
      if (segments_[i] != other.segments_[i]) return false;
    }
    return true;
  }
  /// True when one of the two paths is within the other (setting either changes the other).
  bool overlaps(const ConfigPath& other) const { return is_within(other) || other.is_within(*this); }

  /// The path one key further down.
  ConfigPath child(std::string key) const {
    ConfigPath path = *this;
    path.segments_.push_back({std::move(key), std::nullopt});
    return path;
  }
  /// The path of element `index` (0-based) of the array this path names.
  ConfigPath element(std::size_t index) const {
    ConfigPath path = *this;
    path.segments_.push_back({"", index});
    return path;
  }

  /// The text form of the first `count` segments (all by default): keys joined by '.', indices
  /// as "[i]". It parses back to the same path.
  std::string to_string(std::size_t count = static_cast<std::size_t>(-1)) const {
    std::string text;
    for (std::size_t i = 0; i < segments_.size() && i < count; ++i) {
      if (segments_[i].index) {
        text += '[';
        text += std::to_string(*segments_[i].index);
        text += ']';
      } else {
        if (!text.empty()) text += '.';
        text += segments_[i].key;
      }
    }
    return text;
  }

  friend bool operator==(const ConfigPath& a, const ConfigPath& b) { return a.segments_ == b.segments_; }
  friend bool operator!=(const ConfigPath& a, const ConfigPath& b) { return !(a == b); }

 private:
  std::vector<PathSegment> segments_;
};

/// The project's one parser of a path's text form. Throws std::invalid_argument, whose message
/// says what is malformed without repeating the path ("empty key", "index 'x' is not a number"):
/// the caller names the file and place.
inline ConfigPath parse_config_path(std::string_view text) {
  std::vector<PathSegment> segments;
  if (text.empty()) throw std::invalid_argument("empty path");
  // After a segment: a '.' must be followed by a key.
  const auto skip_dot = [&text](std::size_t& i) {
    if (i < text.size() && text[i] == '.') {
      ++i;
      if (i == text.size()) throw std::invalid_argument("ends with '.'");
    }
  };
  std::size_t i = 0;
  while (i < text.size()) {
    if (text[i] == '[') {
      const std::size_t close = text.find(']', i);
      if (close == std::string_view::npos || close == i + 1) throw std::invalid_argument("unclosed or empty '['");
      const std::string_view digits = text.substr(i + 1, close - i - 1);
      for (char c : digits) {
        if (c < '0' || c > '9') throw std::invalid_argument("index '" + std::string(digits) + "' is not a number");
      }
      if (segments.empty()) throw std::invalid_argument("a path starts with a key");
      std::size_t index = 0;
      const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), index);
      if (error != std::errc() || end != digits.data() + digits.size()) {  // only digits: it overflows
        const std::string shown = digits.size() <= 24 ? std::string(digits) : std::string(digits.substr(0, 24)) + "…";
        throw std::invalid_argument("index " + shown + " is too large for an array index");
      }
      segments.push_back({"", index});
      i = close + 1;
      skip_dot(i);
      continue;
    }
    std::size_t end = i;
    while (end < text.size() && text[end] != '.' && text[end] != '[') ++end;
    if (end == i) throw std::invalid_argument("empty key");
    segments.push_back({std::string(text.substr(i, end - i)), std::nullopt});
    i = end;
    skip_dot(i);
  }
  return ConfigPath(std::move(segments));
}

}  // namespace armfarm
