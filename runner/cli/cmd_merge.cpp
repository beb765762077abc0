// `armfarm merge OUT.db IN.db...`: combines shard databases (or any results databases) into
// OUT. A job present in several files must have the same results there; conflicts are reported
// (exit 1) and OUT keeps its own row. The merge is written to a temporary file beside OUT
// (a copy of OUT when it exists) and renamed into place once complete, so a merge cut short
// leaves OUT as it was, never a part of the result that looks whole. The file is fsynced before
// the rename and the folder after it, so a power loss leaves one or the other.
#include "analysis/printable_text.hpp"
#include "results/results_store.hpp"
#include "runner/cli/subcommand.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <memory>

namespace armfarm::cli {
namespace {

// fsync of a file or folder: false (errno set) when it cannot be opened or synced.
bool sync_path(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool synced = ::fsync(fd) == 0;
  ::close(fd);
  return synced;
}

}  // namespace

RunFunction setup_merge(CLI::App& parent) {
  struct Options {
    std::string out;
    std::vector<std::string> inputs;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand("merge", "Merge results databases (e.g. the shards of a sweep) into one");
  app->add_option("out", options->out, "Database to merge into (created if absent)")->required();
  app->add_option("inputs", options->inputs, "Databases to merge from")->required();

  return [options] {
    for (const std::string& input : options->inputs) {
      if (!std::filesystem::exists(input)) {
        std::cerr << "armfarm: " << input << ": no such database file\n";
        return 2;
      }
      if (std::filesystem::exists(options->out) && std::filesystem::equivalent(input, options->out)) {
        std::cerr << "armfarm: " << input << ": cannot merge a database into itself\n";
        return 2;
      }
    }
    // Every input is verified before the output is opened (or created): a damaged input leaves
    // the output as it was.
    for (const std::string& input : options->inputs) ResultsStore::verify_file(input);
    const std::string temporary = options->out + ".merging-" + std::to_string(::getpid());
    struct RemoveUnlessRenamed {
      std::string path;
      bool renamed = false;
      ~RemoveUnlessRenamed() {
        std::error_code ignored;
        if (!renamed) std::filesystem::remove(path, ignored);
        for (const char* suffix : {"-wal", "-shm", "-journal"}) std::filesystem::remove(path + suffix, ignored);
      }
    } cleanup{temporary};
    std::filesystem::remove(temporary);
    if (std::filesystem::exists(options->out)) {
      // Opened writable and closed once: a WAL left by a crash is folded into the file first.
      ResultsStore::open(options->out, ResultsStore::Mode::read_write).copy_to(temporary);
      if (std::filesystem::exists(options->out + "-wal")) {
        std::cerr << "armfarm: " << options->out << ": in use by another process (its -wal file is open); merge when it is done\n";
        return 2;
      }
    }
    int conflicts = 0;
    {
      ResultsStore store = ResultsStore::open(temporary, ResultsStore::Mode::read_write);
      for (const std::string& input : options->inputs) {
        const MergeReport report = store.merge_from(input);
        std::cout << input << ": " << report.jobs_added << " jobs added, " << report.jobs_replaced
                  << " unfinished jobs completed, " << report.jobs_identical << " identical, " << report.conflicts.size()
                  << " conflicts\n";
        // A conflict quotes names and values of the files: printed as text, not as escapes.
        for (const std::string& conflict : report.conflicts) {
          std::cout << "  conflict: " << make_printable_text(conflict) << "\n";
        }
        conflicts += static_cast<int>(report.conflicts.size());
      }
    }  // closed: the last connection checkpoints its WAL into the file
    // The merged file reaches the disk before its name replaces OUT, and the rename itself
    // (the folder's entry) after: a power loss leaves the old OUT or the whole new one.
    if (!sync_path(temporary)) {
      std::cerr << "armfarm: " << temporary << ": cannot sync the merged file to disk: " << std::strerror(errno)
                << "; " << options->out << " left as it was\n";
      return 2;
    }
    std::filesystem::rename(temporary, options->out);
    cleanup.renamed = true;
    const std::filesystem::path folder = std::filesystem::absolute(options->out).parent_path();
    if (!sync_path(folder.string())) {
      std::cerr << "armfarm: " << folder.string() << ": cannot sync the folder after renaming " << options->out
                << " into place: " << std::strerror(errno) << "\n";
      return 2;
    }
    return conflicts > 0 ? 1 : 0;
  };
}

}  // namespace armfarm::cli
