# Thin wrapper over CMake and the Python analysis. Quick start: `make reproduce`, `make test`.
PYTHON := .venv/bin/python
CMAKE_FLAGS := -G Ninja -DCMAKE_BUILD_TYPE=Release

.PHONY: setup build build-asan test test-cpp test-asan test-python reproduce reproduce-full bench \
        baseline lint format clean

setup:
	@bash scripts/setup.sh

build: setup
	@cmake -S . -B build $(CMAKE_FLAGS) >/dev/null
	@cmake --build build

# Debug build with AddressSanitizer and UndefinedBehaviorSanitizer.
build-asan: setup
	@cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Debug -DHRBENCH_SANITIZE=ON \
	  -DHRBENCH_BUILD_BENCH=OFF >/dev/null
	@cmake --build build-asan

test-cpp: build
	ctest --test-dir build --output-on-failure

test-asan: build-asan
	ctest --test-dir build-asan --output-on-failure

test-python: build
	$(PYTHON) -m pytest tests/analysis tests/tools -q

# Every test: the C++ tests in the release and the sanitizer build, then the analysis tests.
test: test-cpp test-asan test-python

reproduce: build
	$(PYTHON) -m analysis.reproduce --quick

reproduce-full: build
	$(PYTHON) -m analysis.reproduce --full

# The Google Benchmark suites (about a minute and a half), merged into results/bench.json.
# Extra flags, e.g. BENCH_FLAGS=--benchmark_repetitions=5 for tools/compare_bench.py.
BENCH_FLAGS :=
bench: build
	@mkdir -p results
	build/refine_bench --benchmark_out=results/bench-refine.json \
	  --benchmark_out_format=json $(BENCH_FLAGS)
	build/translation_count_bench --benchmark_out=results/bench-translation.json \
	  --benchmark_out_format=json $(BENCH_FLAGS)
	$(PYTHON) tools/merge_bench.py results/bench.json results/bench-refine.json \
	  results/bench-translation.json

# Rewrite tests/baseline/counts.json from the current engine, on purpose (`make test`
# checks it, as the CTest test count_baseline).
baseline: build
	$(PYTHON) tools/check_baseline.py --update

# Formatting and lint: clang-format (.clang-format) on the C++ sources, ruff
# (pyproject.toml) on the Python. `make format` rewrites the C++ in place.
CXX_SOURCES = git ls-files --cached --others --exclude-standard '*.cpp' '*.h'
lint: setup
	@$(CXX_SOURCES) | xargs clang-format --dry-run --Werror
	@.venv/bin/ruff check analysis tools tests
	@echo "lint: clean"

format: setup
	@$(CXX_SOURCES) | xargs clang-format -i

clean:
	rm -rf build build-asan
