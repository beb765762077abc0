#pragma once
// The text of a gnuplot SVG as boxes, to check that no two labels overlap. Each label is a
// <g transform="translate(x,y) [rotate(a)]" ... font-size="f" [text-anchor="..."]> holding one
// <text>; its box is estimated from the font size and the string length (0.55 em a character,
// 1 em high, baseline at 0.8 em), which is generous for digits and tight for capitals.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace armfarm::testing {

struct TextBox {
  std::string text;
  double left = 0, top = 0, right = 0, bottom = 0;
};

inline std::string find_attribute(const std::string& tag, const std::string& name) {
  const std::string key = " " + name + "=\"";
  const auto at = tag.find(key);
  if (at == std::string::npos) return "";
  const auto end = tag.find('"', at + key.size());
  return tag.substr(at + key.size(), end - at - key.size());
}

inline std::size_t count_characters(const std::string& utf8) {
  std::size_t n = 0;
  for (unsigned char c : utf8) n += (c & 0xC0) != 0x80;
  return n;
}

inline std::vector<TextBox> find_text_boxes(const std::string& svg) {
  std::vector<TextBox> boxes;
  for (auto at = svg.find("<g transform=\"translate("); at != std::string::npos; at = svg.find("<g transform=\"translate(", at + 1)) {
    const auto tag_end = svg.find('>', at);
    const std::string tag = svg.substr(at, tag_end - at);
    const auto text_at = svg.find("<text", tag_end);
    const auto next_group = svg.find("<g", tag_end);
    if (text_at == std::string::npos || (next_group != std::string::npos && next_group < text_at)) continue;
    const auto text_start = svg.find('>', text_at) + 1;
    std::string text = svg.substr(text_start, svg.find("</text>", text_start) - text_start);
    // Drop any <tspan> markup around the characters.
    std::string plain;
    bool in_tag = false;
    for (char c : text) {
      if (c == '<') in_tag = true;
      if (!in_tag) plain += c;
      if (c == '>') in_tag = false;
    }
    if (plain.find_first_not_of(" \t\n") == std::string::npos) continue;
    double x = 0, y = 0, angle = 0;
    const std::string transform = find_attribute(tag, "transform");
    if (std::sscanf(transform.c_str(), "translate(%lf,%lf)", &x, &y) != 2) continue;
    const auto rotate = transform.find("rotate(");
    if (rotate != std::string::npos) angle = std::atof(transform.c_str() + rotate + 7);
    const double size = std::atof(find_attribute(tag, "font-size").c_str());
    if (!(size > 0)) continue;
    const double length = 0.55 * size * static_cast<double>(count_characters(plain));
    const std::string anchor = find_attribute(tag, "text-anchor");
    const double start = anchor == "middle" ? -length / 2 : anchor == "end" ? -length : 0.0;
    // Along the text: [start, start + length]; across: [-0.8, 0.2] em from the baseline.
    TextBox box{plain, start, -0.8 * size, start + length, 0.2 * size};
    const double quarter_turns = std::fmod(std::round(angle / 90.0) + 4.0, 4.0);
    if (quarter_turns == 1 || quarter_turns == 3) {  // rotate(90) or rotate(270): along becomes vertical
      const double sign = quarter_turns == 1 ? 1.0 : -1.0;
      const double a = sign * box.left, b = sign * box.right, c = -sign * box.top, d = -sign * box.bottom;
      box = TextBox{plain, std::min(c, d), std::min(a, b), std::max(c, d), std::max(a, b)};
    }
    box.left += x;
    box.right += x;
    box.top += y;
    box.bottom += y;
    boxes.push_back(box);
  }
  return boxes;
}

/// Pairs of labels whose boxes intersect by more than `slack` units each way, as "'a' and 'b'".
inline std::vector<std::string> find_overlapping_text(const std::string& svg, double slack = 0.5) {
  const auto boxes = find_text_boxes(svg);
  std::vector<std::string> overlaps;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    for (std::size_t j = i + 1; j < boxes.size(); ++j) {
      const TextBox& a = boxes[i];
      const TextBox& b = boxes[j];
      const double dx = std::min(a.right, b.right) - std::max(a.left, b.left);
      const double dy = std::min(a.bottom, b.bottom) - std::max(a.top, b.top);
      if (dx > slack && dy > slack) overlaps.push_back("'" + a.text + "' and '" + b.text + "'");
    }
  }
  return overlaps;
}

}  // namespace armfarm::testing
