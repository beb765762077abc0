#include "runner/spec/job_key_template.hpp"

#include "runner/spec/canonical_json.hpp"
#include "runner/spec/input_files.hpp"

#include <algorithm>
#include <utility>

namespace armfarm {
namespace {

// A string no configuration holds: control characters, which specs never carry in values.
std::string make_marker(std::size_t hole) { return "\x1f\x1e" "armfarm key hole " + std::to_string(hole) + "\x1e\x1f"; }

}  // namespace

JobKeyTemplate::JobKeyTemplate(const nlohmann::json& config, const std::vector<ConfigPath>& holes) {
  const auto inputs = config.find("inputs");
  for (std::size_t i = 0; i < holes.size(); ++i) {
    if (holes[i].empty() || holes[i].front().key == "inputs") return;
    for (std::size_t j = i + 1; j < holes.size(); ++j) {
      if (holes[i].overlaps(holes[j])) return;
    }
    if (inputs != config.end() && inputs->is_object()) {
      for (const auto& [name, entry] : inputs->items()) {
        try {
          if (holes[i].overlaps(parse_config_path(name))) return;  // the key document rewrites it
        } catch (const std::invalid_argument&) {
          // not a field path (an include)
        }
      }
    }
  }
  nlohmann::json marked = config;
  for (std::size_t i = 0; i < holes.size(); ++i) {
    std::string problem;
    if (find_config_element(marked, holes[i], problem) == nullptr) return;
    set_config_element(marked, holes[i], make_marker(i));
  }
  const std::string text = calc_canonical_json(make_job_key_document(marked));
  std::vector<std::pair<std::size_t, std::size_t>> cuts;  // (position, hole)
  for (std::size_t i = 0; i < holes.size(); ++i) {
    const std::string needle = calc_canonical_json(make_marker(i));
    const std::size_t at = text.find(needle);
    if (at == std::string::npos || text.find(needle, at + 1) != std::string::npos) return;
    cuts.emplace_back(at, i);
  }
  std::sort(cuts.begin(), cuts.end());
  std::size_t from = 0;
  for (const auto& [at, hole] : cuts) {
    pieces_.push_back(text.substr(from, at - from));
    order_.push_back(hole);
    from = at + calc_canonical_json(make_marker(hole)).size();
  }
  pieces_.push_back(text.substr(from));
  usable_ = true;
}

std::string JobKeyTemplate::calc_key(const std::vector<const std::string*>& values, std::string& scratch) const {
  scratch.clear();
  for (std::size_t k = 0; k < order_.size(); ++k) {
    scratch += pieces_[k];
    scratch += *values.at(order_[k]);
  }
  scratch += pieces_.back();
  return calc_text_hash(scratch);
}

std::size_t JobKeyTemplate::calc_size() const {
  std::size_t bytes = 0;
  for (const std::string& piece : pieces_) bytes += piece.capacity();
  return bytes + order_.capacity() * sizeof(std::size_t);
}

}  // namespace armfarm
