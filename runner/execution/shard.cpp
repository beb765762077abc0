#include "runner/execution/shard.hpp"

#include <stdexcept>

namespace armfarm {

Shard parse_shard(const std::string& text) {
  const std::size_t slash = text.find('/');
  Shard shard;
  try {
    if (slash == std::string::npos) throw std::invalid_argument("");
    std::size_t used_index = 0, used_count = 0;
    shard.index = std::stoi(text.substr(0, slash), &used_index);
    shard.count = std::stoi(text.substr(slash + 1), &used_count);
    if (used_index != slash || used_count != text.size() - slash - 1) throw std::invalid_argument("");
  } catch (const std::exception&) {
    throw std::invalid_argument("--shard " + text + ": expected I/N, e.g. 2/4");
  }
  if (shard.count < 1 || shard.index < 1 || shard.index > shard.count) {
    throw std::invalid_argument("--shard " + text + ": needs 1 <= I <= N");
  }
  return shard;
}

int calc_shard_of(const std::string& key, int count) {
  if (key.size() < 16) throw std::invalid_argument("job key " + key + " is too short");
  const unsigned long long high = std::stoull(key.substr(0, 16), nullptr, 16);
  return static_cast<int>(high % static_cast<unsigned long long>(count)) + 1;
}

}  // namespace armfarm
