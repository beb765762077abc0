#pragma once
// Saving and loading an LwprModel in a versioned, portable binary format: every number is written
// little-endian (IEEE-754 doubles by their bit patterns), so a round trip gives bit-identical
// predictions on any platform. Layout: 8-byte magic "AFLWPR\r\n", u32 format version, u64 payload
// length, payload (sizes, parameters, then each output's fields), u64 FNV-1a hash of the payload.
// The engine writes to and reads from streams; opening files is the caller's business.
#include "engine/lwpr/lwpr_model.hpp"

#include <cstdint>
#include <iosfwd>

namespace armfarm::lwpr {

/// The format version this build writes (and the newest it reads). Version 2 adds the start rule
/// (LwprParams::loo_start) after trust_n_data; version 1 files load with the early rule, the only
/// one there was when they were written.
inline constexpr std::uint32_t kLwprModelFormatVersion = 2;

/// Writes the whole model (parameters, fields, sample count) to `out` (opened in binary mode).
void write_lwpr_model(const LwprModel& model, std::ostream& out);

/// Reads a model written by write_lwpr_model(). Throws std::runtime_error naming the byte offset
/// and the problem for a truncated, corrupt (hash mismatch, bad sizes) or future-version file.
LwprModel load_lwpr_model(std::istream& in);

}  // namespace armfarm::lwpr
