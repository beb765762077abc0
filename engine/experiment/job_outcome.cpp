#include "engine/experiment/job_outcome.hpp"

namespace armfarm {

const char* to_string(JobStatus status) {
  switch (status) {
    case JobStatus::done: return "done";
    case JobStatus::failed: return "failed";
    case JobStatus::diverged: return "diverged";
    case JobStatus::timeout: return "timeout";
  }
  return "failed";
}

}  // namespace armfarm
