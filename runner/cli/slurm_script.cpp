#include "runner/cli/slurm_script.hpp"

#include "analysis/printable_text.hpp"
#include "base/number_format.hpp"
#include "runner/cli/subcommand.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace armfarm::cli {

namespace {

/// "armfarm-<sweep>" with anything but [A-Za-z0-9_.-] replaced by '_' (a Slurm job name).
std::string make_job_name(const std::string& sweep) {
  std::string name = "armfarm-";
  for (const char c : sweep) {
    name += (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.') ? c : '_';
  }
  return name;
}

/// "#SBATCH --<option>=<value quoted>" when `value` is not empty.
void write_directive(std::ostream& out, const std::string& option, const std::string& value) {
  if (!value.empty()) out << "#SBATCH --" << option << "=" << make_sbatch_quoted("--" + option, value) << "\n";
}

/// The #SBATCH lines both scripts share: limits, the site's accounting, the user's own options.
void write_common_directives(std::ostream& out, const SlurmPlan& plan) {
  if (!plan.time_limit.empty()) out << "#SBATCH --time=" << plan.time_limit << "\n";
  if (!plan.partition.empty()) out << "#SBATCH --partition=" << plan.partition << "\n";
  write_directive(out, "account", plan.account);
  write_directive(out, "qos", plan.qos);
  write_directive(out, "mem", plan.mem);
  write_directive(out, "mem-per-cpu", plan.mem_per_cpu);
  for (const std::string& arg : plan.sbatch_args) out << "#SBATCH " << make_sbatch_quoted("--sbatch-arg", arg) << "\n";
}

/// The setup lines (`--setup FILE`), sourced before anything else runs; a setup that fails
/// fails the script before armfarm starts.
void write_setup(std::ostream& out, const SlurmPlan& plan) {
  if (plan.setup.empty()) return;
  out << "# Site setup (--setup): module loads, environments.\n"
      << "source " << make_shell_quoted(plan.setup) << " || { echo \"armfarm slurm: the setup file failed: \"" << make_shell_quoted(plan.setup)
      << " >&2; exit 2; }\n";
}

/// The array's task indices (shard - 1): "0-N" for every shard, else ranges of the listed ones.
std::string make_array_indices(const SlurmPlan& plan) {
  if (plan.shards.empty()) return "0-" + std::to_string(plan.tasks - 1);
  std::vector<int> indices;
  for (const int shard : plan.shards) indices.push_back(shard - 1);
  std::sort(indices.begin(), indices.end());
  indices.erase(std::unique(indices.begin(), indices.end()), indices.end());
  std::string text;
  for (std::size_t i = 0; i < indices.size();) {
    std::size_t j = i;
    while (j + 1 < indices.size() && indices[j + 1] == indices[j] + 1) ++j;
    if (!text.empty()) text += ",";
    text += std::to_string(indices[i]);
    if (j > i) text += "-" + std::to_string(indices[j]);
    i = j + 1;
  }
  return text;
}

/// A decimal field of a time limit: digits only, non-empty.
bool read_time_field(const std::string& text, long& value) {
  if (text.empty() || text.size() > 9) return false;
  for (const char c : text) {
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
  }
  value = std::stol(text);
  return true;
}

/// A user string for a comment line: one line, nothing a terminal or an editor acts on.
std::string make_comment_text(const std::string& text) { return make_printable_text(text); }

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t end = text.find(separator, start);
    parts.push_back(text.substr(start, end == std::string::npos ? std::string::npos : end - start));
    if (end == std::string::npos) return parts;
    start = end + 1;
  }
}

}  // namespace

std::string make_shard_db_path(const std::string& db, int shard) { return db + ".shard-" + std::to_string(shard) + ".db"; }
std::string make_shard_saved_path(const std::string& db, int shard) { return db + ".shard-" + std::to_string(shard) + ".saved"; }
std::string make_array_script_path(const std::string& db) { return db + ".array.sbatch"; }
std::string make_merge_script_path(const std::string& db) { return db + ".merge.sbatch"; }

std::string make_shell_quoted(const std::string& text) {
  std::string quoted = "'";
  for (const char c : text) {
    if (c == '\'') {
      quoted += "'\\''";
    } else {
      quoted += c;
    }
  }
  return quoted + "'";
}

std::string make_sbatch_quoted(const std::string& option, const std::string& text) {
  std::string quoted = "'";
  for (const char c : text) {
    if (std::iscntrl(static_cast<unsigned char>(c))) {
      throw std::invalid_argument(option + " " + make_printable_text(text) + ": control characters (a newline, a tab) cannot go in an #SBATCH line");
    }
    if (c == '\'' || c == '\\') quoted += '\\';
    quoted += c;
  }
  return quoted + "'";
}

void check_slurm_memory(const std::string& option, const std::string& text) {
  std::size_t digits = 0;
  while (digits < text.size() && std::isdigit(static_cast<unsigned char>(text[digits]))) ++digits;
  const std::string unit = text.substr(digits);
  const bool unit_ok = unit.empty() || (unit.size() == 1 && std::string("KMGTkmgt").find(unit[0]) != std::string::npos);
  if (digits == 0 || digits > 12 || !unit_ok) {
    throw std::invalid_argument(option + " " + make_printable_text(text) + ": expected a size such as 4000, 500M, 4G or 1T");
  }
}

void check_sbatch_arg(const std::string& text) {
  if (text.size() < 2 || text[0] != '-') {
    throw std::invalid_argument("--sbatch-arg " + make_printable_text(text) + ": expected one sbatch option, such as --mail-type=END");
  }
  for (const char* own : {"--array", "--dependency", "--output", "--job-name", "-a", "-d", "-o", "-J"}) {
    const std::string name(own);
    if (text == name || text.rfind(name + "=", 0) == 0 || (name.size() == 2 && text.rfind(name, 0) == 0)) {
      throw std::invalid_argument("--sbatch-arg " + make_printable_text(text) + ": armfarm slurm writes " + name + " itself");
    }
  }
  make_sbatch_quoted("--sbatch-arg", text);
}

std::string make_array_script(const SlurmPlan& plan) {
  std::ostringstream out;
  out << "#!/bin/bash\n"
      << "# Sweep " << make_comment_text(plan.sweep) << " (" << plan.jobs << " jobs) as a Slurm job array of " << plan.tasks
      << " tasks, written by `armfarm slurm`.\n"
      << "# Task I (SLURM_ARRAY_TASK_ID + 1) runs shard I/" << plan.tasks
      << " into its own database file; a merge job combines them.\n"
      << "# Submitting again runs only what is missing: each shard resumes from its file.\n"
      << "#SBATCH --job-name=" << make_job_name(plan.sweep) << "\n"
      << "#SBATCH --array=" << make_array_indices(plan);
  if (plan.array_throttle > 0) out << "%" << plan.array_throttle;
  out << "\n"
      << "#SBATCH --ntasks=1\n"
      << "#SBATCH --cpus-per-task=" << plan.cpus_per_task << "\n";
  write_common_directives(out, plan);
  write_directive(out, "gres", plan.gres);
  write_directive(out, "constraint", plan.constraint);
  out << "#SBATCH --signal=B:USR1@" << plan.signal_before << "\n";
  if (plan.requeue) out << "#SBATCH --requeue\n#SBATCH --open-mode=append\n";
  out << "#SBATCH --output=" << plan.db << ".slurm-%A_%a.log\n";
  write_setup(out, plan);
  out << "set -u\n"
      << "cd " << make_shell_quoted(plan.work_dir) << " || exit 2\n"
      << "count=" << plan.tasks << "\n"
      << "shard=$((SLURM_ARRAY_TASK_ID + 1))\n"
      << "db=" << make_shell_quoted(plan.db) << ".shard-\"$shard\".db\n"
      << "saved=" << make_shell_quoted(plan.db) << ".shard-\"$shard\".saved\n"
      << "rm -f -- \"$saved\"\n"
      << "echo \"armfarm slurm: shard $shard/$count on $(hostname) into $db at $(date -u +%T)\"\n"
      << "# Slurm's warning (--signal=B:USR1@" << plan.signal_before << ": a time limit or preemption ahead) goes to this\n"
      << "# shell; it is passed on to armfarm, which stops taking jobs, lets the running ones it expects to end\n"
      << "# within " << calc_stop_grace(plan.signal_before) << " s finish (--stop-grace), stops the others (they stay pending) and saves.\n"
      << "signalled=0\n"
      << "pid=\n"
      << "trap 'signalled=1; [ -n \"$pid\" ] && kill -USR1 \"$pid\" 2>/dev/null' USR1\n"
      << make_shell_quoted(plan.armfarm) << " run " << make_shell_quoted(plan.spec)
      << " --shard \"$shard/$count\" --db \"$db\" -j \"${SLURM_CPUS_PER_TASK:-" << plan.cpus_per_task << "}\""
      << " --stop-grace " << calc_stop_grace(plan.signal_before);
  if (plan.job_timeout > 0) out << " --timeout " << format_shortest_number(plan.job_timeout);
  if (!plan.retry_failed) out << " --keep-failed";
  out << " &\n"
      << "pid=$!\n"
      << "wait \"$pid\"\n"
      << "status=$?\n"
      << "# A trapped signal ends `wait` early: wait again until armfarm has exited.\n"
      << "while kill -0 \"$pid\" 2>/dev/null; do wait \"$pid\"; status=$?; done\n"
      << "if [ \"$signalled\" -eq 1 ] && [ \"$status\" -ne 0 ]; then\n"
      << "  echo \"armfarm slurm: shard $shard/$count stopped by Slurm's warning signal (armfarm run exit $status) at $(date -u +%T); its finished jobs are saved\"\n";
  if (plan.requeue) {
    out << "  # Requeued, the task resumes its shard file: what finished is not run again.\n"
        << "  # At most " << plan.max_requeues << " restarts (--max-requeues): a job too long for the time limit does not loop.\n"
        << "  if [ \"${SLURM_RESTART_COUNT:-0}\" -lt " << plan.max_requeues << " ]; then\n"
        << "    scontrol requeue \"${SLURM_ARRAY_JOB_ID}_${SLURM_ARRAY_TASK_ID}\" && { echo \"armfarm slurm: shard $shard/$count requeued\"; exit 0; }\n"
        << "  else\n"
        << "    echo \"armfarm slurm: shard $shard/$count restarted ${SLURM_RESTART_COUNT} times (--max-requeues " << plan.max_requeues
        << "): a job may not fit in the time limit\" >&2\n"
        << "  fi\n";
  }
  out << "  echo \"armfarm slurm: shard $shard/$count not requeued: not marked saved, submit again to finish it\" >&2\n"
      << "  exit 75\n"
      << "fi\n"
      << "# 0: every job done and saved. 1: every job ran and its outcome is saved, some failed, diverged\n"
      << "# or timed out; those are results too: the merge brings them in"
      << (plan.retry_failed ? " (--retry-failed: a resubmission runs them again).\n"
                            : " and a resubmission keeps them (armfarm slurm --retry-failed runs them again).\n")
      << "# Anything else (" << kExitResultsNotSaved << ": finished jobs not saved, a full disk; 2: bad input) fails the task.\n"
      << "if [ \"$status\" -ne 0 ] && [ \"$status\" -ne 1 ]; then\n"
      << "  echo \"armfarm slurm: shard $shard/$count failed (armfarm run exit $status): not marked saved, the merge leaves it out\" >&2\n"
      << "  exit \"$status\"\n"
      << "fi\n"
      << "if [ \"$status\" -eq 1 ]; then\n"
      << "  echo \"armfarm slurm: shard $shard/$count recorded failed, diverged or timed-out jobs (armfarm status $db)\"\n"
      << "fi\n"
      << ": > \"$saved\" || exit 2\n"
      << "exit 0\n";
  return out.str();
}

std::string make_merge_script(const SlurmPlan& plan) {
  std::ostringstream out;
  out << "#!/bin/bash\n"
      << "# Merges the " << plan.tasks << " shard databases of sweep " << make_comment_text(plan.sweep) << " into "
      << make_comment_text(plan.db)
      << ", written by `armfarm slurm`.\n"
      << "# Submitted with --dependency=afterany:<array job>: it runs however the tasks ended, merges the\n"
      << "# shards that saved their results and names the others; merging again is harmless.\n"
      << "#SBATCH --job-name=" << make_job_name(plan.sweep) << "-merge\n"
      << "#SBATCH --ntasks=1\n"
      << "#SBATCH --cpus-per-task=1\n"
      << "#SBATCH --kill-on-invalid-dep=yes\n";
  write_common_directives(out, plan);
  out << "#SBATCH --output=" << plan.db << ".slurm-%j-merge.log\n";
  write_setup(out, plan);
  out << "set -u\n"
      << "cd " << make_shell_quoted(plan.work_dir) << " || exit 2\n"
      << "db=" << make_shell_quoted(plan.db) << "\n"
      << "# Only shards whose task saved every outcome are merged; the others are named.\n"
      << "saved=()\n"
      << "missing=()\n"
      << "for shard in $(seq 1 " << plan.tasks << "); do\n"
      << "  if [ -e \"$db.shard-$shard.saved\" ]; then saved+=(\"$db.shard-$shard.db\"); else missing+=(\"$shard\"); fi\n"
      << "done\n"
      << "if [ ${#saved[@]} -gt 0 ]; then\n"
      << "  " << make_shell_quoted(plan.armfarm) << " merge \"$db\" \"${saved[@]}\" || exit $?\n"
      << "fi\n"
      << "if [ ${#missing[@]} -gt 0 ]; then\n"
      << "  shown=\"${missing[*]:0:10}\"\n"
      << "  [ ${#missing[@]} -gt 10 ] && shown=\"$shown ... and $((${#missing[@]} - 10)) more\"\n"
      << "  # The jobs not finished in the merged database, by shard.\n"
      << "  " << make_shell_quoted(plan.armfarm) << " slurm " << make_shell_quoted(plan.spec) << " --db \"$db\" --tasks " << plan.tasks
      << (plan.retry_failed ? " --retry-failed" : "") << " --missing\n"
      << "  echo \"armfarm slurm: merged ${#saved[@]} of " << plan.tasks << " shards; ${#missing[@]} did not save their results "
      << "(shard $shown; see $db.slurm-*.log): run the same armfarm slurm command again to submit only those, then a merge\" >&2\n"
      << "fi\n"
      << "[ -e \"$db\" ] && " << make_shell_quoted(plan.armfarm) << " status \"$db\"\n"
      << "[ ${#missing[@]} -eq 0 ] || exit 1\n"
      << "exit 0\n";
  return out.str();
}

std::vector<std::string> make_submit_commands(const SlurmPlan& plan) {
  return {
      "array=$(sbatch --parsable " + make_shell_quoted(make_array_script_path(plan.db)) + ")",
      "sbatch --parsable --dependency=afterany:${array%%;*} " + make_shell_quoted(make_merge_script_path(plan.db)),
  };
}

void check_slurm_time_limit(const std::string& text) {
  const auto fail = [&text](const std::string& why) {
    throw std::invalid_argument("--time " + text + ": " + why);
  };
  std::string lower;
  for (const char c : text) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (lower == "infinite" || lower == "unlimited") return;
  const std::string expected = "expected minutes, M:S, H:M:S, D-H, D-H:M or D-H:M:S (e.g. 90, 2:00:00, 1-12)";
  std::string clock = text;
  bool has_days = false;
  const std::size_t dash = text.find('-');
  if (dash != std::string::npos) {
    long days = 0;
    if (!read_time_field(text.substr(0, dash), days)) fail(expected);
    clock = text.substr(dash + 1);
    has_days = true;
  }
  const std::vector<std::string> fields = split(clock, ':');
  if (fields.size() > 3) fail(expected);
  std::vector<long> values(fields.size());
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (!read_time_field(fields[i], values[i])) fail(expected);
  }
  // With days the first field is hours (D-H, D-H:M, D-H:M:S); without, M, M:S or H:M:S.
  if (has_days) {
    if (values[0] >= 24) fail("hours after a day must be below 24");
    for (std::size_t i = 1; i < values.size(); ++i) {
      if (values[i] >= 60) fail("minutes and seconds must be below 60");
    }
  } else if (values.size() == 2) {
    if (values[1] >= 60) fail("seconds must be below 60");
  } else if (values.size() == 3) {
    if (values[1] >= 60 || values[2] >= 60) fail("minutes and seconds must be below 60");
  }
}

std::optional<long> calc_slurm_time_seconds(const std::string& text) {
  std::string lower;
  for (const char c : text) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (lower == "infinite" || lower == "unlimited") return std::nullopt;
  long days = 0;
  std::string clock = text;
  const std::size_t dash = text.find('-');
  if (dash != std::string::npos) {
    days = std::stol(text.substr(0, dash));
    clock = text.substr(dash + 1);
  }
  std::vector<long> fields;
  for (const std::string& field : split(clock, ':')) fields.push_back(std::stol(field));
  long seconds = 0;
  if (dash != std::string::npos) {  // D-H, D-H:M, D-H:M:S
    const long scale[] = {3600, 60, 1};
    for (std::size_t i = 0; i < fields.size(); ++i) seconds += fields[i] * scale[i];
  } else if (fields.size() == 1) {  // M
    seconds = fields[0] * 60;
  } else if (fields.size() == 2) {  // M:S
    seconds = fields[0] * 60 + fields[1];
  } else {  // H:M:S
    seconds = fields[0] * 3600 + fields[1] * 60 + fields[2];
  }
  return days * 86400 + seconds;
}

int calc_stop_grace(int signal_before) { return std::max(0, signal_before - std::max(5, signal_before / 10)); }

int choose_signal_before(const std::vector<double>& job_seconds, const std::string& time_limit) {
  double longest = 0.0;
  for (const double seconds : job_seconds) longest = std::max(longest, seconds);
  // T - max(5, T / 10) >= 1.5 × longest: T = 1.5 × longest + 5 while that is below 50, else (1.5 × longest) / 0.9.
  const double room = 1.5 * longest;
  double chosen = room + 5.0 <= 50.0 ? room + 5.0 : room / 0.9;
  chosen = std::min(65535.0, std::max(60.0, std::ceil(chosen)));
  if (!time_limit.empty()) {
    const std::optional<long> limit = calc_slurm_time_seconds(time_limit);
    if (limit) chosen = std::min(chosen, static_cast<double>(*limit / 2));
  }
  return std::max(1, static_cast<int>(chosen));
}

void check_slurm_partition(const std::string& text) {
  for (const std::string& name : split(text, ',')) {
    if (name.empty()) throw std::invalid_argument("--partition " + text + ": empty partition name");
    for (const char c : name) {
      if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.')) {
        throw std::invalid_argument("--partition " + text + ": partition names hold letters, digits, '_', '-' and '.'");
      }
    }
  }
}

void check_slurm_db_path(const std::string& path) {
  for (const char c : path) {
    if (std::isspace(static_cast<unsigned char>(c)) || std::iscntrl(static_cast<unsigned char>(c)) || c == '\'' ||
        c == '"' || c == '\\' || c == '%') {
      throw std::invalid_argument(path + ": a database path for Slurm may not hold white space, quotes, '\\' or '%' "
                                         "(they name the shard files and logs in sbatch directives)");
    }
  }
}

}  // namespace armfarm::cli
