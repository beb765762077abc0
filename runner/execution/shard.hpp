#pragma once
// Splitting a sweep across machines: `--shard I/N` runs shard I (1-based) of N. Jobs are dealt
// by estimated cost (job_cost.hpp), largest first, each to the shard with the least cost so far
// (the lowest index among equals); equal costs go in key order. The deal depends only on the
// jobs' keys and costs, never on the spec's order, the thread count or the machine, so every
// shard computes the same partition. (Greedy largest-first is within 4/3 of the best possible
// largest shard, Graham 1969.)
#include <string>
#include <vector>

namespace armfarm {

struct Shard {
  int index = 1;  ///< 1..count
  int count = 1;
};

/// Parses "I/N" (1 ≤ I ≤ N). Throws std::invalid_argument with a message naming the text.
Shard parse_shard(const std::string& text);

/// The 1-based shard of each job (same order as `keys`), dealt by `costs` (one per key, > 0;
/// empty: every job costs 1) among `count` shards.
std::vector<int> calc_shard_assignment(const std::vector<std::string>& keys, const std::vector<double>& costs, int count);

}  // namespace armfarm
