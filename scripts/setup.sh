#!/usr/bin/env bash
# Installs what hrbench needs, idempotently: Debian packages for the C++ build and a
# Python virtual environment (.venv) for the analysis. Safe to run again and again.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(cmake ninja-build g++ make git libeigen3-dev catch2 libcgal-dev libembree-dev
          libbenchmark-dev nlohmann-json3-dev libssl-dev python3 python3-venv clang-format)
# `setup.sh --fuzz` (make build-fuzz, fuzz, fuzz-smoke) adds clang, its libFuzzer and
# sanitizer runtimes (libclang-rt-14-dev, which Debian's clang only recommends) and
# llvm-symbolizer (llvm) for the stacks of findings.
if [[ " $* " == *" --fuzz "* ]]; then
  packages+=(clang libclang-rt-14-dev llvm)
fi
# `setup.sh --browser` (make test-browser) adds Chromium, which the tests marked
# `browser` run headless to drive the explorer page.
if [[ " $* " == *" --browser "* ]]; then
  packages+=(chromium)
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# Another package manager may hold apt's or dpkg's lock (a first boot's automatic
# upgrades, an install in another terminal): apt_locked waits for it, up to
# HRBENCH_APT_LOCK_TIMEOUT seconds in all, saying once what it waits for. apt-get's own
# DPkg::Lock::Timeout covers only dpkg's lock, not the lists' lock of `apt-get update`,
# so each command is retried instead while apt says a lock is held.
lock_limit=${HRBENCH_APT_LOCK_TIMEOUT:-600}
[[ "$lock_limit" =~ ^[0-9]+$ ]] || {
  echo "setup: HRBENCH_APT_LOCK_TIMEOUT must be a number of seconds, not '$lock_limit'" >&2; exit 2; }
lock_deadline=$((SECONDS + lock_limit))
apt_locked() {
  local err status waited=""
  err=$(mktemp)
  while true; do
    status=0
    "$@" 2>"$err" || status=$?
    # apt's line: "E: Could not get lock /var/lib/dpkg/lock-frontend. It is held by
    # process 1234 (apt-get)", or "E: Unable to acquire the dpkg frontend lock (...)".
    local what
    what=$(sed -n -e 's/^E: Could not get lock \([^ ]*\)\. It is held by \(.*\)/\1, held by \2/p' \
                  -e 's/^E: Could not get lock \([^ ]*\)\.*$/\1/p' \
                  -e 's/^E: Unable to acquire the dpkg frontend lock (\([^)]*\)).*/\1/p' \
                  -e 's/^E: Unable to lock directory \(.*\)/\1/p' "$err" | head -n 1)
    if ((status == 0)) || [ -z "$what" ]; then
      cat "$err" >&2; rm -f "$err"; return "$status"
    fi
    if ((SECONDS >= lock_deadline)); then
      rm -f "$err"
      echo "setup: gave up after ${lock_limit} s waiting for the package lock $what; run" \
           "again once the other install ends, or set HRBENCH_APT_LOCK_TIMEOUT=SECONDS" >&2
      return 1
    fi
    if [ -z "$waited" ]; then
      # On standard error: the install's standard output is thrown away.
      echo "setup: waiting up to ${lock_limit} s (HRBENCH_APT_LOCK_TIMEOUT) for the" \
           "package lock $what" >&2
      waited=1
    fi
    sleep 2
  done
}
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo=""; [ "$(id -u)" -eq 0 ] || sudo="sudo"
  apt_locked $sudo apt-get update -qq
  # No wait of apt's own (it would wait in silence, without our limit): apt_locked waits.
  apt_locked $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq \
    -o DPkg::Lock::Timeout=0 --no-install-recommends "${missing[@]}" >/dev/null
fi

# The venv is rebuilt only when the requirements change.
requirements=analysis/requirements.txt
stamp=.venv/.requirements-installed
if [ ! -x .venv/bin/python ]; then
  echo "setup: creating .venv"
  python3 -m venv .venv
fi
if [ ! -f "$stamp" ] || ! cmp -s "$requirements" "$stamp"; then
  # pip prints what it collects and installs: on a fresh clone this is the slow step.
  echo "setup: installing Python packages from $requirements (about a minute)"
  .venv/bin/python -m pip install -q --upgrade pip
  .venv/bin/python -m pip install --progress-bar off -r "$requirements" \
    | { grep --line-buffered -v '^Requirement already satisfied' || true; }
  cp "$requirements" "$stamp"
fi
# The analysis package itself, editable: `python -m hrbench_analysis.reproduce` runs the
# sources in analysis/hrbench_analysis/. Installed again when pyproject.toml changes (its
# console scripts, hrbench-reproduce, hrbench-sweep, hrbench-compare, come from there).
package_stamp=.venv/.pyproject-installed
if ! .venv/bin/python -c "import hrbench_analysis" 2>/dev/null \
    || ! cmp -s pyproject.toml "$package_stamp"; then
  echo "setup: installing the analysis package (pip install -e .)"
  .venv/bin/python -m pip install -q --no-deps -e .
  cp pyproject.toml "$package_stamp"
fi
