#pragma once
// A sweep spec (format in sweeps/README.md): a name, a base job configuration (schema defaults
// ← include files ← `base`) and the axes that vary it: grid, zip groups, random samples, repeat
// seeds. Parsing checks everything that can be checked without running a job; errors name the
// file and the JSON path.
#include "runner/config/config_schema.hpp"
#include "runner/spec/config_path.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace armfarm {

/// A configuration element set to one of a list of values.
struct SpecAxis {
  std::string path;  ///< dotted path into the job configuration
  std::vector<PathSegment> segments;
  std::vector<nlohmann::json> values;  ///< normalized to the configuration's type
  std::string location;                ///< where in the spec, e.g. sweep.grid["control.gain_scale"]
};

/// Lists that vary together: all axes have the same number of values.
struct SpecZipGroup {
  std::vector<SpecAxis> axes;
};

enum class RandomDistribution { uniform, loguniform, choice };

struct SpecRandomParam {
  std::string path;
  std::vector<PathSegment> segments;
  RandomDistribution distribution = RandomDistribution::uniform;
  double low = 0.0, high = 0.0;          ///< uniform and loguniform bounds
  std::vector<nlohmann::json> choices;   ///< choice
  std::string location;
};

/// `samples` draws of every parameter from a generator seeded by `seed`.
struct SpecRandom {
  int samples = 0;
  std::uint64_t seed = 0;
  std::vector<SpecRandomParam> params;  ///< drawn in this order (sorted by path)
};

/// A file the spec includes, as the job configurations record it under "inputs".
struct SpecInclude {
  std::string path;      ///< as written in `include`
  std::string resolved;  ///< absolute
  std::string hash;      ///< XXH3-128 of its bytes
};

struct SweepSpec {
  std::string file;         ///< as given, for messages
  std::string text;         ///< the file's text, stored with the sweep
  std::string folder;       ///< the folder its relative paths resolve against
  std::string name;
  std::string description;
  nlohmann::json base;      ///< defaults ← includes ← base, type-checked and normalized
  std::vector<SpecAxis> grid;
  std::vector<SpecZipGroup> zip;
  std::optional<SpecRandom> random;
  std::vector<std::int64_t> repeat_seeds;  ///< empty: no repeat axis
  std::vector<SpecInclude> includes;       ///< in the order they are merged
  /// For each input-file field of the schema, the folder its value resolves against: that of
  /// the file that wrote it (this spec for `base` and the axes, else the last include that sets
  /// it), or the schema's default folder when no file did.
  std::map<std::string, std::string> input_folders;
  /// For input fields an include sets (and this spec does not): that include's file, for messages.
  std::map<std::string, std::string> input_writers;
};

/// Reads and checks a spec file; include paths are relative to its folder, input paths to the
/// file that wrote them. Throws SpecError.
SweepSpec load_sweep_spec(const std::string& path, const JobConfigSchema& schema);

/// Checks a spec given as text (`file` names it in messages, `folder` resolves includes).
SweepSpec parse_sweep_spec(const std::string& text, const std::string& file, const std::string& folder,
                           const JobConfigSchema& schema);

}  // namespace armfarm
