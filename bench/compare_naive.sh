#!/usr/bin/env bash
# Paired, interleaved comparison of hrbench's count-only 2D kernel with the naive
# baseline of bench/naive_kernel_bench.cpp (docs/benchmarks.md, "The naive baseline and
# where the limit is"). Headline configuration: parallel l=1024 d=1, eps 0.01, garmann,
# count-only, one thread.
#
#   bench/compare_naive.sh [BUILD_DIR=build] [ROUNDS=7] [MIN_TIME=1]
#
# Each round runs BM_NaiveSqrt, BM_Hrbench and BM_NaiveSquares once each, and the 3D
# pair BM_Naive3d and BM_Hrbench3d (parallel3d l=32 d=1, eps 0.01, binary: the same
# 524,286 elements), each row a separate process, the order rotated from round to
# round; takes the CPU time per iteration of each, and prints per round and over the
# rounds (median, min, max): hrbench / naive-sqrt, naive-squares / naive-sqrt, hrbench
# 3D / naive 3D, and the cycles per oracle call of each. Then peak RSS per element
# (/usr/bin/time -v) of the hrbench CLI and of the naive kernel, in 2D and in 3D, the
# branch-free oracle stream (BM_OracleStream), peak RSS per stored link in
# store mode on 1 and 2 threads, and from R rounds of refine_bench's BM_Headline rows the
# count-only speed-up on 2 threads and the store-mode link rate against count-only. Clock: `perf stat -e
# cycles` where it counts, else "cpu MHz" of /proc/cpuinfo (nominal: on a VM that is the
# only figure, and turbo may make the true clock higher).
set -euo pipefail
BUILD=${1:-build}
ROUNDS=${2:-7}
MIN_TIME=${3:-1}
BENCH=$BUILD/naive_kernel_bench
CLI=$BUILD/hrbench
[[ -x $BENCH && -x $CLI ]] || { echo "build $BENCH and $CLI first" >&2; exit 2; }
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT

# Clock frequency.
GHZ=""
CLOCK_SOURCE=""
if command -v perf >/dev/null 2>&1; then
    out=$(perf stat -x, -e cycles,task-clock -- "$BENCH" --benchmark_filter='^BM_NaiveSqrt$' \
          --benchmark_min_time=0.001 2>&1 >/dev/null || true)
    cyc=$(awk -F, '$3 ~ /^cycles/ && $1 ~ /^[0-9]+$/ {print $1}' <<<"$out")
    ms=$(awk -F, '$3 ~ /^task-clock/ {print $1}' <<<"$out")
    if [[ -n $cyc && -n $ms ]]; then
        GHZ=$(awk -v c="$cyc" -v m="$ms" 'BEGIN {printf "%.3f", c / (m * 1e6)}')
        CLOCK_SOURCE="perf stat cycles / task-clock"
    fi
fi
if [[ -z $GHZ ]]; then
    GHZ=$(awk -F: '/cpu MHz/ {s += $2; n++} END {printf "%.3f", s / n / 1000}' /proc/cpuinfo)
    CLOCK_SOURCE="/proc/cpuinfo cpu MHz (perf cycles not available)"
fi

echo "machine: $(awk -F: '/model name/ {print $2; exit}' /proc/cpuinfo | sed 's/^ //'), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "clock: $GHZ GHz from $CLOCK_SOURCE"
echo "rounds: $ROUNDS, --benchmark_min_time=$MIN_TIME per row"

rows=(BM_NaiveSqrt BM_Hrbench BM_NaiveSquares BM_Naive3d BM_Hrbench3d)
for ((r = 0; r < ROUNDS; ++r)); do
    for ((k = 0; k < ${#rows[@]}; ++k)); do
        row=${rows[$(((r + k) % ${#rows[@]}))]}
        "$BENCH" --benchmark_filter="^$row\$" --benchmark_min_time="$MIN_TIME" \
            --benchmark_format=json 2>/dev/null >"$TMP/$r-$row.json"
    done
done

python3 - "$TMP" "$ROUNDS" "$GHZ" <<'EOF'
import json, statistics, sys
tmp, rounds, ghz = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
rows = ["BM_NaiveSqrt", "BM_Hrbench", "BM_NaiveSquares", "BM_Naive3d", "BM_Hrbench3d"]
def load(r, row):
    b = json.load(open(f"{tmp}/{r}-{row}.json"))["benchmarks"][0]
    if b.get("error_occurred"):
        sys.exit(f"{row}: {b.get('error_message')}")
    scale = {"ms": 1e6, "us": 1e3, "ns": 1}[b["time_unit"]]
    return b["cpu_time"] * scale, b
t = {row: [] for row in rows}
info = {}
for r in range(rounds):
    for row in rows:
        ns, b = load(r, row)
        t[row].append(ns)
        info[row] = b
for row in rows:
    b = info[row]
    print(f"{row}: links {int(b['links'])}, oracle_calls {int(b['oracle_calls'])}, "
          f"nodes {int(b['nodes'])}" + (f", counts_match {int(b['counts_match'])}"
                                          if 'counts_match' in b else ""))
def summary(name, xs, fmt="{:.3f}"):
    print(f"{name}: median {fmt.format(statistics.median(xs))}, min {fmt.format(min(xs))}, "
          f"max {fmt.format(max(xs))}  (per round: {' '.join(fmt.format(x) for x in xs)})")
calls = {row: info[row]["oracle_calls"] for row in rows}
for row in rows:
    summary(f"{row} CPU ms", [x / 1e6 for x in t[row]], "{:.1f}")
for row in rows:
    summary(f"{row} cycles/oracle call", [x / calls[row] * ghz for x in t[row]], "{:.2f}")
summary("ratio hrbench / naive-sqrt", [h / n for h, n in zip(t["BM_Hrbench"], t["BM_NaiveSqrt"])])
summary("ratio naive-squares / naive-sqrt",
        [s / n for s, n in zip(t["BM_NaiveSquares"], t["BM_NaiveSqrt"])])
summary("ratio hrbench / naive-squares",
        [h / s for h, s in zip(t["BM_Hrbench"], t["BM_NaiveSquares"])])
summary("ratio hrbench 3D / naive 3D",
        [h / n for h, n in zip(t["BM_Hrbench3d"], t["BM_Naive3d"])])
EOF

# Peak RSS per element.
rss() { /usr/bin/time -v "$@" 2>&1 >/dev/null | awk -F: '/Maximum resident set size/ {print $2 + 0}'; }
nodes=$("$CLI" run parallel l=1024 d=1 --eps 0.01 --count-only --json | python3 -c \
    'import json,sys; print(json.load(sys.stdin)["nodes"])')
kb_cli=$(rss "$CLI" run parallel l=1024 d=1 --eps 0.01 --count-only)
kb_cli0=$(rss "$CLI" run parallel l=1 d=1 --eps 10 --count-only)
kb_naive=$(rss "$BENCH" --benchmark_filter='^BM_NaiveSqrt$' --benchmark_min_time=0.001)
kb_naive0=$(rss "$BENCH" --benchmark_filter='^NONE$')
nodes3=$("$CLI" run parallel3d l=32 d=1 --eps 0.01 --count-only --json | python3 -c \
    'import json,sys; print(json.load(sys.stdin)["nodes"])')
kb_cli3=$(rss "$CLI" run parallel3d l=32 d=1 --eps 0.01 --count-only)
kb_cli30=$(rss "$CLI" run parallel3d l=1 d=1 --eps 10 --count-only)
kb_naive3=$(rss "$BENCH" --benchmark_filter='^BM_Naive3d$' --benchmark_min_time=0.001)
python3 - "$nodes" "$kb_cli" "$kb_cli0" "$kb_naive" "$kb_naive0" "$nodes3" "$kb_cli3" \
    "$kb_cli30" "$kb_naive3" <<'EOF'
import sys
n, cli, cli0, naive, naive0, n3, cli3, cli30, naive3 = map(int, sys.argv[1:])
def line(name, kb, kb0, n=n):
    print(f"peak RSS {name}: {kb} KiB = {kb * 1024 / n:.1f} bytes/element "
          f"({(kb - kb0) * 1024 / n:.1f} above the {kb0} KiB of a run that refines nothing)")
print(f"elements (nodes): {n} in 2D, {n3} in 3D")
line("hrbench run parallel l=1024 d=1 --eps 0.01 --count-only", cli, cli0)
line("naive kernel (naive_kernel_bench BM_NaiveSqrt, 1 iteration)", naive, naive0)
line("hrbench run parallel3d l=32 d=1 --eps 0.01 --count-only", cli3, cli30, n3)
line("naive 3D kernel (naive_kernel_bench BM_Naive3d, 1 iteration)", naive3, naive0, n3)
EOF

# The oracle alone, branch-free, over the first 2^22 pairs of the recursion: the floor
# of a branch-free or vectorised formulation (one run of each row).
"$BENCH" --benchmark_filter='^BM_OracleStream' --benchmark_format=json 2>/dev/null |
    python3 -c '
import json, sys
ghz = float(sys.argv[1])
for b in json.load(sys.stdin)["benchmarks"]:
    name = b["name"]
    if b.get("error_occurred"):
        print(name + ": " + str(b.get("error_message")))
        continue
    ns = b["ns_per_oracle_call"] * 1e9  # the JSON holds seconds per call
    print("%s: %.2f ns = %.2f cycles per oracle call (branch-free, no recursion)" % (name, ns, ns * ghz))
' "$GHZ"

# Store mode: peak RSS per stored link (the links, 8 bytes each, and everything else of
# the run) on 1 and 2 threads; and CPU time of store mode against count-only.
links=$("$CLI" run parallel l=1024 d=1 --eps 0.01 --count-only --json | python3 -c \
    'import json,sys; print(json.load(sys.stdin)["links"])')
for threads in 1 2; do
    kb=$(rss "$CLI" run parallel l=1024 d=1 --eps 0.01 --threads "$threads")
    python3 -c 'import sys; t, kb, l = sys.argv[1:]; print(f"peak RSS store mode, {t} thread(s): {kb} KiB = {int(kb) * 1024 / int(l):.2f} bytes/stored link")' \
        "$threads" "$kb" "$links"
done

# Threads: wall time of count-only on 1 and on 2 threads, and of store mode against
# count-only on 1 thread, by CPU time, in paired rounds (BM_Headline of refine_bench).
REFINE=$BUILD/refine_bench
if [[ -x $REFINE ]]; then
    for ((r = 0; r < ROUNDS; ++r)); do
        "$REFINE" --benchmark_filter='^BM_Headline/' --benchmark_min_time="$MIN_TIME" \
            --benchmark_format=json 2>/dev/null >"$TMP/headline-$r.json"
    done
    python3 - "$TMP" "$ROUNDS" "$(nproc)" <<'PYEOF'
import json, statistics, sys
tmp, rounds, cores = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
real, cpu = {}, {}
for r in range(rounds):
    for b in json.load(open(f"{tmp}/headline-{r}.json"))["benchmarks"]:
        name = b["name"].removesuffix("/real_time")
        real.setdefault(name, []).append(b["real_time"])
        cpu.setdefault(name, []).append(b["cpu_time"])
def summary(name, xs):
    print(f"{name}: median {statistics.median(xs):.3f}, min {min(xs):.3f}, max {max(xs):.3f}")
one, two = "BM_Headline/garmann_count/threads:1", "BM_Headline/garmann_count/threads:2"
store = "BM_Headline/garmann_store/threads:1"
summary(f"speed-up count-only 2 threads / 1 thread, wall time ({cores} cores)",
        [a / b for a, b in zip(real[one], real[two])])
summary("link rate store mode / count-only, 1 thread, CPU time",
        [c / s for c, s in zip(cpu[one], cpu[store])])
PYEOF
fi
