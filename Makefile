# Thin wrapper over CMake and the Python analysis. Quick start: `make reproduce`, `make test`.
PYTHON := .venv/bin/python
CMAKE_FLAGS := -G Ninja -DCMAKE_BUILD_TYPE=Release

.PHONY: setup build build-asan test test-cpp test-asan test-python reproduce reproduce-full bench clean

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
	$(PYTHON) -m pytest tests/analysis -q

# Every test: the C++ tests in the release and the sanitizer build, then the analysis tests.
test: test-cpp test-asan test-python

reproduce: build
	$(PYTHON) -m analysis.reproduce --quick

reproduce-full: build
	$(PYTHON) -m analysis.reproduce --full

clean:
	rm -rf build build-asan
