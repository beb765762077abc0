#include "runner/cli/slurm_script.hpp"

#include "analysis/printable_text.hpp"
#include "runner/cli/subcommand.hpp"

#include <cctype>
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

/// The #SBATCH lines both scripts share.
void write_common_directives(std::ostream& out, const SlurmPlan& plan) {
  if (!plan.time_limit.empty()) out << "#SBATCH --time=" << plan.time_limit << "\n";
  if (!plan.partition.empty()) out << "#SBATCH --partition=" << plan.partition << "\n";
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

std::string make_array_script(const SlurmPlan& plan) {
  std::ostringstream out;
  out << "#!/bin/bash\n"
      << "# Sweep " << make_comment_text(plan.sweep) << " (" << plan.jobs << " jobs) as a Slurm job array of " << plan.tasks
      << " tasks, written by `armfarm slurm`.\n"
      << "# Task I (SLURM_ARRAY_TASK_ID + 1) runs shard I/" << plan.tasks
      << " into its own database file; a merge job combines them.\n"
      << "# Submitting again runs only what is missing: each shard resumes from its file.\n"
      << "#SBATCH --job-name=" << make_job_name(plan.sweep) << "\n"
      << "#SBATCH --array=0-" << plan.tasks - 1 << "\n"
      << "#SBATCH --ntasks=1\n"
      << "#SBATCH --cpus-per-task=" << plan.cpus_per_task << "\n";
  write_common_directives(out, plan);
  out << "#SBATCH --output=" << plan.db << ".slurm-%A_%a.log\n"
      << "set -u\n"
      << "cd " << make_shell_quoted(plan.work_dir) << " || exit 2\n"
      << "count=" << plan.tasks << "\n"
      << "shard=$((SLURM_ARRAY_TASK_ID + 1))\n"
      << "db=" << make_shell_quoted(plan.db) << ".shard-\"$shard\".db\n"
      << "saved=" << make_shell_quoted(plan.db) << ".shard-\"$shard\".saved\n"
      << "rm -f -- \"$saved\"\n"
      << "echo \"armfarm slurm: shard $shard/$count on $(hostname) into $db\"\n"
      << make_shell_quoted(plan.armfarm) << " run " << make_shell_quoted(plan.spec)
      << " --shard \"$shard/$count\" --db \"$db\" -j \"${SLURM_CPUS_PER_TASK:-" << plan.cpus_per_task << "}\"\n"
      << "status=$?\n"
      << "# 0: every job done and saved. 1: every job ran and its outcome is saved, some failed, diverged\n"
      << "# or timed out; those are results too: the merge brings them in (a resubmission runs them again).\n"
      << "# Anything else (" << kExitResultsNotSaved << ": finished jobs not saved, a full disk; 2: bad input) fails the task.\n"
      << "if [ \"$status\" -ne 0 ] && [ \"$status\" -ne 1 ]; then\n"
      << "  echo \"armfarm slurm: shard $shard/$count failed (armfarm run exit $status): not marked saved, the merge will not run\" >&2\n"
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
      << "# Submitted with --dependency=afterok:<array job>; merging again is harmless (identical jobs stay).\n"
      << "#SBATCH --job-name=" << make_job_name(plan.sweep) << "-merge\n"
      << "#SBATCH --ntasks=1\n"
      << "#SBATCH --cpus-per-task=1\n"
      << "#SBATCH --kill-on-invalid-dep=yes\n";
  write_common_directives(out, plan);
  out << "#SBATCH --output=" << plan.db << ".slurm-%j-merge.log\n"
      << "set -u\n"
      << "cd " << make_shell_quoted(plan.work_dir) << " || exit 2\n"
      << "db=" << make_shell_quoted(plan.db) << "\n"
      << "# Only shards whose task saved every outcome are merged; otherwise say which are missing.\n"
      << "missing=()\n"
      << "for shard in $(seq 1 " << plan.tasks << "); do\n"
      << "  [ -e \"$db.shard-$shard.saved\" ] || missing+=(\"$shard\")\n"
      << "done\n"
      << "if [ ${#missing[@]} -gt 0 ]; then\n"
      << "  shown=\"${missing[*]:0:10}\"\n"
      << "  [ ${#missing[@]} -gt 10 ] && shown=\"$shown ... and $((${#missing[@]} - 10)) more\"\n"
      << "  echo \"armfarm slurm: not merging: ${#missing[@]} of " << plan.tasks
      << " shards did not save their results (shard $shown); see $db.slurm-*.log and submit again\" >&2\n"
      << "  exit 1\n"
      << "fi\n"
      << make_shell_quoted(plan.armfarm) << " merge \"$db\"";
  for (int shard = 1; shard <= plan.tasks; ++shard) out << " \"$db.shard-" << shard << ".db\"";
  out << " || exit $?\n"
      << make_shell_quoted(plan.armfarm) << " status \"$db\"\n"
      << "exit 0\n";
  return out.str();
}

std::vector<std::string> make_submit_commands(const SlurmPlan& plan) {
  return {
      "array=$(sbatch --parsable " + make_shell_quoted(make_array_script_path(plan.db)) + ")",
      "sbatch --parsable --dependency=afterok:${array%%;*} " + make_shell_quoted(make_merge_script_path(plan.db)),
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
