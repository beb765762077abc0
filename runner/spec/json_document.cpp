#include "runner/spec/json_document.hpp"

#include "engine/io/input_file.hpp"
#include "runner/spec/spec_error.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <iterator>
#include <vector>

namespace armfarm {
namespace {

// A character iterator that reports how far the parser has read, so that SAX events (which
// carry no position) can be placed in the text.
class TrackingIterator {
 public:
  using iterator_category = std::forward_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;

  TrackingIterator(const char* at, const char** furthest) : at_(at), furthest_(furthest) {}
  reference operator*() const { return *at_; }
  TrackingIterator& operator++() {
    ++at_;
    if (at_ > *furthest_) *furthest_ = at_;
    return *this;
  }
  TrackingIterator operator++(int) {
    TrackingIterator before = *this;
    ++*this;
    return before;
  }
  bool operator==(const TrackingIterator& other) const { return at_ == other.at_; }
  bool operator!=(const TrackingIterator& other) const { return at_ != other.at_; }

 private:
  const char* at_;
  const char** furthest_;
};

// A polynomial hash of a path's characters, so that a path's hash is its parent's extended by
// its segment, and a query path hashes to the same value in one pass.
std::size_t extend_path_hash(std::size_t hash, const std::string& segment) {
  for (const char c : segment) hash = hash * 1099511628211ULL + static_cast<unsigned char>(c) + 1;
  return hash;
}

bool needs_quotes(const std::string& key) {
  if (key.empty()) return true;
  return std::any_of(key.begin(), key.end(), [](char c) {
    const auto byte = static_cast<unsigned char>(c);
    return c == '.' || c == '[' || c == ']' || c == '"' || c == ' ' || byte < 0x20 || byte == 0x7f;
  });
}

// Builds the DOM and records where each value starts.
class TrackingSax : public nlohmann::json_sax<nlohmann::json> {
 public:
  TrackingSax(const std::string& text, const char** furthest, JsonDocument& document)
      : text_(text), furthest_(furthest), document_(document) {}

  bool null() override { return put(nullptr, 4); }
  bool boolean(bool value) override { return put(value, value ? 4 : 5); }
  bool number_integer(number_integer_t value) override { return put_number(value); }
  bool number_unsigned(number_unsigned_t value) override { return put_number(value); }
  bool number_float(number_float_t value, const string_t&) override { return put_number(value); }
  bool string(string_t& value) override {
    const std::size_t start = opening_quote_before(read_offset());
    if (!refuse_control_characters(value, start, "string")) return false;
    return put_at(std::move(value), start) != nullptr;
  }
  bool binary(binary_t& value) override { return put(nlohmann::json::binary(value), 0); }
  bool start_object(std::size_t) override { return open(nlohmann::json::object()); }
  bool key(string_t& key) override {
    Frame& frame = frames_.back();
    frame.key = key;
    if (!refuse_control_characters(key, opening_quote_before(read_offset()), "key")) return false;
    if (frame.container->contains(key)) {
      error_position_ = opening_quote_before(read_offset());
      error_path_ = make_next_path();
      error_message_ = "the key " + nlohmann::json(key).dump() + " appears twice in this object (JSON keeps only one: remove the other)";
      return false;
    }
    return true;
  }
  bool end_object() override { return close(); }
  bool start_array(std::size_t) override { return open(nlohmann::json::array()); }
  bool end_array() override { return close(); }

  bool parse_error(std::size_t position, const std::string& last_token, const nlohmann::detail::exception& ex) override {
    if (ex.id == 406) {
      error_position_ = position >= last_token.size() ? position - last_token.size() : 0;  // the number's start
      error_path_ = current_path();
      error_message_ = "the number " + last_token + " does not fit a double (JSON numbers here must be finite)";
    } else {
      // Syntax errors: the character the reader stopped at, no path (the key may not be read yet).
      const auto* syntax = dynamic_cast<const nlohmann::detail::parse_error*>(&ex);
      error_position_ = calc_json_syntax_error_offset(syntax != nullptr ? syntax->byte : position);
      error_message_ = make_json_syntax_reason(ex.what());
    }
    return false;
  }

  std::size_t error_position() const { return error_position_; }
  const std::string& error_path() const { return error_path_; }
  const std::string& error_message() const { return error_message_; }

 private:
  struct Frame {
    nlohmann::json* container;
    std::size_t node;  // the container's index in document_.nodes
    std::string key;   // the key of the value being read (objects)
  };

  std::size_t read_offset() const { return static_cast<std::size_t>(*furthest_ - text_.data()); }

  // The reader stands just after a string's closing quote at `end`; walks back to the opening one.
  std::size_t opening_quote_before(std::size_t end) const {
    std::size_t start = end > 0 ? end - 1 : 0;
    while (start > 0) {
      --start;
      if (text_[start] == '"' && (start == 0 || text_[start - 1] != '\\')) break;
    }
    return start;
  }

  // The path segment of the next value the innermost container receives ("" at the top).
  std::string make_next_segment() const {
    if (frames_.empty()) return "";
    const Frame& frame = frames_.back();
    if (frame.container->is_array()) return "[" + std::to_string(frame.container->size()) + "]";
    if (needs_quotes(frame.key)) return "[" + nlohmann::json(frame.key).dump() + "]";
    return (frame.node == 0 ? "" : ".") + frame.key;
  }

  std::string make_next_path() const {
    return frames_.empty() ? std::string() : document_.make_path(frames_.back().node) + make_next_segment();
  }

  // A name or value prints as itself on one line: NUL, newlines, escapes (ANSI) are refused.
  bool refuse_control_characters(const std::string& value, std::size_t start, const char* what) {
    for (const char c : value) {
      const auto byte = static_cast<unsigned char>(c);
      if (byte >= 0x20 && byte != 0x7f) continue;
      char code[8];
      std::snprintf(code, sizeof code, "U+%04X", static_cast<unsigned>(byte));
      error_position_ = start;
      error_path_ = make_next_path();
      error_message_ = std::string("the ") + what + " holds the control character " + code +
                       " (names and values must be printable text)";
      return false;
    }
    return true;
  }

  std::string current_path() const {
    std::string path;
    for (std::size_t f = 0; f < frames_.size(); ++f) {
      const Frame& frame = frames_[f];
      if (frame.container->is_array()) {
        // The innermost array receives its next element; an outer one is filling its last.
        const std::size_t size = frame.container->size();
        path += "[" + std::to_string(f + 1 == frames_.size() || size == 0 ? size : size - 1) + "]";
      } else if (needs_quotes(frame.key)) {
        path += "[" + nlohmann::json(frame.key).dump() + "]";
      } else {
        path += (path.empty() ? "" : ".") + frame.key;
      }
    }
    return path;
  }

  // Numbers end one character before the reader (it looked ahead to find the end).
  template <typename Number>
  bool put_number(Number value) {
    std::size_t end = read_offset();
    std::size_t start = end > 0 ? end - 1 : 0;
    while (start > 0 && (std::isdigit(static_cast<unsigned char>(text_[start - 1])) || text_[start - 1] == '-' ||
                         text_[start - 1] == '+' || text_[start - 1] == '.' || text_[start - 1] == 'e' ||
                         text_[start - 1] == 'E')) {
      --start;
    }
    return put_at(nlohmann::json(value), start);
  }

  bool put(nlohmann::json value, std::size_t length) {
    const std::size_t end = read_offset();
    return put_at(std::move(value), end >= length ? end - length : 0);
  }

  nlohmann::json* put_at(nlohmann::json value, std::size_t start) {
    record_node(start);
    if (frames_.empty()) {
      document_.value = std::move(value);
      return &document_.value;
    }
    Frame& frame = frames_.back();
    if (frame.container->is_array()) {
      frame.container->push_back(std::move(value));
      return &frame.container->back();
    }
    nlohmann::json& slot = (*frame.container)[frame.key];
    slot = std::move(value);
    return &slot;
  }

  // The value put next gets node index nodes.size(): its parent, segment, offset and path hash.
  // An array element stores its index, not its segment's text: `[1999]` is longer than `,1`.
  void record_node(std::size_t start) {
    std::string segment = make_next_segment();
    const std::size_t parent = frames_.empty() ? 0 : frames_.back().node;
    const std::size_t hash = frames_.empty() ? 0 : extend_path_hash(document_.nodes[parent].hash, segment);
    JsonDocument::Node node;
    node.parent = parent;
    node.offset = start;
    node.hash = hash;
    if (!frames_.empty() && frames_.back().container->is_array()) {
      node.element = frames_.back().container->size();
    } else {
      node.segment = std::move(segment);
    }
    document_.by_hash.emplace(hash, document_.nodes.size());
    document_.nodes.push_back(std::move(node));
  }

  bool open(nlohmann::json empty) {
    const std::size_t end = read_offset();
    const std::size_t start = end > 0 ? end - 1 : 0;
    if (frames_.size() >= kMaxJsonDepth) {
      // No path: at this depth it would be hundreds of segments long.
      error_position_ = start;
      error_message_ = "arrays and objects nest deeper than " + std::to_string(kMaxJsonDepth) +
                       " levels (the most a spec may nest)";
      return false;
    }
    nlohmann::json* container = put_at(std::move(empty), start);
    frames_.push_back({container, document_.nodes.size() - 1, ""});
    return true;
  }

  bool close() {
    frames_.pop_back();
    return true;
  }

 private:
  const std::string& text_;
  const char** furthest_;
  JsonDocument& document_;
  std::vector<Frame> frames_;
  std::size_t error_position_ = 0;
  std::string error_path_;
  std::string error_message_;
};

}  // namespace

std::string JsonDocument::make_path(std::size_t index) const {
  std::vector<std::size_t> chain;
  for (std::size_t at = index; at != 0; at = nodes[at].parent) chain.push_back(at);
  std::string path;
  for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
    const Node& node = nodes[*it];
    path += node.element == Node::kNotAnElement ? node.segment : "[" + std::to_string(node.element) + "]";
  }
  return path;
}

std::string JsonDocument::describe_position(const std::string& path) const {
  const auto [first, last] = by_hash.equal_range(extend_path_hash(0, path));
  for (auto it = first; it != last; ++it) {
    if (make_path(it->second) == path) return describe_text_position(text, nodes[it->second].offset);
  }
  return std::string();
}

bool is_non_finite_number_text(const std::string& text) {
  std::string lower;
  for (char c : text) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (!lower.empty() && (lower[0] == '-' || lower[0] == '+')) lower = lower.substr(1);
  return lower == "nan" || lower == "inf" || lower == "infinity";
}

JsonDocument parse_json_document(const std::string& text, const std::string& file) {
  JsonDocument document;
  document.text = text;
  const char* furthest = document.text.data();
  TrackingSax sax(document.text, &furthest, document);
  const char* begin = document.text.data();
  const bool ok = nlohmann::json::sax_parse(TrackingIterator(begin, &furthest),
                                            TrackingIterator(begin + document.text.size(), &furthest), &sax);
  if (!ok) {
    const std::string path = sax.error_path().empty() ? "" : sax.error_path() + ": ";
    throw SpecError({file + ": " + describe_text_position(document.text, sax.error_position()) + ": " + path +
                     sax.error_message()});
  }
  return document;
}

nlohmann::json read_json_file(const std::string& path) {
  return parse_json_document(read_input_file(path, InputFileKind::json), path).value;
}

}  // namespace armfarm
