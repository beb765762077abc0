// Fuzz target: sweep specs (runner/spec: JSON with positions, the structural check, includes,
// expansion) against the fake job schema, expansion capped at 1000 jobs so that one input
// cannot take minutes. A well-formed rejection is a SpecError.
#include "support/fake_job.hpp"
#include "runner/spec/spec_error.hpp"
#include "runner/spec/sweep_expansion.hpp"
#include "runner/spec/sweep_spec.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const armfarm::JobConfigSchema schema = armfarm::make_fake_job_config_schema();
  const std::string text(reinterpret_cast<const char*>(data), size);
  armfarm::ExpansionLimits limits;
  limits.max_jobs = 1000;
  try {
    armfarm::expand_sweep(armfarm::parse_sweep_spec(text, "fuzz.json", ARMFARM_FUZZ_SPEC_FOLDER, schema), schema, limits);
  } catch (const armfarm::SpecError&) {
  }
  return 0;
}
