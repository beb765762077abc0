// Fuzz target: learner model files (engine/lwpr/lwpr_model_file, engine/ssgpr/ssgpr_model_file
// over engine/learner/model_file_codec). The first byte picks the format and whether the input
// is taken as a whole file (mostly refused by its magic or checksum) or as a payload that gets a
// valid header and checksum, so that the payload decoder itself is explored. A well-formed
// rejection is a std::runtime_error.
#include "engine/learner/model_file_codec.hpp"
#include "engine/lwpr/lwpr_model_file.hpp"
#include "engine/ssgpr/ssgpr_model_file.hpp"

#include <cstddef>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>

namespace {

// magic, u32 version, u64 payload length, payload, u64 FNV-1a of the payload (both formats).
std::string make_file(const char* magic, std::uint32_t version, const std::string& payload) {
  armfarm::ModelFileWriter header;
  header.put_u32(version);
  header.put_u64(payload.size());
  armfarm::ModelFileWriter checksum;
  checksum.put_u64(armfarm::calc_model_file_checksum(payload));
  return std::string(magic, 8) + header.bytes() + payload + checksum.bytes();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const unsigned mode = data[0] % 4;
  const std::string rest(reinterpret_cast<const char*>(data) + 1, size - 1);
  const bool lwpr = mode < 2;
  const std::string file = mode % 2 == 0 ? rest
                           : lwpr        ? make_file("AFLWPR\r\n", armfarm::lwpr::kLwprModelFormatVersion, rest)
                                         : make_file("AFSSGP\r\n", armfarm::ssgpr::kSsgprModelFormatVersion, rest);
  std::istringstream in(file);
  try {
    if (lwpr) {
      armfarm::lwpr::load_lwpr_model(in);
    } else {
      armfarm::ssgpr::load_ssgpr_model(in);
    }
  } catch (const std::runtime_error&) {
  }
  return 0;
}
