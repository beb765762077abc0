#pragma once
// A sweep spec (format in sweeps/README.md): a name, a base job configuration (schema defaults
// ← include files ← `base`) and the axes that vary it: grid, zip groups, random samples, repeat
// seeds. Parsing checks everything that can be checked without running a job; errors name the
// file and the JSON path.
#include "runner/spec/config_schema.hpp"
#include "runner/search/search_schedule.hpp"
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
  ConfigPath segments;
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
  ConfigPath segments;
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

/// The objective of a search (sweeps/README.md, "Search"): a result metric of the catalog, better
/// in the catalog's direction, of one joint or the mean over the joints, at a checkpoint.
struct SpecObjective {
  std::string metric;
  bool lower_is_better = true;  ///< from the catalog
  int joint = 0;                ///< 1-based joint number; 0: the job-level mean row
  /// The checkpoint's number (a learning.heldout_checkpoints value); empty for a metric without
  /// checkpoints. The search's rungs are the checkpoints up to and including it.
  std::optional<std::int64_t> checkpoint;
};

/// One axis of a search space, where it was written and, for a categorical axis, its values.
struct SpecSearchAxis {
  ConfigPath segments;
  std::vector<nlohmann::json> choices;  ///< categorical: normalized to the configuration's type
  std::string location;
};

/// `sweep.search`: the trials are decided as the search runs (runner/search/).
struct SpecSearch {
  search::SearchSettings settings;     ///< space, method, sampler, seed, η, slots, limits; costs set by the runner
  std::vector<SpecSearchAxis> axes;    ///< parallel to settings.space.axes
  SpecObjective objective;
  std::vector<std::int64_t> rungs;     ///< the checkpoints that are rungs, increasing (one rung when none)
  enum class BudgetUnit { jobs, cpu_seconds } budget_unit = BudgetUnit::jobs;
  double budget = 0.0;
  /// `tpe_startup`: prior draws before TPE's estimators are used; 0 (not given): the runner sets
  /// search::calc_tpe_startup of what the budget buys (tpe_sampler.hpp).
  std::size_t tpe_startup = 0;
  /// `tpe_rule` given: TPE's estimator rule (settings.tpe.joint) is the spec's, compared with a
  /// resumed search's; not given: the default, the joint rule, or a resumed search's recorded rule.
  bool tpe_rule_given = false;
  /// "learning.heldout_checkpoints": a step to rung r runs the checkpoints rungs[0 … r].
  ConfigPath checkpoint_segments;
  /// The key that makes a job learn exactly to a checkpoint, in the checkpoints' unit, for asha,
  /// successive_halving and hyperband: "learning.epochs" (batch; checkpoints count epochs) or
  /// "trajectory.reaching.reaches" (online on reaches; checkpoints count reaches). A step to a
  /// rung r below the last sets it to rungs[r], so a short rung is a short job. Empty for other
  /// job kinds (an online pass over a sine or figure-eight): their short rungs run the whole pass.
  std::string length_path;
  ConfigPath length_segments;
  /// The steps to expand, (point, rung) each, as the search runner decided them; unset: the steps
  /// decided before any result (calc_initial_search_steps).
  std::optional<std::vector<std::pair<search::SearchPoint, std::size_t>>> decided;
};

/// The values a search step sets, {"dotted.path": value}: each axis's value at `point` (a
/// categorical axis's choice, an integer axis's whole number), when the objective has
/// checkpoints, learning.heldout_checkpoints up to rung `rung`, and below the last rung
/// length_path = rungs[rung].
nlohmann::json calc_search_step_params(const SpecSearch& search, const search::SearchPoint& point, std::size_t rung);

/// The steps a search decides before any job has finished (at most `slots`), with their trials.
search::SearchHistory calc_initial_search_steps(const SpecSearch& search);

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
  std::optional<SpecSearch> search;
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
