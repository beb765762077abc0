#include "runner/execution/search_runner.hpp"

#include <cstdlib>
#include <filesystem>
#include <limits>
#include <map>

#include "base/number_format.hpp"
#include "runner/search/search_sequence.hpp"
#include "runner/spec/spec_error.hpp"

namespace armfarm {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The expanded job of one step (its key is the job key).
ExpandedJob expand_step(const SweepSpec& spec, const JobConfigSchema& schema, const search::SearchPoint& point,
                        std::size_t rung) {
  SweepSpec one = spec;
  one.search->decided = std::vector<std::pair<search::SearchPoint, std::size_t>>{{point, rung}};
  ExpandedSweep sweep = expand_sweep(std::move(one), schema);
  return sweep.jobs.front();
}

// The objective of a done job at `rung` (as the metric), or empty when the metric is NULL or absent.
// Without learning.heldout_checkpoints in the spec a held-out metric is still stored at the
// job's one default checkpoint (the end of learning): the objective is then the row of the
// highest checkpoint (the "default the last"), a metric without checkpoints its only row.
std::optional<double> find_objective(const ResultsStore& store, std::int64_t job_id, const SpecSearch& search,
                                     std::size_t rung) {
  // The rows wanted: this joint's (or the job-level one when joint is 0). The joint is compared
  // against a plain value: two local std::optional objects compared with == drew a false
  // -Wmaybe-uninitialized from g++ 12 -O3.
  const int joint = search.objective.joint;
  const MetricRecord* found = nullptr;
  const std::vector<MetricRecord> metrics = store.find_metrics(job_id);
  for (const MetricRecord& m : metrics) {
    if (m.name != search.objective.metric) continue;
    if (joint > 0 ? m.joint != joint : m.joint.has_value()) continue;
    if (search.objective.checkpoint) {
      if (m.checkpoint == search.rungs[rung]) return m.value;
    } else if (found == nullptr || (found->checkpoint && (!m.checkpoint || *m.checkpoint > *found->checkpoint))) {
      found = &m;
    }
  }
  return found != nullptr ? found->value : std::nullopt;
}

struct Replay {
  search::SearchHistory history;
  std::vector<std::string> keys;                 ///< per step
  std::vector<std::optional<double>> objectives;  ///< per committed step, as the metric
  std::vector<std::string> reasons;               ///< per committed step, why the objective is empty
  bool finished = false;                          ///< the search decided it is over
};

Replay replay(const SweepSpec& spec, const search::SearchSettings& settings, const JobConfigSchema& schema,
              const std::string& db_path, std::map<std::pair<std::size_t, std::size_t>, std::string>& key_cache) {
  Replay r;
  std::optional<ResultsStore> store;
  // Opened writable, as run opens it: a file another runner is creating at this moment (empty,
  // its schema not yet committed) is waited for, not refused as "empty file".
  if (std::filesystem::exists(db_path)) store = ResultsStore::open(db_path, ResultsStore::Mode::read_write);
  // Takes the committed outcome of the next step without a loss; false when its job has not run.
  const auto take_loss = [&] {
    const std::size_t s = r.history.losses.size();
    const std::optional<JobRecord> job = store ? store->find_job(r.keys[s]) : std::nullopt;
    if (!job || (job->status != "done" && job->status != "failed" && job->status != "diverged" && job->status != "timeout")) {
      return false;
    }
    std::optional<double> objective;
    std::string reason = job->status;
    if (job->status == "done") {
      objective = find_objective(*store, job->id, *spec.search, r.history.steps[s].rung);
      reason = objective ? "" : "the objective metric is undefined (NULL) or missing";
    }
    r.history.losses.push_back(!objective ? kInfinity : spec.search->objective.lower_is_better ? *objective : -*objective);
    r.objectives.push_back(objective);
    r.reasons.push_back(reason);
    return true;
  };
  for (;;) {
    const search::NextStep next = search::calc_next_step(settings, r.history);
    if (next.needs_loss) {
      if (!take_loss()) return r;  // not run yet: the replay stops here
      continue;
    }
    if (next.decision.kind != search::SearchDecision::Kind::run) {
      r.finished = true;
      while (r.history.losses.size() < r.history.steps.size() && take_loss()) {
      }
      return r;
    }
    search::add_step(next.decision, next.visible, r.history);
    const search::SearchStep& step = r.history.steps.back();
    const auto id = std::make_pair(step.trial, step.rung);
    auto cached = key_cache.find(id);
    if (cached == key_cache.end()) {
      cached = key_cache.emplace(id, expand_step(spec, schema, r.history.trials[step.trial].point, step.rung).key).first;
    }
    r.keys.push_back(cached->second);
  }
}

// The space as stored (searches.space): per axis in order, its path, kind, bounds or choices.
std::string make_space_text(const SpecSearch& search) {
  nlohmann::json axes = nlohmann::json::array();
  for (std::size_t d = 0; d < search.settings.space.axes.size(); ++d) {
    const search::SearchAxis& axis = search.settings.space.axes[d];
    nlohmann::json entry = {{"path", axis.path}, {"kind", search::to_string(axis.kind)}};
    if (axis.kind == search::AxisKind::categorical) {
      entry["choices"] = search.axes[d].choices;
    } else {
      entry["low"] = axis.low;
      entry["high"] = axis.high;
    }
    axes.push_back(std::move(entry));
  }
  return axes.dump();
}

// Whether the search proposes with TPE: the method itself, or the sampler of ASHA and Hyperband.
bool uses_tpe(const search::SearchSettings& settings) {
  return settings.method == search::SearchMethod::tpe || settings.sampler == search::SearchSampler::tpe;
}

// The search's row as this runner takes its decisions.
SearchRecord make_search_record(const SweepSpec& spec, const search::SearchSettings& settings) {
  const SpecSearch& search = *spec.search;
  SearchRecord record;
  record.sweep = spec.name;
  record.method = search::to_string(settings.method);
  record.sampler = search::to_string(settings.sampler);
  record.seed = static_cast<std::int64_t>(settings.seed);
  record.eta = static_cast<std::int64_t>(settings.eta);
  record.slots = static_cast<std::int64_t>(settings.slots);
  record.budget_unit = search.budget_unit == SpecSearch::BudgetUnit::jobs ? "jobs" : "cpu_seconds";
  record.budget = settings.budget;
  record.resumable = settings.resumable;
  record.objective_metric = search.objective.metric;
  record.objective_direction = search.objective.lower_is_better ? "lower" : "higher";
  if (search.objective.joint > 0) record.objective_joint = search.objective.joint;
  record.objective_checkpoint = search.objective.checkpoint;
  for (std::size_t k = 0; k < settings.rung_cost.size(); ++k) {
    SearchRungRecord rung;
    rung.rung = static_cast<std::int64_t>(k);
    if (search.objective.checkpoint) rung.checkpoint = search.rungs[k];
    rung.cost = settings.rung_cost[k];
    record.rungs.push_back(rung);
  }
  record.max_trials = static_cast<std::int64_t>(settings.max_trials);
  record.bracket_size = static_cast<std::int64_t>(settings.bracket_size);
  record.tpe_startup = static_cast<std::int64_t>(settings.tpe.startup);
  record.tpe_gamma = settings.tpe.gamma;
  record.tpe_max_good = static_cast<std::int64_t>(settings.tpe.max_good);
  record.tpe_candidates = static_cast<std::int64_t>(settings.tpe.candidates);
  record.space = make_space_text(search);
  if (uses_tpe(settings)) record.tpe_rule = settings.tpe.joint ? "joint" : "per_axis";
  if (uses_tpe(settings) && settings.tpe.joint) {
    record.tpe_prior_weight = settings.tpe.prior_weight;
    record.tpe_bandwidth = settings.tpe.bandwidth;
    record.tpe_liar_bandwidth = settings.tpe.liar_bandwidth;
  }
  return record;
}

// The joint rule's constants (w, h, λ) are this build's, not the file's: a row of a joint search
// whose constants differ (a NULL read as the schema-8 build's, kTpeConstantsOfVersion8) is
// refused with one line, since this build would continue it with other proposals.
void refuse_other_tpe_constants(const SweepSpec& spec, const std::string& db_path, const SearchRecord& stored,
                                const search::TpeSettings& tpe, std::vector<std::string>& lines) {
  const TpeJointConstants in_file = read_tpe_constants(stored);
  if (in_file.prior_weight == tpe.prior_weight && in_file.bandwidth == tpe.bandwidth &&
      in_file.liar_bandwidth == tpe.liar_bandwidth) {
    return;
  }
  const auto exact = [](double value) {  // the fewest digits that read back as the same double
    int digits = 1;
    while (digits < 17 && std::strtod(format_number(value, digits).c_str(), nullptr) != value) ++digits;
    return format_number(value, digits);
  };
  const auto describe = [&](double w, double h, double lambda) {
    return "prior weight " + exact(w) + ", bandwidth " + exact(h) + " and liar bandwidth " + exact(lambda);
  };
  lines.push_back(spec.file + ": sweep.search: " + db_path + " holds search '" + spec.name +
                  "' proposed by TPE's joint rule with " + describe(in_file.prior_weight, in_file.bandwidth, in_file.liar_bandwidth) +
                  ", this build's are " + describe(tpe.prior_weight, tpe.bandwidth, tpe.liar_bandwidth) +
                  "; it would continue with other proposals (resume it with a build of the file's constants, or give the "
                  "sweep another name, or use another database)");
}

// A search the file holds already under this sweep's name (a resume, or another runner that
// started first): what the spec decides must be the same, or the steps replayed would be
// another search's (refused, one line per difference, before anything is written); what the
// build decides (each rung's estimated cost, TPE's start-up by the budget rule, its constants
// and its rule, joint or per axis) is taken from the file, so a runner of another build
// continues the same search. A row of schema version 6 lacks some of them (empty): this
// runner's are used and written. TPE's rule is the exception: NULL (a row of schema 6 or 7) is
// the per-axis rule those builds proposed with, adopted and then written as "per_axis". The
// joint rule's constants are compared, not adopted (refuse_other_tpe_constants).
void adopt_stored_search(const SweepSpec& spec, const std::string& db_path, search::SearchSettings& settings) {
  if (!std::filesystem::exists(db_path)) return;
  const std::optional<SearchRecord> stored = ResultsStore::open(db_path, ResultsStore::Mode::read_write).find_search(spec.name);
  if (!stored) return;
  const SearchRecord wanted = make_search_record(spec, settings);
  std::vector<std::string> lines;
  const auto differs = [&](const std::string& key, const std::string& in_file, const std::string& in_spec) {
    if (in_file == in_spec) return;
    lines.push_back(spec.file + ": sweep.search" + (key.empty() ? "" : "." + key) + ": " + db_path + " holds search '" +
                    spec.name + "' with " + (key.empty() ? "this" : key) + " " + in_file + ", the spec gives " + in_spec +
                    "; a search cannot change under its name (give the sweep another name, or use another database)");
  };
  const auto optional_text = [](const std::optional<std::int64_t>& v) { return v ? std::to_string(*v) : std::string("none"); };
  differs("method", stored->method, wanted.method);
  differs("sampler", stored->sampler, wanted.sampler);
  differs("seed", std::to_string(stored->seed), std::to_string(wanted.seed));
  differs("eta", std::to_string(stored->eta), std::to_string(wanted.eta));
  differs("slots", std::to_string(stored->slots), std::to_string(wanted.slots));
  differs("budget", format_number(stored->budget, 17) + " " + stored->budget_unit,
          format_number(wanted.budget, 17) + " " + wanted.budget_unit);
  differs("objective.metric", stored->objective_metric, wanted.objective_metric);
  differs("objective.joint", stored->objective_joint ? std::to_string(*stored->objective_joint) : "mean",
          wanted.objective_joint ? std::to_string(*wanted.objective_joint) : "mean");
  differs("objective.checkpoint", optional_text(stored->objective_checkpoint), optional_text(wanted.objective_checkpoint));
  std::string stored_rungs, wanted_rungs;
  for (const SearchRungRecord& r : stored->rungs) stored_rungs += (stored_rungs.empty() ? "" : ",") + optional_text(r.checkpoint);
  for (const SearchRungRecord& r : wanted.rungs) wanted_rungs += (wanted_rungs.empty() ? "" : ",") + optional_text(r.checkpoint);
  differs("rungs", "[" + stored_rungs + "]", "[" + wanted_rungs + "]");
  if (stored->max_trials) differs("max_trials", std::to_string(*stored->max_trials), std::to_string(*wanted.max_trials));
  if (stored->bracket_size) differs("bracket_size", std::to_string(*stored->bracket_size), std::to_string(*wanted.bracket_size));
  if (stored->space) differs("space", *stored->space, *wanted.space);
  if (spec.search->tpe_rule_given && uses_tpe(settings)) {
    differs("tpe_rule", stored->tpe_rule.value_or("per_axis"), wanted.tpe_rule.value_or("per_axis"));
  }
  if (stored->tpe_startup && spec.search->tpe_startup != 0) {
    differs("tpe_startup", std::to_string(*stored->tpe_startup), std::to_string(spec.search->tpe_startup));
  }
  if (stored->resumable != wanted.resumable) differs("", stored->resumable ? "resumable promotions" : "rerun promotions",
                                                     wanted.resumable ? "resumable promotions" : "rerun promotions");
  // TPE's rule: NULL is a row of a build before schema version 8, whose TPE was per axis.
  const bool joint = uses_tpe(settings) && stored->tpe_rule.value_or("per_axis") == "joint";
  if (joint) refuse_other_tpe_constants(spec, db_path, *stored, settings.tpe, lines);
  if (!lines.empty()) throw SpecError(lines);
  // The build's part, from the file.
  if (stored->rungs.size() == settings.rung_cost.size()) {
    for (std::size_t k = 0; k < stored->rungs.size(); ++k) settings.rung_cost[k] = stored->rungs[k].cost;
  }
  if (stored->tpe_startup) settings.tpe.startup = static_cast<std::size_t>(*stored->tpe_startup);
  if (stored->tpe_gamma) settings.tpe.gamma = *stored->tpe_gamma;
  if (stored->tpe_max_good) settings.tpe.max_good = static_cast<std::size_t>(*stored->tpe_max_good);
  if (stored->tpe_candidates) settings.tpe.candidates = static_cast<std::size_t>(*stored->tpe_candidates);
  if (uses_tpe(settings)) settings.tpe.joint = joint;
}

// Writes what the store lacks of the replayed search: the search row, new steps, objectives.
void record_search(const SweepSpec& spec, const search::SearchSettings& settings, const Replay& r,
                   const std::string& db_path) {
  ResultsStore store = ResultsStore::open(db_path, ResultsStore::Mode::read_write);
  if (!store.find_sweep(spec.name)) return;
  const SpecSearch& search = *spec.search;
  store.insert_search(make_search_record(spec, settings));
  const std::vector<SearchStepRecord> stored = store.find_search_steps(spec.name);
  // A step is its trial's first ("new") by the history, never by what the file holds yet: another
  // runner may be writing the same steps (insert_search_step keeps the first writer's agreeing row).
  std::vector<bool> trial_started(r.history.trials.size(), false);
  for (std::size_t s = 0; s < stored.size() && s < r.history.steps.size(); ++s) trial_started[r.history.steps[s].trial] = true;
  for (std::size_t s = stored.size(); s < r.history.steps.size(); ++s) {
    if (!store.find_job(r.keys[s])) break;  // registered by a later round
    const search::SearchStep& step = r.history.steps[s];
    SearchStepRecord row;
    row.step = static_cast<std::int64_t>(s);
    row.trial = static_cast<std::int64_t>(step.trial);
    row.rung = static_cast<std::int64_t>(step.rung);
    row.visible = static_cast<std::int64_t>(step.visible);
    row.cost = step.cost;
    row.job_key = r.keys[s];
    const bool new_trial = !trial_started[step.trial];
    trial_started[step.trial] = true;
    row.kind = new_trial ? "new" : "promotion";
    std::optional<SearchTrialRecord> trial;
    if (new_trial) {
      // The trial's point: the axes' values, not the first step's rung (checkpoints, length).
      nlohmann::json point = calc_search_step_params(search, r.history.trials[step.trial].point, step.rung);
      point.erase("learning.heldout_checkpoints");
      if (!search.length_path.empty()) point.erase(search.length_path);
      trial = SearchTrialRecord{row.trial, static_cast<std::int64_t>(r.history.trials[step.trial].bracket), point.dump()};
    }
    store.insert_search_step(spec.name, row, trial);
  }
  const std::vector<SearchStepRecord> now = store.find_search_steps(spec.name);
  for (std::size_t s = 0; s < now.size() && s < r.objectives.size(); ++s) {
    if (!now[s].committed) store.update_search_objective(spec.name, static_cast<std::int64_t>(s), r.objectives[s], r.reasons[s]);
  }
}

bool is_sweep_registered(const std::string& db_path, const std::string& sweep) {
  if (!std::filesystem::exists(db_path)) return false;
  return ResultsStore::open(db_path, ResultsStore::Mode::read_only).find_sweep(sweep).has_value();
}

}  // namespace

double calc_search_cpu_seconds(const JobKind& kind, const nlohmann::json& config) {
  const double estimate = kind.estimate_cost(config, nullptr).cost;
  return kind.name == "experiment" ? estimate * kSearchCpuSecondsPerJointSecond : estimate;
}

SearchRunSummary run_search(const SweepSpec& spec, const JobKind& kind, const RunOptions& options,
                            const ExpansionLimits& limits, const std::atomic<bool>& stop_requested) {
  const SpecSearch& search = *spec.search;
  search::SearchSettings settings = search.settings;
  settings.resumable = false;  // promotions rerun from scratch (see the header)
  settings.budget = search.budget;
  settings.rung_cost.assign(search.rungs.size(), 1.0);
  if (search.budget_unit == SpecSearch::BudgetUnit::cpu_seconds) {
    // Each rung's job at the first prior point (the axes change little of a job's cost; the
    // checkpoints, i.e. the rung, decide it).
    RandomStream stream = search::make_trial_stream(settings.seed, 0);
    const search::SearchPoint point = search::calc_random_point(settings.space, stream);
    for (std::size_t k = 0; k < search.rungs.size(); ++k) {
      settings.rung_cost[k] = calc_search_cpu_seconds(kind, expand_step(spec, kind.schema, point, k).config());
    }
  }
  // TPE's start-up: the spec's, or a quarter of the whole jobs to the last rung the budget buys
  // (the schedule's budget check, so that 25 % of a grid of 48 equal jobs is 12 jobs, start-up 3,
  // whichever way budget / cost rounds).
  settings.tpe.startup = search.tpe_startup != 0
                             ? search.tpe_startup
                             : search::calc_tpe_startup(search::calc_whole_jobs(settings.budget, settings.rung_cost.back()));
  adopt_stored_search(spec, options.db_path, settings);
  RunOptions round = options;
  round.rerun_unsuccessful = false;  // a failed or diverged trial is an outcome (+∞), not retried every round
  std::map<std::pair<std::size_t, std::size_t>, std::string> key_cache;
  SearchRunSummary summary;
  for (;;) {
    const Replay r = replay(spec, settings, kind.schema, options.db_path, key_cache);
    summary.steps = r.history.steps.size();
    summary.trials = r.history.trials.size();
    summary.spent = search::calc_spent(r.history);
    const std::size_t last = settings.rung_cost.size() - 1;
    summary.best.reset();
    for (std::size_t s = 0; s < r.objectives.size(); ++s) {
      if (r.history.steps[s].rung != last || !r.objectives[s]) continue;
      const double loss = r.history.losses[s];
      if (!summary.best || loss < (search.objective.lower_is_better ? *summary.best : -*summary.best)) {
        summary.best = r.objectives[s];
        summary.best_trial = r.history.steps[s].trial;
      }
    }
    if (summary.rounds > 0 || std::filesystem::exists(options.db_path)) record_search(spec, settings, r, options.db_path);
    // Every step's job may already be done under another sweep of the file (a random search
    // and a TPE search of the same seed share their first trials, and a job is its key): the
    // sweep is then registered by one round that runs nothing, so its search is recorded.
    const bool registered = summary.rounds > 0 || is_sweep_registered(options.db_path, spec.name);
    if (r.finished && r.history.losses.size() == r.history.steps.size() && registered) {
      summary.finished = true;
      return summary;
    }
    if (r.history.steps.size() == r.history.losses.size() && registered) return summary;  // nothing to run: cannot happen
    SweepSpec expanded = spec;
    expanded.search->decided.emplace();
    for (const search::SearchStep& step : r.history.steps) {
      expanded.search->decided->emplace_back(r.history.trials[step.trial].point, step.rung);
    }
    const ExpandedSweep sweep = expand_sweep(std::move(expanded), kind.schema, limits);
    summary.last = run_sweep(sweep, kind.executor, round, stop_requested);
    ++summary.rounds;
    if (summary.last.interrupted || !summary.last.write_error.empty() || summary.last.abandoned > 0 ||
        stop_requested.load()) {
      const Replay after = replay(spec, settings, kind.schema, options.db_path, key_cache);
      record_search(spec, settings, after, options.db_path);
      return summary;
    }
  }
}

}  // namespace armfarm
