#pragma once
// The check readers run before they read a database (`status`, `table`, `compare`, `report`,
// `plot`, `export`).
#include "results/results_store.hpp"

namespace armfarm {

/// SQLite's quick_check, then ResultsStore::check_contents without integrity_check (dangling
/// rows, unknown status values, storage classes, every series blob and its checksum): linear in
/// the file's size, as quick_check already is. Throws StoreError "<path>: damaged armfarm
/// database: <first problem> (armfarm status --check <path> lists every problem)".
void verify_readable(const ResultsStore& store);

}  // namespace armfarm
