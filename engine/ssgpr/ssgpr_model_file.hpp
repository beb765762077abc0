#pragma once
// Saving and loading an SsgprModel in a versioned, portable binary format (the conventions of
// engine/lwpr/lwpr_model_file.hpp): every number little-endian (doubles by their IEEE-754 bit
// patterns), so a round trip predicts bit-identically on any platform. Layout: 8-byte magic
// "AFSSGP\r\n", u32 format version, u64 payload length, payload, u64 FNV-1a hash of the payload.
// Payload: u32 n_in, u32 n_out, u64 n_updates, the parameters, then Ω, L (lower triangle,
// column by column), B and W (each matrix as u32 rows, u32 cols, column-major doubles).
// The frequencies are stored, not redrawn, so a file does not depend on the random stream.
#include "engine/ssgpr/ssgpr_model.hpp"

#include <cstdint>
#include <iosfwd>

namespace armfarm::ssgpr {

/// The format version this build writes (and the newest it reads).
inline constexpr std::uint32_t kSsgprModelFormatVersion = 1;

/// Writes the whole model to `out` (opened in binary mode). Throws std::runtime_error on failure.
void write_ssgpr_model(const SsgprModel& model, std::ostream& out);

/// Reads a model written by write_ssgpr_model(). Throws std::runtime_error naming the byte
/// offset and the problem for a truncated, corrupt (checksum, sizes, values) or future file.
SsgprModel load_ssgpr_model(std::istream& in);

}  // namespace armfarm::ssgpr
