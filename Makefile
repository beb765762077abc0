# Two commands on a fresh machine: `make run` and `make test`.
# make run   : install missing Debian packages, build, run the default sweep, print its table
# make test  : install what only the tests use (Chromium, as root), build and run the GoogleTest suites (SANITIZE=1 for ASan+UBSan)
# make test-slurm : run a sweep on a private one-node Slurm cluster (root; see tests/slurm)
# make bench : build and run the Google Benchmark programs (long; not part of test)

JOBS      ?= $(shell nproc)
SANITIZE  ?= 0
SPEC      ?= sweeps/quickstart.json
DB        ?= results.db

# CMAKE_ARGS: more configure options, e.g. -DARMFARM_WERROR=ON (.ci/run); read when BUILD_DIR is first configured.
CMAKE_ARGS ?=

ifeq ($(SANITIZE),1)
BUILD_DIR ?= build-sanitize
CMAKE_FLAGS = -DCMAKE_BUILD_TYPE=RelWithDebInfo -DARMFARM_SANITIZE=ON $(CMAKE_ARGS)
else
BUILD_DIR ?= build
CMAKE_FLAGS = -DCMAKE_BUILD_TYPE=Release $(CMAKE_ARGS)
endif

ARMFARM = $(BUILD_DIR)/runner/armfarm

# make test-sanitize-subset : the parser and store tests under ASan+UBSan (.ci/run): one binary,
# sanitize_subset_tests, whose source files tests/CMakeLists.txt lists. The first sanitizer
# report stops the test process with a non-zero status (UBSan through -fno-sanitize-recover).
SANITIZER_ENV = ASAN_OPTIONS=halt_on_error=1:detect_leaks=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
# make fuzz  : build the libFuzzer targets (clang) and run each for FUZZ_SECONDS (tests/fuzz/README.md)
FUZZ_SECONDS ?= 60
FUZZ_TARGETS ?= spec urdf dcg obj csv model_file

.PHONY: all deps deps-test configure build build-armfarm install run test test-sanitize-subset test-slurm bench fuzz fuzz-build clean

all: build

# deps: what make run needs; deps-test: and what only the test suites use (Chromium, as root).
deps:
	@bash .ci/install-deps

deps-test: deps
	@bash .ci/install-deps --tests

$(BUILD_DIR)/CMakeCache.txt: | deps
	cmake -S . -B $(BUILD_DIR) $(CMAKE_FLAGS)

configure: deps $(BUILD_DIR)/CMakeCache.txt

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

# What `make run` needs: the armfarm executable and its libraries, not the test suites.
build-armfarm: configure
	cmake --build $(BUILD_DIR) -j $(JOBS) --target armfarm

# make run: the quick-start sweep, its headline table (tracking on the training trajectory and on
# the held-out one, and held-out torque prediction), then where things are and what to try next.
run: build-armfarm
	$(ARMFARM) run $(SPEC) --db $(DB)
	$(ARMFARM) table $(DB) --cols tracking_nmse,heldout_tracking_nmse,heldout_test_nmse
	@printf '%s\n' "" "results: $(DB) (SQLite; every job's configuration, metrics and recorded series)" \
	  "next:    $(ARMFARM) table $(DB)                        # every table of the sweep" \
	  "         $(ARMFARM) report $(DB) --out report/         # HTML pages with tables and figures" \
	  "         $(ARMFARM) plot $(DB) metric-vs-param --metric tracking_nmse --param learning.lwpr.init_D --out plot.png" \
	  "PATH:    export PATH=\"$$PWD/$(BUILD_DIR)/runner:\$$PATH\"   (or: make install PREFIX=\$$HOME/.local)"

# make install PREFIX=DIR : the armfarm executable, the engine and store libraries and the models.
PREFIX ?= /usr/local
install: build-armfarm
	cmake --install $(BUILD_DIR) --prefix $(PREFIX)

test: deps-test build
	cd $(BUILD_DIR) && $(if $(filter 1,$(SANITIZE)),$(SANITIZER_ENV)) ctest --output-on-failure -j $(JOBS)

# A private one-node Slurm on this machine (root; installs slurm-wlm and munge if missing).
test-slurm: build
	bash tests/slurm/run_slurm_test.sh $(ARMFARM)

bench: deps
	cmake -S . -B build-bench -DCMAKE_BUILD_TYPE=Release -DARMFARM_BUILD_BENCH=ON
	cmake --build build-bench -j $(JOBS)
	@for b in build-bench/tests/bench/bench_*; do echo "== $$b"; $$b || exit 1; done

# Built at -O1 with line tables only (-g1): ASan's and UBSan's reports keep file:line, and one
# compile costs half the CPU of -O2 -g (engine/control/step_stability.cpp with the sanitizers,
# g++ 12: 72 s user at -O2 -g, 38 s at -O1 -g1, on a shared 2-core machine).
SANITIZE_SUBSET_FLAGS = -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG"
test-sanitize-subset: deps
	cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DARMFARM_SANITIZE=ON $(SANITIZE_SUBSET_FLAGS) $(CMAKE_ARGS)
	cmake --build build-sanitize -j $(JOBS) --target sanitize_subset_tests
	cd build-sanitize/tests && $(SANITIZER_ENV) ./sanitize_subset_tests --gtest_brief=1

# `make -j2 fuzz` runs two targets at a time; each target's output goes to build-fuzz/logs/<target>.log
# and its final libFuzzer statistics are printed when it ends.
fuzz: $(addprefix fuzz-run-,$(FUZZ_TARGETS))

fuzz-build: deps
	@command -v clang++ >/dev/null || { echo "armfarm: make fuzz needs clang and libFuzzer: apt-get install -y clang libclang-rt-dev" >&2; exit 1; }
	cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
	  -DARMFARM_FUZZ=ON -DARMFARM_BUILD_TESTS=OFF
	cmake --build build-fuzz -j $(JOBS) --target $(addprefix fuzz_,$(FUZZ_TARGETS))

fuzz-run-%: fuzz-build
	@mkdir -p build-fuzz/corpus/$* build-fuzz/crashes build-fuzz/logs
	@echo "== fuzz_$* for $(FUZZ_SECONDS) s (log: build-fuzz/logs/$*.log)"
	@build-fuzz/tests/fuzz/fuzz_$* -max_total_time=$(FUZZ_SECONDS) -max_len=65536 -rss_limit_mb=2048 -timeout=10 \
	  -print_final_stats=1 -artifact_prefix=build-fuzz/crashes/$*- build-fuzz/corpus/$* tests/data/fuzz/$* \
	  > build-fuzz/logs/$*.log 2>&1; status=$$?; \
	  echo "== fuzz_$* exit $$status: $$(ls build-fuzz/corpus/$* | wc -l) files in build-fuzz/corpus/$*"; \
	  grep -E '^(stat::|#[0-9]+[[:space:]]+DONE|INFO: (seed corpus|-max_total_time)|Done |==[0-9]+==|SUMMARY|artifact_prefix|Test unit written)' build-fuzz/logs/$*.log \
	    | sed 's/^/fuzz_$*: /'; \
	  exit $$status

clean:
	rm -rf build build-sanitize build-bench build-fuzz
