#include "runner/spec/sweep_expansion.hpp"

#include "runner/spec/canonical_json.hpp"
#include "runner/spec/config_check.hpp"
#include "runner/spec/input_files.hpp"
#include "runner/spec/job_key_template.hpp"
#include "runner/spec/spec_error.hpp"

#include "engine/random/random_stream.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <string_view>
#include <unordered_set>

namespace armfarm {
namespace {

// One value of a factor: the elements it sets, each with its spec location for messages.
struct Assignment {
  std::string path;
  const std::vector<PathSegment>* segments;
  nlohmann::json value;
  std::string location;
  std::string canonical = calc_canonical_json(value);  ///< what the job key hashes of it
};
using FactorEntry = std::vector<Assignment>;
using Factor = std::vector<FactorEntry>;

std::vector<Factor> make_factors(const SweepSpec& spec, const std::vector<PathSegment>& seed_segments) {
  std::vector<Factor> factors;
  for (const SpecAxis& axis : spec.grid) {
    Factor factor;
    for (std::size_t i = 0; i < axis.values.size(); ++i) {
      factor.push_back({{axis.path, &axis.segments, axis.values[i], axis.location + "[" + std::to_string(i) + "]"}});
    }
    factors.push_back(std::move(factor));
  }
  for (const SpecZipGroup& group : spec.zip) {
    Factor factor(group.axes.front().values.size());
    for (const SpecAxis& axis : group.axes) {
      for (std::size_t i = 0; i < axis.values.size(); ++i) {
        factor[i].push_back({axis.path, &axis.segments, axis.values[i], axis.location + "[" + std::to_string(i) + "]"});
      }
    }
    factors.push_back(std::move(factor));
  }
  if (spec.random) {
    RandomStream generator(spec.random->seed, "sweep.random");
    Factor factor;
    for (int s = 0; s < spec.random->samples; ++s) {
      FactorEntry entry;
      for (const SpecRandomParam& param : spec.random->params) {
        const double u = generator.uniform();
        nlohmann::json value;
        switch (param.distribution) {
          case RandomDistribution::uniform:
            value = param.low + u * (param.high - param.low);
            break;
          case RandomDistribution::loguniform:
            value = std::exp(std::log(param.low) + u * (std::log(param.high) - std::log(param.low)));
            break;
          case RandomDistribution::choice:
            value = param.choices[std::min(param.choices.size() - 1,
                                           static_cast<std::size_t>(u * static_cast<double>(param.choices.size())))];
            break;
        }
        entry.push_back({param.path, &param.segments, value, param.location + " (sample " + std::to_string(s) + ")"});
      }
      factor.push_back(std::move(entry));
    }
    factors.push_back(std::move(factor));
  }
  if (spec.search) {
    // The steps decided before any result (the search runner decides the rest as jobs finish).
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
  if (!spec.repeat_seeds.empty()) {
    Factor factor;
    for (std::size_t i = 0; i < spec.repeat_seeds.size(); ++i) {
      factor.push_back({{"seed", &seed_segments, spec.repeat_seeds[i], "sweep.repeat (seed " +
                                                                            std::to_string(spec.repeat_seeds[i]) + ")"}});
    }
    factors.push_back(std::move(factor));
  }
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

ExpandedSweep expand_sweep(SweepSpec spec, const JobConfigSchema& schema, const ExpansionLimits& limits) {
  // Count first: a sweep over the limit is refused before any job (or random sample) is made.
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
  ExpandedSweep sweep;
  sweep.jobs.reserve(static_cast<std::size_t>(count));  // never reallocated below: seen_keys views its keys
  const std::vector<PathSegment> seed_segments = {{"seed", std::nullopt}};
  const std::vector<Factor> factors = make_factors(spec, seed_segments);
  const auto shared_base = std::make_shared<const nlohmann::json>(spec.base);
  // Jobs mostly record the same inputs: one copy per distinct "inputs" object.
  std::map<std::string, std::shared_ptr<const nlohmann::json>> shared_inputs;
  std::shared_ptr<const nlohmann::json> last_inputs;
  nlohmann::json include_inputs = nlohmann::json::object();
  for (std::size_t i = 0; i < spec.includes.size(); ++i) {
    const SpecInclude& include = spec.includes[i];
    include_inputs["include[" + std::to_string(i) + "]"] = {
        {"path", include.path}, {"resolved", include.resolved}, {"hash", include.hash}, {"kind", "include"}};
  }
  // Every job sets the same elements (one entry of each factor); the key of a job hashes the
  // canonical text of its configuration, which differs from job to job only there: one cut-up
  // text (JobKeyTemplate) per distinct "inputs" serves every job that records them.
  std::vector<std::vector<PathSegment>> holes;
  for (const Factor& factor : factors) {
    for (const Assignment& a : factor.front()) holes.push_back(*a.segments);
  }
  std::map<const nlohmann::json*, std::unique_ptr<const JobKeyTemplate>> key_templates;
  std::string key_scratch;
  std::vector<const std::string*> key_values(holes.size());

  // The job being checked, in place: the base with this job's values set and its inputs recorded;
  // afterwards its elements are set back to the base's (or the whole tree when something else
  // changed), so a job costs no copy of the ~15 KB tree.
  nlohmann::json work = spec.base;
  std::vector<const nlohmann::json*> base_values;
  for (const std::vector<PathSegment>& hole : holes) {
    std::string unused;
    base_values.push_back(find_config_element(*shared_base, hole, unused));
  }
  const auto base_inputs = shared_base->find("inputs");

  const std::function<void(const nlohmann::json&)> validate =
      schema.make_sweep_validate ? schema.make_sweep_validate() : schema.validate;

  std::vector<std::size_t> counter(factors.size(), 0);
  std::vector<std::string> errors;
  std::set<std::string> seen_errors;
  std::unordered_set<std::string_view> seen_keys;
  InputFileReader reader;
  std::vector<const Assignment*> slots;
  FactorEntry assignments;
  for (bool more = true; more;) {
    slots.clear();
    for (std::size_t f = 0; f < factors.size(); ++f) {
      for (const Assignment& a : factors[f][counter[f]]) slots.push_back(&a);
    }
    bool dirty = false;  // changed beyond the holes and "inputs": restore the whole tree
    nlohmann::json params = nlohmann::json::object();
    for (std::size_t i = 0; i < slots.size(); ++i) {
      const Assignment& a = *slots[i];
      set_config_element(work, *a.segments, a.value);
      params[a.path] = a.value;
      key_values[i] = &a.canonical;
    }
    // Spec locations for messages (built only when a message needs them).
    auto located = [&]() -> const FactorEntry& {
      assignments.clear();
      for (const Assignment* a : slots) assignments.push_back(*a);
      return assignments;
    };
    // Stored results the job starts from (a learned model), by hash.
    bool unresolved = false;
    bool resolved_changed = false;
    if (schema.resolve_references) {
      try {
        resolved_changed = schema.resolve_references(work);
      } catch (const std::runtime_error& e) {
        const std::string what = e.what();
        const std::size_t colon = what.find(": ");
        const std::string path = colon == std::string::npos ? std::string() : what.substr(0, colon);
        const std::string line = spec.file + ": " + locate_error(path, located()) + ": " + what;
        if (seen_errors.insert(line).second && errors.size() < 20) errors.push_back(line);
        unresolved = true;
      }
      dirty = resolved_changed || unresolved;
    }
    // Input files: includes first, then every file field, resolved against the file that wrote it.
    if (!include_inputs.empty()) {
      nlohmann::json& inputs = work["inputs"];
      if (!inputs.is_object()) inputs = nlohmann::json::object();
      for (const auto& [name, entry] : include_inputs.items()) inputs[name] = entry;
    }
    auto folder_of = [&](const std::string& field) {
      const auto found = spec.input_folders.find(field);
      return found == spec.input_folders.end() ? schema.default_folder : found->second;
    };
    const std::vector<InputProblem> problems = record_input_files(work, schema.input_files, folder_of, reader);
    // A file that cannot be read must not hide the job's other problems: check the rest against
    // the field's default (said so in the message), and keep the job out of the sweep.
    const nlohmann::json* check_config = unresolved ? nullptr : &work;
    nlohmann::json stand_in;
    std::string stand_in_note;
    if (!problems.empty() && check_config != nullptr) {
      stand_in = work;
      check_config = &stand_in;
    }
    for (const InputProblem& problem : problems) {
      const std::string line = locate_input(problem.field, spec, located()) + ": " + problem.message;
      if (seen_errors.insert(line).second && errors.size() < 20) errors.push_back(line);
      std::string unused;
      const std::vector<PathSegment> segments = parse_config_path(problem.field);
      const nlohmann::json* fallback = find_config_element(schema.defaults, segments, unused);
      if (fallback != nullptr && check_config != nullptr) set_config_element(stand_in, segments, *fallback);
      stand_in_note += (stand_in_note.empty() ? " (checked with the default " : ", ") + problem.field;
    }
    if (!problems.empty() && check_config != nullptr) {
      stand_in_note += ", since the file cannot be read)";
      if (!record_input_files(stand_in, schema.input_files, [&](const std::string&) { return schema.default_folder; },
                              reader).empty()) {
        check_config = nullptr;  // even the default cannot be read: nothing more to check
      }
    }
    try {
      if (validate && check_config != nullptr) validate(*check_config);
    } catch (const ConfigError& e) {
      const std::string where = locate_error(e.json_path(), located());
      const std::string what = e.what();
      const std::string bare = e.json_path().empty() ? what : what.substr(e.json_path().size() + 2);
      const bool on_axis = where.rfind("base", 0) != 0;
      const std::string line = spec.file + ": " + where + ": " + (on_axis && !e.json_path().empty() ? e.json_path() + ": " : "") +
                               bare + stand_in_note;
      if (seen_errors.insert(line).second && errors.size() < 20) errors.push_back(line);
      check_config = nullptr;
    }
    if (problems.empty() && check_config != nullptr) {
      ExpandedJob compact;
      const auto inputs = work.find("inputs");
      if (inputs != work.end()) {
        if (!last_inputs || *last_inputs != *inputs) {
          auto& slot = shared_inputs[inputs->dump()];
          if (!slot) slot = std::make_shared<const nlohmann::json>(*inputs);
          last_inputs = slot;
        }
        compact.inputs = last_inputs;
      }
      const JobKeyTemplate* key_template = nullptr;
      if (!resolved_changed && key_templates.size() < 64) {
        auto& entry = key_templates[compact.inputs.get()];
        if (!entry) entry = std::make_unique<const JobKeyTemplate>(work, holes);
        if (entry->usable()) key_template = entry.get();
      }
      compact.key = key_template ? key_template->calc_key(key_values, key_scratch) : calc_job_key(work);
      const auto seed = work.find("seed");
      if (seed != work.end() && seed->is_number_integer()) compact.seed = seed->get<std::int64_t>();
      // The set views the kept jobs' keys: `jobs` holds its reserved `count` places, so they stay put.
      if (seen_keys.count(compact.key) == 0) {
        compact.params = std::move(params);
        compact.base = shared_base;
        if (resolved_changed) compact.full = std::make_shared<const nlohmann::json>(work);
        sweep.jobs.push_back(std::move(compact));
        seen_keys.insert(sweep.jobs.back().key);
      }
    }
    // Back to the base for the next job.
    if (dirty) {
      work = *shared_base;
    } else {
      for (std::size_t i = 0; i < slots.size(); ++i) set_config_element(work, holes[i], *base_values[i]);
      if (base_inputs == shared_base->end()) {
        work.erase("inputs");
      } else {
        work["inputs"] = *base_inputs;
      }
    }
    // Odometer: the last factor varies fastest.
    more = false;
    for (std::size_t f = factors.size(); f-- > 0;) {
      if (++counter[f] < factors[f].size()) {
        more = true;
        break;
      }
      counter[f] = 0;
    }
  }
  if (!errors.empty()) throw SpecError(errors);

  std::vector<const std::string*> sorted_keys;
  sorted_keys.reserve(sweep.jobs.size());
  for (const ExpandedJob& job : sweep.jobs) sorted_keys.push_back(&job.key);
  std::sort(sorted_keys.begin(), sorted_keys.end(), [](const std::string* a, const std::string* b) { return *a < *b; });
  // calc_canonical_json of the sorted keys as a JSON array (hex digits need no escaping).
  std::string keys = "[";
  keys.reserve(2 + sorted_keys.size() * 35);
  for (const std::string* key : sorted_keys) {
    if (keys.size() > 1) keys += ',';
    keys += '"';
    keys += *key;
    keys += '"';
  }
  keys += ']';
  sweep.spec_hash = calc_text_hash(keys);
  sweep.spec = std::move(spec);
  return sweep;
}

}  // namespace armfarm
