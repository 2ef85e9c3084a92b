#!/usr/bin/env bash
# Builds examples/consumer twice and checks its counts against those of
# `hrbench run parallel l=64 d=1 --eps 0.25`: against the package installed from the
# build folder $1 (default build) into a scratch prefix (find_package(hrbench)), and with
# hrbench as a subproject (add_subdirectory), which must not need Catch2 or Python.
# Then builds examples/tiny_kernel against the installed probe, and checks its link dump
# with the installed `hrbench check-links`.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
cmake --install "$build" --prefix "$scratch/prefix" >/dev/null
want=$("$scratch/prefix/bin/hrbench" run parallel l=64 d=1 --eps 0.25 |
  grep -E '^(nodes|links|oracle_calls) ' | tr -s ' ')

check() {  # check NAME CMAKE-ARGS...: configure, build and run the consumer
  local name=$1
  shift
  cmake -S examples/consumer -B "$scratch/$name" -G Ninja -DCMAKE_BUILD_TYPE=Release "$@" \
    >"$scratch/$name.log" 2>&1 && cmake --build "$scratch/$name" >>"$scratch/$name.log" 2>&1 ||
    { cat "$scratch/$name.log" >&2; echo "examples: the $name build failed" >&2; exit 1; }
  if grep -q -E '^(Catch2_DIR|benchmark_DIR|Python3_EXECUTABLE)' "$scratch/$name/CMakeCache.txt"; then
    echo "examples: the $name build looked for the tests' or benchmarks' tools" >&2
    exit 1
  fi
  local got
  got=$("$scratch/$name/count_plates")
  if [ "$got" != "$want" ]; then
    printf 'examples: the %s consumer counted\n%s\nbut hrbench\n%s\n' "$name" "$got" "$want" >&2
    exit 1
  fi
  echo "examples: $name consumer built; counts agree ($(echo $got))"
}
check installed -DCMAKE_PREFIX_PATH="$scratch/prefix"
check subproject -DHRBENCH_SOURCE_DIR="$PWD" -DCMAKE_CXX_COMPILER_LAUNCHER="${CMAKE_CXX_COMPILER_LAUNCHER:-}"

# The independent kernel: its own recursion, only <hrbench/probe.h> from the package.
cmake -S examples/tiny_kernel -B "$scratch/tiny" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$scratch/prefix" >"$scratch/tiny.log" 2>&1 &&
  cmake --build "$scratch/tiny" >>"$scratch/tiny.log" 2>&1 ||
  { cat "$scratch/tiny.log" >&2; echo "examples: the tiny kernel build failed" >&2; exit 1; }
got=$("$scratch/tiny/tiny_kernel" 64 1 0.25 "$scratch/tiny.dump" | grep -E '^links ')
if [ "$got" != "links 5092" ]; then
  echo "examples: the tiny kernel counted '$got', not 'links 5092'" >&2
  exit 1
fi
"$scratch/prefix/bin/hrbench" check-links parallel l=64 d=1 --eps 0.25 \
  --links "$scratch/tiny.dump" >"$scratch/check.txt" ||
  { echo "examples: check-links rejected the tiny kernel's dump" >&2; exit 1; }
echo "examples: tiny kernel built; check-links accepts its $got"
