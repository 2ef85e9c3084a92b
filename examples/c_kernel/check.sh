#!/usr/bin/env bash
# The C kernel as another project builds it: gcc in strict C99 with the probe header
# alone (no C++ runtime linked), its link dump judged by `hrbench check-links` on the
# conventions the dump declares, and claims C1 and C4 run on it through the engine
# contract (engine.py), each of which must come out `reproduced`.
#   examples/c_kernel/check.sh [BUILD [PYTHON]]    (defaults: build, .venv/bin/python)
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
python=${2:-.venv/bin/python}
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

gcc -std=c99 -pedantic -Wall -Wextra -Werror -O2 -ffp-contract=off -Iinclude \
  examples/c_kernel/c_kernel.c -o "$scratch/c_kernel" -lm
echo "examples: c_kernel built with gcc -std=c99 -pedantic (no C++ runtime)"

# The plates (ties at every level), and a scene of 30 segments where element pairs are
# culled, read from the JSON `hrbench save` writes.
"$scratch/c_kernel" 0.25 parallel 64 1 "$scratch/plates.dump" >/dev/null
"$build/hrbench" save random n=30 seed=3 >"$scratch/random.json"
"$scratch/c_kernel" 0.05 "$scratch/random.json" "$scratch/random.dump" >/dev/null
for scene in "parallel l=64 d=1 --eps 0.25 --links $scratch/plates.dump" \
  "--scene-file $scratch/random.json --eps 0.05 --links $scratch/random.dump"; do
  # shellcheck disable=SC2086 # the words of a command line
  "$build/hrbench" check-links $scene >"$scratch/check.txt" ||
    { echo "examples: check-links rejected the C kernel's dump ($scene)" >&2; exit 1; }
  echo "examples: check-links accepts the C kernel's dump: $(head -n 1 "$scratch/check.txt")"
done

"$python" -m hrbench_analysis.reproduce --quick --no-pictures \
  --engine "python3 examples/c_kernel/engine.py $scratch/c_kernel" \
  --claims examples/c_kernel/claims.toml --results "$scratch/results" >"$scratch/reproduce.txt" 2>&1 ||
  { cat "$scratch/reproduce.txt" >&2; echo "examples: the claims on the C kernel failed" >&2; exit 1; }
"$python" - "$scratch/results/claims.json" <<'EOF'
import json, sys
claims = json.load(open(sys.argv[1]))["claims"]
verdicts = {c["id"]: c["verdict"] for c in claims}
print("examples: claims on the C kernel through the engine contract:", verdicts)
sys.exit(0 if verdicts and set(verdicts.values()) == {"reproduced"} else 1)
EOF
