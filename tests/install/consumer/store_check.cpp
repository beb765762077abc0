// armfarm::results from the installed package: creates a results database and reads it back.
#include "results/results_store.hpp"

#include <cstdio>

int main(int argc, char** argv) {
  if (argc != 2) return std::fprintf(stderr, "usage: store_check NEW.db\n"), 2;
  armfarm::ResultsStore::open(argv[1], armfarm::ResultsStore::Mode::read_write);
  const armfarm::ResultsStore store = armfarm::ResultsStore::open(argv[1], armfarm::ResultsStore::Mode::read_only);
  std::printf("%s: schema %d, %zu sweeps\n", argv[1], store.schema_version(), store.find_sweeps().size());
  return store.schema_version() == armfarm::kResultsSchemaVersion && store.find_sweeps().empty() ? 0 : 1;
}
