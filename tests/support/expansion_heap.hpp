// The heap an expanded sweep holds, for the expansion-memory tests: glibc's heap in use
// (mallinfo2) before and after expand_sweep, per job. Sanitizers replace glibc's allocator,
// so callers skip under them (and off glibc, where there is no mallinfo2).
#pragma once

#include "runner/spec/sweep_expansion.hpp"
#include "runner/spec/sweep_spec.hpp"

#include <malloc.h>

#include <string>

namespace armfarm::test_support {

struct MeasuredExpansion {
  ExpandedSweep sweep;
  double bytes_per_job = 0.0;  ///< heap in use after the expansion less before, over the jobs
};

/// Parses `text` (a spec named m.json) against `schema`, expands it, and measures the heap the
/// expansion holds. Precondition: glibc, no sanitizer.
inline MeasuredExpansion expand_measuring_heap(const std::string& text, const JobConfigSchema& schema) {
  SweepSpec spec = parse_sweep_spec(text, "m.json", ".", schema);
  const std::size_t before = mallinfo2().uordblks;
  MeasuredExpansion out{expand_sweep(std::move(spec), schema)};
  const std::size_t after = mallinfo2().uordblks;
  out.bytes_per_job = out.sweep.jobs.empty() ? 0.0
                                             : (static_cast<double>(after) - static_cast<double>(before)) /
                                                   static_cast<double>(out.sweep.jobs.size());
  return out;
}

}  // namespace armfarm::test_support
