#pragma once
// Splitting a sweep across machines: `--shard I/N` runs the jobs whose key falls in shard I
// (1-based) of N. The shard of a key is its first 64 bits modulo N, so it depends only on the
// job's configuration, never on the spec's order or on the machine.
#include <string>

namespace armfarm {

struct Shard {
  int index = 1;  ///< 1..count
  int count = 1;
};

/// Parses "I/N" (1 ≤ I ≤ N). Throws std::invalid_argument with a message naming the text.
Shard parse_shard(const std::string& text);

/// The 1-based shard of a job key (32 hex digits) among `count`.
int calc_shard_of(const std::string& key, int count);

}  // namespace armfarm
