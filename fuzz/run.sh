#!/usr/bin/env bash
# Runs the libFuzzer harnesses of build-fuzz (make build-fuzz) for SECONDS each, one after
# the other, on a scratch copy of their committed corpus (docs/fuzzing.md).
#   usage: fuzz/run.sh SECONDS HARNESS...
# FUZZ_FLAGS adds libFuzzer flags, e.g. FUZZ_FLAGS=-seed=1 for a repeatable run.
# Writes results/fuzz/<harness>.log, the grown corpus to results/fuzz/corpus/<harness>/ and
# any reproducer to results/fuzz/<harness>-{crash,leak,timeout,oom}-<sha1>. Exits 1 when a
# harness found something, after running all of them.
set -uo pipefail
cd "$(dirname "$0")/.."

seconds=$1
shift
out=results/fuzz
mkdir -p "$out"

# Longest input a harness may try, in bytes: scene files get room for deep nesting.
max_len() {
    case $1 in
    scene_json) echo 32768 ;;
    cli) echo 1024 ;;
    *) echo 8192 ;;
    esac
}

# Stacks of findings: symbolised, and printed for UBSan too.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_stack_use_after_return=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1}

failed=()
for harness in "$@"; do
    binary=build-fuzz/fuzz_$harness
    if [ ! -x "$binary" ]; then
        echo "fuzz: $binary is missing; run make build-fuzz" >&2
        exit 2
    fi
    corpus=$out/corpus/$harness
    rm -rf "$corpus"
    mkdir -p "$corpus"
    cp fuzz/corpus/"$harness"/* "$corpus"/
    flags=(-max_total_time="$seconds" -max_len="$(max_len "$harness")" -timeout=10
           -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$out/$harness-")
    [ -f "fuzz/$harness.dict" ] && flags+=(-dict="fuzz/$harness.dict")
    read -r -a extra <<<"${FUZZ_FLAGS:-}"
    flags+=("${extra[@]}")
    log=$out/$harness.log
    stamp=$out/.$harness.started
    touch "$stamp"
    echo "fuzz: $harness for ${seconds}s ($(ls "$corpus" | wc -l) seed inputs), log $log"
    if "$binary" "${flags[@]}" "$corpus" >"$log" 2>&1; then
        grep -E '^stat::(number_of_executed_units|average_exec_per_sec|new_units_added)' "$log" |
            sed 's/^/    /'
    else
        echo "fuzz: $harness FOUND SOMETHING; reproducer:" >&2
        find "$out" -maxdepth 1 -name "$harness-*" -newer "$stamp" | sed 's/^/    /' >&2
        grep -E 'ERROR: |FINDING: |runtime error: |SUMMARY: ' "$log" | head -5 | sed 's/^/    /' >&2
        failed+=("$harness")
    fi
done
if ((${#failed[@]})); then
    echo "fuzz: findings in ${failed[*]}; see $out/ and docs/fuzzing.md" >&2
    exit 1
fi
echo "fuzz: no findings"
