"""Building any commit of hrbench in a git worktree, and running its benchmarks.

The CI gates (``scripts/ci/gates``: a base and a head commit) and ``hrbench-history
measure`` (every commit of a range) both build commits this way and time them with one
command: ``refine_bench`` of the build, or a command of the user's (``--bench-cmd``)
that writes Google Benchmark JSON.

Each commit is built under ``WORKDIR/commits/<sha[:12]>/``: ``src`` (the worktree) and
``build`` (Release, the targets ``hrbench`` and ``refine_bench``, through ccache when it
is installed); a finished build is reused. The work folder is the user's own
(:func:`default_workdir`, :func:`prepare_workdir`). Standard library only, like
:mod:`hrbench_analysis.bench.gbench`, so that the count gate runs without numpy.
"""

import hashlib
import os
import re
import shutil
import subprocess
import sys

from ..engine import run_engine
from ..errors import AnalysisError
from ..stages import Stage

__all__ = ["UsageError", "BuildError", "DEFAULT_FILTER", "git", "locate_project",
           "resolve_ref", "read_file_at", "commits_between", "build_commit",
           "run_benchmarks", "bench_limit", "BENCH_TIMEOUT", "BENCH_LIMIT_FACTOR",
           "default_workdir", "prepare_workdir", "tree_of", "files_digest"]

# Five refine_bench benchmarks, both oracles, count-only and store mode, both sweeps:
# about 0.3 s each at --benchmark_min_time 0.2.
DEFAULT_FILTER = ("^BM_EpsSweep/garmann_(count|store)/inv_eps:64/"
                  "|^BM_EpsSweep/hanrahan_count/inv_eps:256/"
                  "|^BM_GeometrySweep/garmann_count/g:256/"
                  "|^BM_GeometrySweep/hanrahan_store/g:16/")


class UsageError(AnalysisError, ValueError):
    """Bad input: not a git repository, an unknown ref, a commit that is not hrbench."""


class BuildError(RuntimeError):
    """A git command, a build or a benchmark run failed."""


def git(repo, *args, check=True):
    proc = subprocess.run(["git", "-C", str(repo), *args], capture_output=True, text=True)
    if check and proc.returncode != 0:
        raise BuildError(f"git {' '.join(args)} failed: {proc.stderr.strip()}")
    return proc


def locate_project(project):
    """(git top level, the project's path inside it with a trailing slash or '')."""
    if not os.path.isdir(project):
        raise UsageError(f"--project {project}: no such directory")
    top = git(project, "rev-parse", "--show-toplevel", check=False)
    if top.returncode != 0:
        raise UsageError(f"{os.path.abspath(project)} is not in a git repository")
    prefix = git(project, "rev-parse", "--show-prefix").stdout.strip()
    return top.stdout.strip(), prefix


def resolve_ref(repo, ref, which):
    proc = git(repo, "rev-parse", "--verify", "--quiet", f"{ref}^{{commit}}", check=False)
    if proc.returncode != 0:
        raise UsageError(f"{which} {ref!r} is not a commit of {repo} (fetch it first: "
                         "actions/checkout needs fetch-depth: 0)")
    return proc.stdout.strip()


def read_file_at(repo, sha, path):
    """The content of _path_ at commit _sha_, or None if it has no such file."""
    proc = subprocess.run(["git", "-C", str(repo), "show", f"{sha}:{path}"],
                          capture_output=True)
    return proc.stdout if proc.returncode == 0 else None


def commits_between(repo, base, head):
    """The commits of ``base..head`` (reachable from _head_, not from _base_), oldest
    first, as ``(sha, subject)``; None if git cannot tell here (not a repository, an
    unknown commit)."""
    try:
        proc = subprocess.run(["git", "-C", str(repo), "--no-optional-locks", "log",
                               "--reverse", "--format=%H%x09%s", f"{base}..{head}", "--"],
                              capture_output=True, text=True, timeout=60)
    except (OSError, subprocess.SubprocessError):
        return None
    if proc.returncode != 0:
        return None
    return [tuple((line.split("\t", 1) + [""])[:2]) for line in proc.stdout.splitlines()]


def default_workdir():
    """The default work folder of the gates and ``hrbench-history``: the user's own.

    ``$RUNNER_TEMP/hrbench-gates`` on a CI runner (a job's own temporary folder), else
    ``$XDG_CACHE_HOME/hrbench-gates`` (``~/.cache/hrbench-gates``): private to the user,
    and kept, so that a commit's finished build is reused by the next run. A folder in
    /tmp shared by every user would let one user's builds be read, replaced or blocked
    by another's.
    """
    if os.environ.get("RUNNER_TEMP"):
        return os.path.join(os.environ["RUNNER_TEMP"], "hrbench-gates")
    cache = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(cache, "hrbench-gates")


def prepare_workdir(path, option="--workdir"):
    """Create the work folder, readable by its user only, and refuse another user's.

    Returns the absolute path. Raises UsageError if it cannot be created, or if it
    exists and belongs to another user (whose builds this run would use or replace).
    """
    path = os.path.abspath(path)
    try:
        os.makedirs(path, mode=0o700, exist_ok=True)
        owner = os.stat(path).st_uid
    except OSError as exc:
        raise UsageError(f"{option} {path}: cannot create it ({exc.strerror or exc})") from None
    if hasattr(os, "getuid") and owner != os.getuid():
        raise UsageError(f"{option} {path} belongs to another user (uid {owner}); give a "
                         f"folder of your own with {option} DIR")
    return path


def tree_of(repo, sha, prefix):
    """The git tree hash of hrbench's directory at commit _sha_: two commits with the same
    tree build the same program, whatever their names."""
    return git(repo, "rev-parse", f"{sha}:{prefix}").stdout.strip()


def files_digest(folder, names):
    """The SHA-256 of the files _names_ of _folder_ (their names and bytes, in order)."""
    digest = hashlib.sha256()
    for name in names:
        digest.update(name.encode() + b"\0")
        with open(os.path.join(folder, name), "rb") as f:
            for block in iter(lambda: f.read(1 << 20), b""):
                digest.update(block)
    return digest.hexdigest()


def _tail(path, n=30):
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            return "".join(f.readlines()[-n:])
    except OSError:
        return ""


def build_commit(repo, prefix, sha, workdir, jobs, use_ccache, which, log):
    """Build hrbench and refine_bench of _sha_ in a worktree; reuse a finished build.

    Parameters
    ----------
    repo, prefix : str
        The repository and hrbench's directory in it (`locate_project`).
    sha : str
        The full commit hash.
    workdir : str
        Where the worktrees and builds live.
    jobs : int
        Parallel build jobs.
    use_ccache : bool
        Compile through ccache if it is installed.
    which : str
        What the commit is, in messages ("base", "head", a short hash).
    log : callable
        Takes one progress message.

    Returns
    -------
    str
        The build directory.

    Raises
    ------
    UsageError
        The commit has no CMakeLists.txt where hrbench should be.
    BuildError
        git or the build failed (the tail of the build log goes to stderr).
    """
    short = sha[:12]
    # workdir/commits/SHA/src (the worktree) and .../build: the same relative paths
    # from every build to its sources, so that ccache (CCACHE_BASEDIR) hits across commits.
    tree = os.path.join(workdir, "commits", short, "src")
    build = os.path.join(workdir, "commits", short, "build")
    stamp = os.path.join(build, ".hrbench-gates-built")
    exes = [os.path.join(build, e) for e in ("hrbench", "refine_bench")]
    if os.path.isfile(stamp) and all(os.access(e, os.X_OK) for e in exes):
        with open(stamp) as f:
            if f.read().strip() == sha:
                log(f"{which} {short}: reusing the build in {build}")
                return build
    if not (os.path.isdir(tree) and git(tree, "rev-parse", "HEAD", check=False)
            .stdout.strip() == sha):
        if os.path.exists(tree):
            shutil.rmtree(tree)
        git(repo, "worktree", "prune")
        os.makedirs(os.path.dirname(tree), exist_ok=True)
        git(repo, "worktree", "add", "--detach", "--force", tree, sha)
    source = os.path.join(tree, prefix)
    if not os.path.isfile(os.path.join(source, "CMakeLists.txt")):
        raise UsageError(f"{which} {short} has no {prefix}CMakeLists.txt: not hrbench")
    os.makedirs(build, exist_ok=True)
    configure = ["cmake", "-S", source, "-B", build, "-DCMAKE_BUILD_TYPE=Release",
                 "-DHRBENCH_BUILD_BENCH=ON", "-DHRBENCH_BUILD_TESTS=OFF"]
    if shutil.which("ninja") and not os.path.isfile(os.path.join(build, "Makefile")):
        configure += ["-G", "Ninja"]
    env = dict(os.environ)
    if use_ccache and shutil.which("ccache"):
        configure.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
        # Paths under the workdir hash alike in every commit's build: a file the change
        # leaves alone is a cache hit.
        env.setdefault("CCACHE_BASEDIR", workdir)
    build_log = os.path.join(build, "hrbench-gates-build.log")
    # A build takes minutes: a line every few seconds with the build's last step
    # ("step 34/89"), so that a slow build is not taken for a hung one.
    with open(build_log, "w") as out, Stage(
            f"{which} {short}: building", log=log, detail=lambda: _build_step(build_log),
            start=f"{which} {short}: building in {build} (log {build_log})"):
        for cmd in (configure, ["cmake", "--build", build, "--target", "hrbench",
                                "refine_bench", "--parallel", str(jobs)]):
            out.write("$ " + " ".join(cmd) + "\n")
            out.flush()
            rc = subprocess.run(cmd, stdout=out, stderr=subprocess.STDOUT, env=env).returncode
            if rc != 0:
                sys.stderr.write(_tail(build_log))
                raise BuildError(f"the build of {which} {short} failed (exit code {rc}); "
                                 f"see {build_log}")
    with open(stamp, "w") as f:
        f.write(sha + "\n")
    return build


def _build_step(build_log):
    # The last "[done/total]" step ninja or make wrote to the build log, or "".
    steps = re.findall(r"^\[\s*(\d+/\d+|\d+%)\]", _tail(build_log, 20), re.MULTILINE)
    return f"step {steps[-1]}" if steps else ""


#: Seconds one benchmark run may take before it is ended with its child processes, while
#: no run of the same series has finished to measure it by.
BENCH_TIMEOUT = 1800
#: A later run may take this many times the first finished run of its series (the gates:
#: the base's first run; ``hrbench-history measure``: the first commit measured), but
#: never less than :data:`BENCH_LIMIT_FLOOR` seconds nor more than :data:`BENCH_TIMEOUT`:
#: a hung benchmark holds the caller about ten times a run, not 30 minutes. A change that
#: makes a run ten times slower fails its gate either way.
BENCH_LIMIT_FACTOR = 10
#: Seconds: the least limit :func:`bench_limit` gives (start-up noise of short runs).
BENCH_LIMIT_FLOOR = 60


def bench_limit(reference_seconds):
    """The time limit of a benchmark run, given the wall time of the first finished run of
    its series (None while there is none): ``BENCH_LIMIT_FACTOR`` times it, within
    ``[BENCH_LIMIT_FLOOR, BENCH_TIMEOUT]`` seconds."""
    if reference_seconds is None:
        return BENCH_TIMEOUT
    return min(BENCH_TIMEOUT, max(BENCH_LIMIT_FLOOR, BENCH_LIMIT_FACTOR * reference_seconds))


def run_benchmarks(build, out, what, *, bench_cmd=None, bench_filter=DEFAULT_FILTER,
                   min_time=0.2, repetitions=1, env=None, timeout=BENCH_TIMEOUT):
    """Run the benchmarks of one build once, writing Google Benchmark JSON to _out_.

    Parameters
    ----------
    build : str
        The build directory.
    out : str
        The JSON file to write.
    what : str
        The run, in the error message ("round 3: head's benchmarks").
    bench_cmd : str, optional
        A shell command instead of refine_bench. It runs with ``HRBENCH_BUILD`` (the
        build directory) and ``HRBENCH_BENCH_OUT`` (_out_) in its environment, plus
        _env_, and must write Google Benchmark JSON (``--benchmark_out_format=json``)
        to ``$HRBENCH_BENCH_OUT``.
    bench_filter, min_time, repetitions : optional
        ``--benchmark_filter``, ``--benchmark_min_time`` (seconds) and
        ``--benchmark_repetitions`` of refine_bench; unused with _bench_cmd_.
    env : dict, optional
        More environment variables for _bench_cmd_.
    timeout : float, optional
        Seconds the run may take (:data:`BENCH_TIMEOUT`; :func:`bench_limit` for the
        runs after a first one); then its process group is killed and the run fails.

    Returns
    -------
    seconds : float
        The run's wall time.

    Raises
    ------
    BuildError
        The command failed, ran out of time or wrote no file.

    Notes
    -----
    The run is an engine run (:func:`hrbench_analysis.engine.run_engine`): it ends when
    the command exits, and its process group is killed then, so a child the command
    leaves in the background holds neither the caller nor the next run; the command is
    killed with the caller, however the caller ends.
    """
    if bench_cmd:
        cmd = ["sh", "-c", bench_cmd]
        run_env = dict(os.environ, HRBENCH_BUILD=os.path.abspath(build),
                       HRBENCH_BENCH_OUT=os.path.abspath(out), **(env or {}))
    else:
        cmd = [os.path.join(build, "refine_bench"), f"--benchmark_filter={bench_filter}",
               f"--benchmark_min_time={min_time:g}", f"--benchmark_out={out}",
               "--benchmark_out_format=json"]
        if repetitions > 1:
            cmd.append(f"--benchmark_repetitions={repetitions}")
        run_env = None
    if os.path.exists(out):
        os.remove(out)  # a file left by an earlier run must not pass for this one's
    run = run_engine(cmd, timeout=timeout, env=run_env)
    if run.stopped == "timeout":
        raise BuildError(f"{what} did not finish within {timeout:g} s; it was ended with "
                         "its child processes")
    if run.stopped:
        raise BuildError(f"{what}: {run.reason}")
    if run.exit_code != 0 or not os.path.isfile(out):
        why = (f"exit code {run.exit_code}" if run.exit_code != 0
               else f"it wrote no {out}")
        raise BuildError(f"{what} failed ({why}): {run.stderr.strip()[-300:]}")
    return run.wall_seconds
