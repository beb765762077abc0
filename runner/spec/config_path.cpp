#include "runner/spec/config_path.hpp"

#include "base/did_you_mean.hpp"

#include <cctype>
#include <charconv>
#include <stdexcept>

namespace armfarm {

std::vector<PathSegment> parse_config_path(const std::string& path) {
  std::vector<PathSegment> segments;
  std::size_t i = 0;
  if (path.empty()) throw std::invalid_argument("empty path");
  while (i < path.size()) {
    if (path[i] == '[') {
      const std::size_t close = path.find(']', i);
      if (close == std::string::npos || close == i + 1) throw std::invalid_argument("unclosed or empty '['");
      const std::string digits = path.substr(i + 1, close - i - 1);
      for (char c : digits) {
        if (!std::isdigit(static_cast<unsigned char>(c))) throw std::invalid_argument("index '" + digits + "' is not a number");
      }
      if (segments.empty()) throw std::invalid_argument("a path starts with a key");
      std::size_t index = 0;
      const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), index);
      if (error != std::errc() || end != digits.data() + digits.size()) {  // only digits: it overflows
        throw std::invalid_argument("index " + (digits.size() <= 24 ? digits : digits.substr(0, 24) + "…") +
                                    " is too large for an array index");
      }
      segments.push_back({"", index});
      i = close + 1;
      if (i < path.size() && path[i] == '.') {
        ++i;
        if (i == path.size()) throw std::invalid_argument("ends with '.'");
      }
      continue;
    }
    std::size_t end = i;
    while (end < path.size() && path[end] != '.' && path[end] != '[') ++end;
    if (end == i) throw std::invalid_argument("empty key");
    segments.push_back({path.substr(i, end - i), std::nullopt});
    i = end;
    if (i < path.size() && path[i] == '.') {
      ++i;
      if (i == path.size()) throw std::invalid_argument("ends with '.'");
    }
  }
  return segments;
}

std::string make_config_path(const std::vector<PathSegment>& segments, std::size_t count) {
  std::string text;
  for (std::size_t i = 0; i < segments.size() && i < count; ++i) {
    if (segments[i].index) {
      text += "[" + std::to_string(*segments[i].index) + "]";
    } else {
      text += (text.empty() ? "" : ".") + segments[i].key;
    }
  }
  return text;
}

const nlohmann::json* find_config_element(const nlohmann::json& config, const std::vector<PathSegment>& segments,
                                          std::string& problem) {
  const nlohmann::json* node = &config;
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const PathSegment& segment = segments[i];
    const std::string parent = i == 0 ? std::string("the configuration") : "'" + make_config_path(segments, i) + "'";
    if (segment.index) {
      if (!node->is_array()) {
        problem = parent + " is not an array";
        return nullptr;
      }
      if (*segment.index >= node->size()) {
        problem = "index " + std::to_string(*segment.index) + " is out of range: " + parent + " has " +
                  std::to_string(node->size()) + " elements";
        return nullptr;
      }
      node = &(*node)[*segment.index];
    } else {
      if (!node->is_object()) {
        problem = parent + " is not an object";
        return nullptr;
      }
      const auto found = node->find(segment.key);
      if (found == node->end()) {
        std::vector<std::string> keys;
        for (const auto& item : node->items()) keys.push_back(item.key());
        problem = "no key '" + segment.key + "' in " + parent + make_did_you_mean(segment.key, keys);
        return nullptr;
      }
      node = &*found;
    }
  }
  return node;
}

void set_config_element(nlohmann::json& config, const std::vector<PathSegment>& segments, nlohmann::json value) {
  nlohmann::json* node = &config;
  for (const PathSegment& segment : segments) node = segment.index ? &node->at(*segment.index) : &node->at(segment.key);
  *node = std::move(value);
}

}  // namespace armfarm
