#pragma once
// The text of a gnuplot SVG as boxes, to check that no two labels overlap. Each label is a
// <g transform="translate(x,y) [rotate(a)]" ... font-size="f" [text-anchor="..."]> holding one
// <text>; its box is estimated from the font size and the string length (0.55 em a character,
// 1 em high, baseline at 0.8 em), which is generous for digits and tight for capitals.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace armfarm::testing {

struct TextBox {
  std::string text;
  double left = 0, top = 0, right = 0, bottom = 0;
  bool rotated = false;   ///< a quarter turn (a y label)
  double font_size = 0;
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
    TextBox box{plain, start, -0.8 * size, start + length, 0.2 * size, false, size};
    const double quarter_turns = std::fmod(std::round(angle / 90.0) + 4.0, 4.0);
    if (quarter_turns == 1 || quarter_turns == 3) {  // rotate(90) or rotate(270): along becomes vertical
      const double sign = quarter_turns == 1 ? 1.0 : -1.0;
      const double a = sign * box.left, b = sign * box.right, c = -sign * box.top, d = -sign * box.bottom;
      box = TextBox{plain, std::min(c, d), std::min(a, b), std::max(c, d), std::max(a, b), true, size};
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

/// A panel's plot area: gnuplot draws each border as one closed path "M a,b L a,c L d,c L d,b
/// L a,b Z" (its grid and curves are open paths).
struct Frame {
  double left = 0, top = 0, right = 0, bottom = 0;
};

inline std::vector<Frame> find_plot_frames(const std::string& svg) {
  std::vector<Frame> frames;
  for (auto at = svg.find("d='M"); at != std::string::npos; at = svg.find("d='M", at + 1)) {
    double x[5], y[5];
    char close = 0;
    if (std::sscanf(svg.c_str() + at + 3, "M%lf,%lf L%lf,%lf L%lf,%lf L%lf,%lf L%lf,%lf %c", &x[0], &y[0], &x[1], &y[1], &x[2], &y[2],
                    &x[3], &y[3], &x[4], &y[4], &close) != 11 || close != 'Z') {
      continue;
    }
    const bool rectangle = x[0] == x[1] && y[1] == y[2] && x[2] == x[3] && y[3] == y[0] && x[4] == x[0] && y[4] == y[0] &&
                           x[0] != x[2] && y[0] != y[1];
    if (!rectangle) continue;
    const Frame frame{std::min(x[0], x[2]), std::min(y[0], y[1]), std::max(x[0], x[2]), std::max(y[0], y[1])};
    const bool seen = std::any_of(frames.begin(), frames.end(), [&](const Frame& f) {
      return std::abs(f.left - frame.left) < 0.5 && std::abs(f.top - frame.top) < 0.5 && std::abs(f.right - frame.right) < 0.5 &&
             std::abs(f.bottom - frame.bottom) < 0.5;
    });
    if (!seen) frames.push_back(frame);
  }
  return frames;
}

inline bool is_number_text(const std::string& text) {
  char* end = nullptr;
  std::strtod(text.c_str(), &end);
  return end != text.c_str() && *end == '\0';
}

/// The x tick labels of a frame: numbers centred within its width, just below its bottom edge.
inline std::vector<std::string> find_x_tick_labels(const std::vector<TextBox>& boxes, const Frame& frame) {
  std::vector<std::string> labels;
  for (const TextBox& box : boxes) {
    const double centre = (box.left + box.right) / 2;
    const bool below = box.top >= frame.bottom - 0.5 && box.top <= frame.bottom + 1.5 * box.font_size;
    if (!box.rotated && below && centre >= frame.left - 1 && centre <= frame.right + 1 && is_number_text(box.text)) {
      labels.push_back(box.text);
    }
  }
  return labels;
}

/// Rotated labels (y labels) nearer than `gap_em` of their font size to an upright text beside
/// them (tick labels), as "'label' and 'tick' 0.1 em apart": touching is not overlapping, but
/// reads as one blot on paper.
inline std::vector<std::string> find_crowded_y_labels(const std::vector<TextBox>& boxes, double gap_em) {
  std::vector<std::string> crowded;
  for (const TextBox& label : boxes) {
    if (!label.rotated) continue;
    for (const TextBox& other : boxes) {
      if (other.rotated || std::min(label.bottom, other.bottom) - std::max(label.top, other.top) <= 0) continue;
      const double gap = std::max(other.left - label.right, label.left - other.right);
      if (gap < gap_em * label.font_size) {
        char apart[32];
        std::snprintf(apart, sizeof apart, "%.2f", gap / label.font_size);
        crowded.push_back("'" + label.text + "' and '" + other.text + "' " + apart + " em apart");
      }
    }
  }
  return crowded;
}

/// The empty room between each frame's top and the lowest text above it (its title, or the
/// figure's), in units of that text's font size; a frame with no text above is left out.
inline std::vector<double> find_room_above_frames(const std::vector<TextBox>& boxes, const std::vector<Frame>& frames) {
  std::vector<double> rooms;
  for (const Frame& frame : frames) {
    const TextBox* lowest = nullptr;
    for (const TextBox& box : boxes) {
      const bool above = box.bottom <= frame.top + 0.5 && box.right > frame.left && box.left < frame.right && !box.rotated;
      if (above && (!lowest || box.bottom > lowest->bottom)) lowest = &box;
    }
    if (lowest) rooms.push_back((frame.top - lowest->bottom) / lowest->font_size);
  }
  return rooms;
}

}  // namespace armfarm::testing
