#include "runner/spec/sweep_expansion.hpp"

#include "runner/spec/canonical_json.hpp"
#include "runner/spec/config_check.hpp"
#include "runner/spec/input_files.hpp"
#include "runner/spec/job_key_template.hpp"
#include "runner/spec/spec_error.hpp"

#include "engine/random/random_stream.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string_view>
#include <unordered_set>

namespace armfarm {
namespace {

// One value of a factor: the elements it sets, each with its spec location for messages.
struct Assignment {
  std::string path;
  const ConfigPath* segments;
  nlohmann::json value;
  std::string location;
  std::string canonical = calc_canonical_json(value);  ///< what the job key hashes of it
};
using FactorEntry = std::vector<Assignment>;
using Factor = std::vector<FactorEntry>;

// One factor per grid axis: its values, one element each.
void add_grid_factors(const SweepSpec& spec, std::vector<Factor>& factors) {
  for (const SpecAxis& axis : spec.grid) {
    Factor factor;
    for (std::size_t i = 0; i < axis.values.size(); ++i) {
      factor.push_back({{axis.path, &axis.segments, axis.values[i], axis.location + "[" + std::to_string(i) + "]"}});
    }
    factors.push_back(std::move(factor));
  }
}

// One factor per zip group: its i-th entry sets the i-th value of every axis of the group.
void add_zip_factors(const SweepSpec& spec, std::vector<Factor>& factors) {
  for (const SpecZipGroup& group : spec.zip) {
    Factor factor(group.axes.front().values.size());
    for (const SpecAxis& axis : group.axes) {
      for (std::size_t i = 0; i < axis.values.size(); ++i) {
        factor[i].push_back({axis.path, &axis.segments, axis.values[i], axis.location + "[" + std::to_string(i) + "]"});
      }
    }
    factors.push_back(std::move(factor));
  }
}

// One value of a random parameter from a uniform draw u in [0, 1).
nlohmann::json calc_random_value(const SpecRandomParam& param, double u) {
  switch (param.distribution) {
    case RandomDistribution::uniform:
      return param.low + u * (param.high - param.low);
    case RandomDistribution::loguniform:
      return std::exp(std::log(param.low) + u * (std::log(param.high) - std::log(param.low)));
    case RandomDistribution::choice:
      return param.choices[std::min(param.choices.size() - 1, static_cast<std::size_t>(u * static_cast<double>(param.choices.size())))];
  }
  return nlohmann::json();
}

// The random samples: one factor, an entry per sample, drawn in order from the spec's seed.
void add_random_factor(const SweepSpec& spec, std::vector<Factor>& factors) {
  if (!spec.random) return;
  RandomStream generator(spec.random->seed, "sweep.random");
  Factor factor;
  for (int s = 0; s < spec.random->samples; ++s) {
    FactorEntry entry;
    for (const SpecRandomParam& param : spec.random->params) {
      const double u = generator.uniform();
      entry.push_back({param.path, &param.segments, calc_random_value(param, u), param.location + " (sample " + std::to_string(s) + ")"});
    }
    factor.push_back(std::move(entry));
  }
  factors.push_back(std::move(factor));
}

// The search's steps decided before any result (the search runner decides the rest as jobs
// finish): one factor, an entry per step.
void add_search_factor(const SweepSpec& spec, std::vector<Factor>& factors) {
  if (!spec.search) return;
  std::vector<std::pair<search::SearchPoint, std::size_t>> decided;
  if (spec.search->decided) {
    decided = *spec.search->decided;
  } else {
    const search::SearchHistory initial = calc_initial_search_steps(*spec.search);
    for (const search::SearchStep& step : initial.steps) decided.emplace_back(initial.trials[step.trial].point, step.rung);
  }
  Factor factor;
  for (std::size_t s = 0; s < decided.size(); ++s) {
    const nlohmann::json params = calc_search_step_params(*spec.search, decided[s].first, decided[s].second);
    FactorEntry entry;
    const std::string where = " (step " + std::to_string(s) + ", rung " + std::to_string(decided[s].second) + ")";
    for (std::size_t d = 0; d < spec.search->axes.size(); ++d) {
      const SpecSearchAxis& axis = spec.search->axes[d];
      const std::string& path = spec.search->settings.space.axes[d].path;
      entry.push_back({path, &axis.segments, params.at(path), axis.location + where});
    }
    if (params.contains("learning.heldout_checkpoints")) {
      entry.push_back({"learning.heldout_checkpoints", &spec.search->checkpoint_segments,
                       params.at("learning.heldout_checkpoints"), "sweep.search.objective.checkpoint" + where});
    }
    if (!spec.search->length_path.empty()) {
      // Every entry of a factor sets the same elements (the job keys rely on it): a step to the
      // last rung sets the base's own length, which leaves its configuration and key the base's.
      std::string unused;
      const nlohmann::json* base_length = find_config_element(spec.base, spec.search->length_segments, unused);
      const nlohmann::json length = params.contains(spec.search->length_path) ? params.at(spec.search->length_path)
                                    : base_length != nullptr                     ? *base_length
                                                                                 : nlohmann::json();
      entry.push_back({spec.search->length_path, &spec.search->length_segments, length,
                       "sweep.search.objective.checkpoint" + where});
    }
    factor.push_back(std::move(entry));
  }
  factors.push_back(std::move(factor));
}

// The repeat seeds: one factor, an entry per seed.
void add_repeat_factor(const SweepSpec& spec, const ConfigPath& seed_segments, std::vector<Factor>& factors) {
  if (spec.repeat_seeds.empty()) return;
  Factor factor;
  for (std::size_t i = 0; i < spec.repeat_seeds.size(); ++i) {
    factor.push_back({{"seed", &seed_segments, spec.repeat_seeds[i], "sweep.repeat (seed " +
                                                                          std::to_string(spec.repeat_seeds[i]) + ")"}});
  }
  factors.push_back(std::move(factor));
}

// Every factor of the sweep, in the order the odometer turns them (the last fastest).
std::vector<Factor> make_factors(const SweepSpec& spec, const ConfigPath& seed_segments) {
  std::vector<Factor> factors;
  add_grid_factors(spec, factors);
  add_zip_factors(spec, factors);
  add_random_factor(spec, factors);
  add_search_factor(spec, factors);
  add_repeat_factor(spec, seed_segments, factors);
  return factors;
}

// The spec location to blame for a schema error at `error_path`: the axis that set it (or an
// element inside it, or the array it is part of), otherwise the base configuration.
std::string locate_error(const std::string& error_path, const FactorEntry& assignments) {
  auto related = [](const std::string& a, const std::string& b) {
    if (a.empty() || b.empty()) return false;
    if (a == b) return true;
    const std::string& shorter = a.size() < b.size() ? a : b;
    const std::string& longer = a.size() < b.size() ? b : a;
    return longer.compare(0, shorter.size(), shorter) == 0 &&
           (longer[shorter.size()] == '.' || longer[shorter.size()] == '[');
  };
  for (const Assignment& a : assignments) {
    if (related(a.path, error_path)) return a.location;
  }
  return error_path.empty() ? std::string("base") : "base." + error_path;
}

// Where an input field's value was written, for messages: the axis or base location in the spec,
// else the include, else the default.
std::string locate_input(const std::string& field, const SweepSpec& spec, const FactorEntry& assignments) {
  const auto writer = spec.input_writers.find(field);
  if (writer != spec.input_writers.end()) return writer->second + ": " + field;
  const auto folder = spec.input_folders.find(field);
  if (folder == spec.input_folders.end() || folder->second == spec.folder) return spec.file + ": " + locate_error(field, assignments);
  return spec.file + ": " + field + " (the default, resolved against " + folder->second + ")";
}

std::uint64_t multiply_saturating(std::uint64_t a, std::uint64_t b) {
  if (a != 0 && b > std::numeric_limits<std::uint64_t>::max() / a) return std::numeric_limits<std::uint64_t>::max();
  return a * b;
}

// The errors of a sweep's expansion: each line once, at most 20 kept.
class ExpansionErrors {
 public:
  void add(const std::string& line) {
    if (seen_.insert(line).second && lines_.size() < 20) lines_.push_back(line);
  }
  bool empty() const { return lines_.empty(); }
  const std::vector<std::string>& lines() const { return lines_; }

 private:
  std::vector<std::string> lines_;
  std::set<std::string> seen_;
};

// The job of one combination of factor entries: the elements it sets, one per hole.
using JobSlots = std::vector<const Assignment*>;

// Makes each job's configuration tree (the base with the job's slots set) and its key; the two
// implementations are JobAssemblyMethod's (sweep_expansion.hpp).
class JobAssembly {
 public:
  virtual ~JobAssembly() = default;
  /// The base with `slots` set, to be completed (references, inputs) and checked; valid until
  /// finish().
  virtual nlohmann::json& start(const JobSlots& slots) = 0;
  /// The key of the tree start() gave, completed; `inputs`: its shared "inputs" object (nullptr:
  /// none); `resolved_changed`: references resolved changed it beyond the slots and "inputs".
  virtual std::string calc_key(const JobSlots& slots, const nlohmann::json* inputs, bool resolved_changed) = 0;
  /// Done with the tree; `dirty`: it changed beyond the slots and "inputs".
  virtual void finish(bool dirty) = 0;
};

// The reference: a copy of the base per job, the whole tree hashed.
class PlainJobAssembly : public JobAssembly {
 public:
  explicit PlainJobAssembly(const nlohmann::json& base) : base_(base) {}
  nlohmann::json& start(const JobSlots& slots) override {
    work_ = base_;
    for (const Assignment* a : slots) set_config_element(work_, *a->segments, a->value);
    return work_;
  }
  std::string calc_key(const JobSlots&, const nlohmann::json*, bool) override { return calc_job_key(work_); }
  void finish(bool) override {}

 private:
  const nlohmann::json& base_;
  nlohmann::json work_;
};

// The speed-up: one tree edited in place and set back (a job costs no copy of the ~15 KB tree),
// and keys from a text cut up at the holes once per distinct "inputs" (JobKeyTemplate): every
// job sets the same elements, so its canonical text differs from job to job only there.
class FastJobAssembly : public JobAssembly {
 public:
  FastJobAssembly(const nlohmann::json& base, std::vector<ConfigPath> holes)
      : base_(base), holes_(std::move(holes)), work_(base), key_values_(holes_.size()) {
    for (const ConfigPath& hole : holes_) {
      std::string unused;
      base_values_.push_back(find_config_element(base_, hole, unused));
    }
  }
  nlohmann::json& start(const JobSlots& slots) override {
    for (const Assignment* a : slots) set_config_element(work_, *a->segments, a->value);
    return work_;
  }
  std::string calc_key(const JobSlots& slots, const nlohmann::json* inputs, bool resolved_changed) override {
    const JobKeyTemplate* key_template = nullptr;
    if (!resolved_changed && templates_.size() < 64) {
      auto& entry = templates_[inputs];
      if (!entry) entry = std::make_unique<const JobKeyTemplate>(work_, holes_);
      if (entry->usable()) key_template = entry.get();
    }
    if (key_template == nullptr) return calc_job_key(work_);
    for (std::size_t i = 0; i < slots.size(); ++i) key_values_[i] = &slots[i]->canonical;
    return key_template->calc_key(key_values_, scratch_);
  }
  void finish(bool dirty) override {
    if (dirty) {
      work_ = base_;
      return;
    }
    for (std::size_t i = 0; i < holes_.size(); ++i) set_config_element(work_, holes_[i], *base_values_[i]);
    const auto base_inputs = base_.find("inputs");
    if (base_inputs == base_.end()) {
      work_.erase("inputs");
    } else {
      work_["inputs"] = *base_inputs;
    }
  }

 private:
  const nlohmann::json& base_;
  std::vector<ConfigPath> holes_;
  nlohmann::json work_;
  std::vector<const nlohmann::json*> base_values_;  // the base's element at each hole
  std::map<const nlohmann::json*, std::unique_ptr<const JobKeyTemplate>> templates_;
  std::vector<const std::string*> key_values_;
  std::string scratch_;
};

// The elements every job sets: one per entry of the first of each factor's entries.
std::vector<ConfigPath> collect_holes(const std::vector<Factor>& factors) {
  std::vector<ConfigPath> holes;
  for (const Factor& factor : factors) {
    for (const Assignment& a : factor.front()) holes.push_back(*a.segments);
  }
  return holes;
}

std::unique_ptr<JobAssembly> make_job_assembly(JobAssemblyMethod method, const nlohmann::json& base,
                                               const std::vector<Factor>& factors) {
  if (method == JobAssemblyMethod::plain) return std::make_unique<PlainJobAssembly>(base);
  return std::make_unique<FastJobAssembly>(base, collect_holes(factors));
}

// Refuses, before any job (or random sample) is made, a sweep over the limit; returns its count.
std::uint64_t check_expansion_count(const SweepSpec& spec, const ExpansionLimits& limits) {
  const std::uint64_t count = calc_expansion_count(spec);
  const std::string shown = count == std::numeric_limits<std::uint64_t>::max() ? "more than 1.8e19" : std::to_string(count);
  if (count > limits.max_jobs) {
    throw SpecError({spec.file + ": sweep: expands to " + shown + " jobs, over the limit of " +
                     std::to_string(limits.max_jobs) + " (--max-jobs N raises it)"});
  }
  if (count > kMaxSweepJobs) {
    throw SpecError({spec.file + ": sweep: expands to " + shown + " jobs, over armfarm's ceiling of " +
                     std::to_string(kMaxSweepJobs) + " jobs per sweep (--max-jobs " + std::to_string(limits.max_jobs) +
                     " cannot raise it past that; split the sweep)"});
  }
  return count;
}

// The "inputs" entries of the spec's includes, which every job records.
nlohmann::json make_include_inputs(const SweepSpec& spec) {
  nlohmann::json include_inputs = nlohmann::json::object();
  for (std::size_t i = 0; i < spec.includes.size(); ++i) {
    const SpecInclude& include = spec.includes[i];
    include_inputs["include[" + std::to_string(i) + "]"] = {
        {"path", include.path}, {"resolved", include.resolved}, {"hash", include.hash}, {"kind", "include"}};
  }
  return include_inputs;
}

// The slots of the combination `counter` names (an entry index per factor).
JobSlots collect_slots(const std::vector<Factor>& factors, const std::vector<std::size_t>& counter) {
  JobSlots slots;
  for (std::size_t f = 0; f < factors.size(); ++f) {
    for (const Assignment& a : factors[f][counter[f]]) slots.push_back(&a);
  }
  return slots;
}

// The next combination, the last factor varying fastest (an odometer); false after the last.
bool advance_counter(const std::vector<Factor>& factors, std::vector<std::size_t>& counter) {
  for (std::size_t f = factors.size(); f-- > 0;) {
    if (++counter[f] < factors[f].size()) return true;
    counter[f] = 0;
  }
  return false;
}

// The sweep's hash: calc_canonical_json of its sorted job keys as a JSON array (hex digits need
// no escaping), hashed.
std::string calc_sweep_hash(const std::vector<ExpandedJob>& jobs) {
  std::vector<const std::string*> sorted_keys;
  sorted_keys.reserve(jobs.size());
  for (const ExpandedJob& job : jobs) sorted_keys.push_back(&job.key);
  std::sort(sorted_keys.begin(), sorted_keys.end(), [](const std::string* a, const std::string* b) { return *a < *b; });
  std::string keys = "[";
  keys.reserve(2 + sorted_keys.size() * 35);
  for (const std::string* key : sorted_keys) {
    if (keys.size() > 1) keys += ',';
    keys += '"';
    keys += *key;
    keys += '"';
  }
  keys += ']';
  return calc_text_hash(keys);
}

// One sweep's expansion, job by job: the steps each job goes through, in order, are the
// member functions expand_job calls.
class SweepExpansion {
 public:
  SweepExpansion(const SweepSpec& spec, const JobConfigSchema& schema, JobAssembly& assembly, std::size_t count)
      : spec_(spec),
        schema_(schema),
        assembly_(assembly),
        shared_base_(std::make_shared<const nlohmann::json>(spec.base)),
        include_inputs_(make_include_inputs(spec)),
        validate_(schema.make_sweep_validate ? schema.make_sweep_validate() : schema.validate) {
    jobs_.reserve(count);  // never reallocated: seen_keys_ views its keys
  }

  void expand_job(const JobSlots& slots) {
    nlohmann::json& work = assembly_.start(slots);
    const ReferenceOutcome references = resolve_references(work, slots);
    record_includes(work);
    const CheckTarget target = record_inputs(work, slots, references.unresolved);
    const std::optional<std::shared_ptr<const CheckedConfig>> checked =
        target.checkable ? validate_job(target.config(work), target.note, slots) : std::nullopt;
    if (checked && target.inputs_read) keep_job(work, slots, references.changed, *checked);
    assembly_.finish(references.changed || references.unresolved);
  }

  const ExpansionErrors& errors() const { return errors_; }
  std::vector<ExpandedJob> take_jobs() { return std::move(jobs_); }

 private:
  struct ReferenceOutcome {
    bool changed = false;     // stored results resolved changed the tree
    bool unresolved = false;  // a reference could not be resolved: the job is not checked further
  };
  // What the job's schema check reads: the job's tree, a stand-in with a default for each input
  // file that cannot be read, or nothing (checkable false) when there is nothing to check.
  struct CheckTarget {
    bool checkable = true;
    bool use_stand_in = false;
    nlohmann::json stand_in;
    std::string note;  // says which defaults the stand-in holds
    bool inputs_read = true;
    const nlohmann::json& config(const nlohmann::json& work) const { return use_stand_in ? stand_in : work; }
  };

  // Spec locations of the job's slots, for messages.
  static FactorEntry locate(const JobSlots& slots) {
    FactorEntry assignments;
    for (const Assignment* a : slots) assignments.push_back(*a);
    return assignments;
  }

  // Stored results the job starts from (a learned model), by hash.
  ReferenceOutcome resolve_references(nlohmann::json& work, const JobSlots& slots) {
    ReferenceOutcome outcome;
    if (!schema_.resolve_references) return outcome;
    try {
      outcome.changed = schema_.resolve_references(work);
    } catch (const ConfigError& e) {
      errors_.add(spec_.file + ": " + locate_error(e.json_path(), locate(slots)) + ": " + e.what());
      outcome.unresolved = true;
    } catch (const std::runtime_error& e) {  // not about a key (the results database cannot be read)
      errors_.add(spec_.file + ": base: " + e.what());
      outcome.unresolved = true;
    }
    return outcome;
  }

  // The includes' entries in "inputs".
  void record_includes(nlohmann::json& work) const {
    if (include_inputs_.empty()) return;
    nlohmann::json& inputs = work["inputs"];
    if (!inputs.is_object()) inputs = nlohmann::json::object();
    for (const auto& [name, entry] : include_inputs_.items()) inputs[name] = entry;
  }

  // Every input file field, resolved against the file that wrote it. A file that cannot be read
  // must not hide the job's other problems: the rest is checked against the field's default (said
  // so in the message), and the job is kept out of the sweep.
  CheckTarget record_inputs(nlohmann::json& work, const JobSlots& slots, bool unresolved) {
    auto folder_of = [&](const std::string& field) {
      const auto found = spec_.input_folders.find(field);
      return found == spec_.input_folders.end() ? schema_.default_folder : found->second;
    };
    const std::vector<InputProblem> problems = record_input_files(work, schema_.input_files, folder_of, reader_);
    CheckTarget target;
    target.checkable = !unresolved;
    target.inputs_read = problems.empty();
    if (problems.empty()) return target;
    if (target.checkable) {
      target.stand_in = work;
      target.use_stand_in = true;
    }
    for (const InputProblem& problem : problems) {
      errors_.add(locate_input(problem.field, spec_, locate(slots)) + ": " + problem.message);
      std::string unused;
      const ConfigPath segments = parse_config_path(problem.field);
      const nlohmann::json* fallback = find_config_element(schema_.defaults, segments, unused);
      if (fallback != nullptr && target.checkable) set_config_element(target.stand_in, segments, *fallback);
      target.note += (target.note.empty() ? " (checked with the default " : ", ") + problem.field;
    }
    if (target.checkable) {
      target.note += ", since the file cannot be read)";
      if (!record_input_files(target.stand_in, schema_.input_files, [&](const std::string&) { return schema_.default_folder; },
                              reader_).empty()) {
        target.checkable = false;  // even the default cannot be read: nothing more to check
      }
    }
    return target;
  }

  // The schema's check: what it made of the job (null: nothing), empty when it found a problem,
  // which is reported at the spec location that set its path.
  std::optional<std::shared_ptr<const CheckedConfig>> validate_job(const nlohmann::json& config, const std::string& note,
                                                                   const JobSlots& slots) {
    if (!validate_) return std::shared_ptr<const CheckedConfig>();
    try {
      return validate_(config);
    } catch (const ConfigError& e) {
      const std::string where = locate_error(e.json_path(), locate(slots));
      const bool on_axis = where.rfind("base", 0) != 0;
      errors_.add(spec_.file + ": " + where + ": " + (on_axis && !e.json_path().empty() ? e.json_path() + ": " : "") +
                  e.message() + note);
      return std::nullopt;
    }
  }

  // The checked job, unless an earlier job had its key: its values, shared base and inputs, key,
  // seed and what the check made of it.
  void keep_job(const nlohmann::json& work, const JobSlots& slots, bool resolved_changed,
                std::shared_ptr<const CheckedConfig> checked) {
    ExpandedJob compact;
    const auto inputs = work.find("inputs");
    if (inputs != work.end()) {
      // Jobs mostly record the same inputs: one copy per distinct "inputs" object.
      if (!last_inputs_ || *last_inputs_ != *inputs) {
        auto& slot = shared_inputs_[inputs->dump()];
        if (!slot) slot = std::make_shared<const nlohmann::json>(*inputs);
        last_inputs_ = slot;
      }
      compact.inputs = last_inputs_;
    }
    compact.key = assembly_.calc_key(slots, compact.inputs.get(), resolved_changed);
    const auto seed = work.find("seed");
    if (seed != work.end() && seed->is_number_integer()) compact.seed = seed->get<std::int64_t>();
    if (seen_keys_.count(compact.key) != 0) return;
    compact.params = nlohmann::json::object();
    for (const Assignment* a : slots) compact.params[a->path] = a->value;
    compact.base = shared_base_;
    if (resolved_changed) compact.full = std::make_shared<const nlohmann::json>(work);
    compact.checked = std::move(checked);
    jobs_.push_back(std::move(compact));
    seen_keys_.insert(jobs_.back().key);  // jobs_ holds its reserved places, so the view stays put
  }

  const SweepSpec& spec_;
  const JobConfigSchema& schema_;
  JobAssembly& assembly_;
  const std::shared_ptr<const nlohmann::json> shared_base_;
  const nlohmann::json include_inputs_;
  const ConfigCheck validate_;
  InputFileReader reader_;
  ExpansionErrors errors_;
  std::map<std::string, std::shared_ptr<const nlohmann::json>> shared_inputs_;
  std::shared_ptr<const nlohmann::json> last_inputs_;
  std::vector<ExpandedJob> jobs_;
  std::unordered_set<std::string_view> seen_keys_;
};

}  // namespace

nlohmann::json ExpandedJob::config() const {
  if (full) return *full;
  nlohmann::json config = base ? *base : nlohmann::json::object();
  for (const auto& [path, value] : params.items()) set_config_element(config, parse_config_path(path), value);
  if (inputs) {
    config["inputs"] = *inputs;
  } else {
    config.erase("inputs");
  }
  return config;
}

ExpandedJob ExpandedJob::from_config(const nlohmann::json& config) {
  ExpandedJob job;
  nlohmann::json base = config;
  if (base.contains("inputs")) {
    job.inputs = std::make_shared<const nlohmann::json>(base["inputs"]);
    base.erase("inputs");
  }
  job.base = std::make_shared<const nlohmann::json>(std::move(base));
  job.params = nlohmann::json::object();
  job.key = calc_job_key(config);
  if (config.contains("seed") && config["seed"].is_number_integer()) job.seed = config["seed"].get<std::int64_t>();
  return job;
}

std::uint64_t calc_expansion_count(const SweepSpec& spec) {
  std::uint64_t count = 1;
  for (const SpecAxis& axis : spec.grid) count = multiply_saturating(count, axis.values.size());
  for (const SpecZipGroup& group : spec.zip) {
    count = multiply_saturating(count, group.axes.empty() ? 1 : group.axes.front().values.size());
  }
  if (spec.random) count = multiply_saturating(count, static_cast<std::uint64_t>(spec.random->samples));
  if (spec.search) {
    count = multiply_saturating(count, spec.search->decided ? spec.search->decided->size()
                                                            : std::max<std::uint64_t>(spec.search->settings.slots, 1));
  }
  if (!spec.repeat_seeds.empty()) count = multiply_saturating(count, spec.repeat_seeds.size());
  return count;
}

ExpandedSweep expand_sweep(SweepSpec spec, const JobConfigSchema& schema, const ExpansionLimits& limits,
                           JobAssemblyMethod method) {
  const std::uint64_t count = check_expansion_count(spec, limits);
  const ConfigPath seed_path = {{"seed", std::nullopt}};
  const std::vector<Factor> factors = make_factors(spec, seed_path);
  ExpandedSweep sweep;
  {
    const std::unique_ptr<JobAssembly> assembly = make_job_assembly(method, spec.base, factors);
    SweepExpansion expansion(spec, schema, *assembly, static_cast<std::size_t>(count));
    std::vector<std::size_t> counter(factors.size(), 0);
    do {
      expansion.expand_job(collect_slots(factors, counter));
    } while (advance_counter(factors, counter));
    if (!expansion.errors().empty()) throw SpecError(expansion.errors().lines());
    sweep.jobs = expansion.take_jobs();
  }
  sweep.spec_hash = calc_sweep_hash(sweep.jobs);
  sweep.spec = std::move(spec);
  return sweep;
}

}  // namespace armfarm
