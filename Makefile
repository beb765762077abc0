# Two commands on a fresh machine: `make run` and `make test`.
# make run   : install missing Debian packages, build, run the default sweep, print its table
# make test  : build and run the GoogleTest suites (SANITIZE=1 for ASan+UBSan)
# make test-slurm : run a sweep on a private one-node Slurm cluster (root; see tests/slurm)
# make bench : build and run the Google Benchmark programs (long; not part of test)

JOBS      ?= $(shell nproc)
SANITIZE  ?= 0
SPEC      ?= sweeps/quickstart.json
DB        ?= results.db

ifeq ($(SANITIZE),1)
BUILD_DIR ?= build-sanitize
CMAKE_FLAGS = -DCMAKE_BUILD_TYPE=RelWithDebInfo -DARMFARM_SANITIZE=ON
else
BUILD_DIR ?= build
CMAKE_FLAGS = -DCMAKE_BUILD_TYPE=Release
endif

ARMFARM = $(BUILD_DIR)/runner/armfarm

.PHONY: all deps configure build run test test-slurm bench clean

all: build

deps:
	@bash .ci/install-deps

$(BUILD_DIR)/CMakeCache.txt: | deps
	cmake -S . -B $(BUILD_DIR) $(CMAKE_FLAGS)

configure: deps $(BUILD_DIR)/CMakeCache.txt

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

run: build
	$(ARMFARM) run $(SPEC) --db $(DB)
	$(ARMFARM) table $(DB)

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

# A private one-node Slurm on this machine (root; installs slurm-wlm and munge if missing).
test-slurm: build
	bash tests/slurm/run_slurm_test.sh $(ARMFARM)

bench: deps
	cmake -S . -B build-bench -DCMAKE_BUILD_TYPE=Release -DARMFARM_BUILD_BENCH=ON
	cmake --build build-bench -j $(JOBS)
	@for b in build-bench/tests/bench/bench_*; do echo "== $$b"; $$b || exit 1; done

clean:
	rm -rf build build-sanitize build-bench
