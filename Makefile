# Thin wrapper over CMake and the Python analysis. Quick start: `make reproduce`, `make test`.
PYTHON := .venv/bin/python
CMAKE_FLAGS := -G Ninja -DCMAKE_BUILD_TYPE=Release

.PHONY: setup build build-cli build-tests build-asan build-fuzz test test-cpp test-asan \
        test-asan-core test-python test-browser reproduce reproduce-full bench bench-naive history gates \
        baseline examples python-package fuzz fuzz-smoke lint format clean meshes bunny-box \
        docs-check
JOBS := $(shell nproc)
CONFIGURE := cmake -S . -B build $(CMAKE_FLAGS) >/dev/null

setup:
	@bash scripts/setup.sh

# Everything: the engine, the CLI, the tests, the examples' kernel and the benchmarks.
build: setup
	@$(CONFIGURE)
	@cmake --build build

# Only what a target runs: the CLI (reproduce, the Python tests), or the CLI with the
# C++ tests (test-cpp).
build-cli: setup
	@$(CONFIGURE)
	@cmake --build build --target hrbench

build-tests: setup
	@$(CONFIGURE)
	@cmake --build build --target hrbench_core_tests hrbench_tests

# AddressSanitizer and UndefinedBehaviorSanitizer, with assertions on; -Og and line
# tables only: it builds in a third of -O1's time (the kernel's file: 36 s against 105 s)
# and still names file and line.
# `make test` builds the core tests only (ASAN_TARGETS), `make test-asan` everything.
ASAN_TARGETS :=
build-asan: setup
	@cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Debug "-DCMAKE_CXX_FLAGS_DEBUG=-Og -g1" \
	  -DHRBENCH_SANITIZE=ON -DHRBENCH_BUILD_BENCH=OFF >/dev/null
	@cmake --build build-asan $(if $(ASAN_TARGETS),--target $(ASAN_TARGETS))

# CTest runs each Catch2 case as its own test, JOBS at a time, and prints each as it ends.
test-cpp: build-tests
	ctest --test-dir build -j $(JOBS) --output-on-failure

# The sanitizer build on the cases of the input parsers and the refinement kernel (the
# CTest label `core`); `test-asan` on every case (CI runs both).
test-asan-core: ASAN_TARGETS := hrbench_core_tests
test-asan-core: build-asan
	ctest --test-dir build-asan -L core -j $(JOBS) --output-on-failure

# ASAN_CTEST adds ctest flags: CI, having run the core cases in `make test`, passes
# `-LE core` so that `test-asan` runs each remaining case once.
ASAN_CTEST :=
test-asan: build-asan
	ctest --test-dir build-asan -j $(JOBS) --output-on-failure $(ASAN_CTEST)

test-python: build-cli
	$(PYTHON) -m pytest tests/analysis tests/tools -q -m "not browser" -n $(JOBS)

# Every console block of README.md and docs/*.md run and its output compared
# (docs/docs-check.md); the two example kernels that some of them run are built too.
docs-check: build-cli
	@cmake --build build --target tiny_kernel c_kernel
	$(PYTHON) tools/docs_check.py $(DOCS_CHECK_FLAGS)

# The explorer page of `make reproduce` (results/explorer.html) in headless Chromium
# (installed by `scripts/setup.sh --browser`): sliders moved, the counts it shows checked
# against the engine's. The tests marked `browser`, which `make test-python` leaves out.
test-browser: build-cli
	@bash scripts/setup.sh --browser
	$(PYTHON) -m pytest tests/analysis -q -m browser

# Every test of the release build, the sanitizer build on the parsers and the kernel,
# and the analysis tests: about 10 minutes on 2 cores from a fresh clone.
test: test-cpp test-asan-core test-python

reproduce: build-cli
	@$(MAKE) --no-print-directory bunny-box || echo "warning: no bunny box: the report goes without its picture"
	$(PYTHON) -m hrbench_analysis.reproduce --quick

reproduce-full: build-cli
	$(PYTHON) -m hrbench_analysis.reproduce --full

# The Google Benchmark suites, merged into results/bench.json: 9 repetitions of each
# benchmark, so that hrbench-compare (tools/compare_bench.py) and Google Benchmark's own
# compare.py can run their U tests on two such files. BENCH_FLAGS replaces these flags.
# Then the performance targets' figures, from NAIVE_ROUNDS paired rounds against the
# naive kernel (bench-naive below; NAIVE_ROUNDS=0 skips them).
BENCH_FLAGS := --benchmark_repetitions=9 --benchmark_min_time=0.1
NAIVE_ROUNDS := 3
bench: build
	@mkdir -p results
	build/refine_bench --benchmark_out=results/bench-refine.json \
	  --benchmark_out_format=json $(BENCH_FLAGS)
	build/translation_count_bench --benchmark_out=results/bench-translation.json \
	  --benchmark_out_format=json $(BENCH_FLAGS)
	$(PYTHON) tools/merge_bench.py results/bench.json results/bench-refine.json \
	  results/bench-translation.json
	@if [ "$(NAIVE_ROUNDS)" != 0 ]; then bash bench/compare_naive.sh build $(NAIVE_ROUNDS) 0.5; fi

# hrbench's count-only kernel against the naive flat-array kernel of bench/, in paired
# interleaved rounds by CPU time: the ratio, cycles per oracle call, bytes per element.
bench-naive: build
	bash bench/compare_naive.sh build

# The benchmark history (docs/history.md): record results/bench.json for HEAD, then
# draw the page of times and counters over commits with the detected steps.
HISTORY_DIR := results/history
history: build
	$(MAKE) bench NAIVE_ROUNDS=0
	$(PYTHON) -m hrbench_analysis.bench.history record --history $(HISTORY_DIR) results/bench.json \
	  --hrbench build/hrbench
	$(PYTHON) -m hrbench_analysis.bench.history html --history $(HISTORY_DIR) --out results/history.html

# The CI gates of a change (docs/ci.md, also the GitHub Action of action.yml): build BASE
# and HEAD, check the count baseline, time both in interleaved rounds, print a summary.
gates: setup
	scripts/ci/gates $(or $(BASE),origin/main) $(or $(HEAD),HEAD) $(GATES_FLAGS)

# The example consumer project, built against the package installed from build/ and
# with hrbench as a subproject, and the tiny kernel of examples/tiny_kernel, whose link
# dump the installed `hrbench check-links` must accept (examples/build_consumer.sh); then
# the C kernel of examples/c_kernel, built with gcc -std=c99, its dump checked and claims
# run on it through the engine contract (examples/c_kernel/check.sh).
examples: build
	@bash examples/build_consumer.sh build
	@bash examples/c_kernel/check.sh build $(PYTHON)

# The analysis as another project installs it: `pip install .` into a fresh venv, then,
# from /, its import, its commands, and a reproduction on the external engine of
# examples/external_engine/ with its explorer page (CI).
python-package: setup
	@tmp=$$(mktemp -d) && python3 -m venv $$tmp/venv && $$tmp/venv/bin/python -m pip install -q . \
	  && cd / && $$tmp/venv/bin/python -c "import hrbench_analysis" \
	  && $$tmp/venv/bin/hrbench-reproduce --help >/dev/null \
	  && $$tmp/venv/bin/hrbench-sweep --help >/dev/null \
	  && $$tmp/venv/bin/hrbench-compare --help >/dev/null \
	  && $$tmp/venv/bin/hrbench-history --help >/dev/null \
	  && $$tmp/venv/bin/hrbench-tiling --help >/dev/null \
	  && $$tmp/venv/bin/hrbench-render --help >/dev/null \
	  && $$tmp/venv/bin/hrbench-explorer --help >/dev/null \
	  && HRBENCH_ENGINE="python3 $(CURDIR)/examples/external_engine/engine.py" \
	     $$tmp/venv/bin/hrbench-reproduce --claims $(CURDIR)/examples/external_engine/claims.toml \
	     --results $$tmp/results >/dev/null 2>&1 && test -s $$tmp/results/explorer.html; \
	  status=$$?; rm -rf $$tmp; \
	  if [ $$status -ne 0 ]; then echo "python-package: failed (exit code $$status)" >&2; exit 1; fi; \
	  echo "python-package: installed, imported and run from /"

# Rewrite tests/baseline/counts.json from the current engine, on purpose (`make test`
# checks it, as the CTest test count_baseline).
baseline: build
	$(PYTHON) tools/check_baseline.py --update

# Fuzzing (docs/fuzzing.md): the libFuzzer harnesses of fuzz/, built with clang, ASan and
# UBSan in build-fuzz, run FUZZ_SECONDS each on a scratch copy of fuzz/corpus/. A finding
# fails the target and leaves its reproducer in results/fuzz/.
FUZZ_HARNESSES := scene_json off obj cli
FUZZ_SECONDS := 600
FUZZ_SMOKE_SECONDS := 30
build-fuzz:
	@bash scripts/setup.sh --fuzz
	@CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=Debug \
	  "-DCMAKE_CXX_FLAGS_DEBUG=-O1" -DHRBENCH_FUZZ=ON -DHRBENCH_BUILD_BENCH=OFF >/dev/null
	@cmake --build build-fuzz --target fuzzers

fuzz: build-fuzz
	@bash fuzz/run.sh $(FUZZ_SECONDS) $(FUZZ_HARNESSES)

# A short run of every harness (CI): FUZZ_SMOKE_SECONDS each, two minutes in all. A fixed
# seed: runs try the same inputs in the same order and differ only in how far they get.
fuzz-smoke: build-fuzz
	@FUZZ_FLAGS=-seed=1 bash fuzz/run.sh $(FUZZ_SMOKE_SECONDS) $(FUZZ_HARNESSES)

# Formatting and lint: clang-format (.clang-format) on the C++ and C sources, ruff
# (pyproject.toml) on the Python. `make format` rewrites the C++ and C in place.
CXX_SOURCES = git ls-files --cached --others --exclude-standard '*.cpp' '*.h' '*.c'
lint: setup
	@$(CXX_SOURCES) | xargs clang-format --dry-run --Werror
	@.venv/bin/ruff check analysis tools tests examples
	@echo "lint: clean"

format: setup
	@$(CXX_SOURCES) | xargs clang-format -i

# The meshes of scenes at scale, in data/meshes/ (git-ignored; docs/meshes.md): the
# Stanford bunny from libcgal-demo (CGAL_DEMO_DEB=path/to/libcgal-demo_*.deb, or an
# installed package, or apt-get download) in a closed box lit from its ceiling, and the
# closed sphere of 1,002,528 triangles. `make reproduce` makes the bunny's box (for the
# report's picture of it) and goes on without it where the package cannot be had.
bunny-box: build-cli
	@bash scripts/fetch_bunny.sh $(CGAL_DEMO_DEB)
	@$(PYTHON) -m hrbench_analysis.meshes bunny-box --off data/meshes/bunny00.off --out data/meshes

meshes: bunny-box
	@build/hrbench save sphere n=354 --out data/meshes/sphere1m.obj
	@echo "data/meshes/sphere1m.obj: 1002528 triangles"

clean:
	rm -rf build build-asan build-fuzz
