#!/usr/bin/env python3
"""Run the console blocks of the docs and compare their output (docs/docs-check.md).

usage: docs_check.py [FILE.md ...] [--root DIR] [--timeout S] [--jobs N]

Reads README.md and docs/*.md of the checkout (or the FILEs given) and runs every fenced
block tagged ``console``: its ``$ `` lines are commands (a trailing backslash continues
one on the next line), the lines after a command up to the next ``$ `` line its expected
output, stdout and stderr merged, then optionally ``[exit N]``, the exit code it expects
(0 otherwise). A line that is exactly ``...`` matches zero or more lines; ``[...]``
inside a line matches any text within that line. Every other character is compared.

A block runs in a scratch directory of its own that links every top-level entry of the
checkout but ``.git`` and ``results`` (so build/hrbench, tests/data/... and examples/...
resolve, and what the commands write stays there), with build/ and the directory of
this Python on the PATH, HOME and TMPDIR inside the scratch directory, and no HRBENCH_*
variable. The commands of one block run one after the other, each with ``bash -c`` in
that directory; the first to differ ends its block.

An HTML comment on the line before a block's fence sets options:
``<!-- docs-check: timeout=S -->`` gives each command of the block S seconds (default
--timeout); ``<!-- docs-check: quotes=PATH -->`` marks a block that quotes a file that
``make reproduce`` writes (PATH relative to the checkout, e.g. results/report.md): it is
not run, but compared with PATH as lines that must appear in it consecutively, and listed
as not checked while PATH does not exist.

A ``$ `` line in a fenced block not tagged console fails the check: a command shown with
its output must be a console block, so that none escapes the check.

Prints one line per block as it ends (``docs/solve.md:570 ok (1.2 s)``), the failures
with a unified diff of expected against actual output, then ``N passed, M failed``.
Exit codes: 0 every block passes; 1 a block fails; 2 usage error.
"""

import concurrent.futures
import difflib
import glob
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field

from hrbench_analysis.errors import OneLineParser

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_TIMEOUT = 120.0  # seconds per command
NOT_LINKED = {".git", "results"}  # the repository itself, and what make reproduce writes

FENCE = re.compile(r"^(?P<indent>\s*)(?P<fence>`{3,}|~{3,})(?P<info>.*)$")
MARKER = re.compile(r"^\s*<!--\s*docs-check:(?P<options>.*?)-->\s*$")
EXIT = re.compile(r"^\[exit (?P<code>\d+)\]$")
ANY_LINES = "..."  # a line that matches zero or more lines
ANY_TEXT = "[...]"  # matches any text within a line
DIFF_CELLS = 4_000_000  # above this, the diff is not aligned on the elisions


@dataclass
class Block:
    """A fenced block of a Markdown file: where it is, its tag, its lines, its options."""

    path: str  # as printed
    line: int  # line of the opening fence, from 1
    tag: str  # the first word of the info string
    lines: list = field(default_factory=list)  # the content, the fence's indent removed
    options: dict = field(default_factory=dict)  # timeout (seconds), quotes (a path)
    error: str = ""  # what makes the block itself wrong

    @property
    def where(self):
        return f"{self.path}:{self.line}"


@dataclass
class Command:
    """One ``$ `` command of a console block and the output it must print."""

    line: int  # of its ``$ `` line
    text: str
    expected: list
    exit_code: int


@dataclass
class Outcome:
    """A checked block: passed, failed (with the message) or not checked (with the reason)."""

    block: Block
    status: str  # "ok", "FAILED", "not checked"
    seconds: float = 0.0
    message: str = ""


# Reading the blocks.


def parse_blocks(text, path):
    """The fenced blocks of a Markdown text, and a failed Block for every stray marker."""
    lines = text.split("\n")
    blocks, used_markers, inside = [], set(), set()
    i = 0
    while i < len(lines):
        opening = FENCE.match(lines[i])
        if not opening or (opening["fence"][0] == "`" and "`" in opening["info"]):
            i += 1
            continue
        fence, indent = opening["fence"], len(opening["indent"])
        info = opening["info"].split()
        block = Block(path, i + 1, info[0] if info else "")
        marker = _marker_line(lines, i)
        if marker is not None:
            used_markers.add(marker)
            block.options, block.error = _parse_options(MARKER.match(lines[marker])["options"])
        j = i + 1
        while j < len(lines):
            closing = FENCE.match(lines[j])
            if (closing and closing["fence"][0] == fence[0]
                    and len(closing["fence"]) >= len(fence) and not closing["info"].strip()):
                break
            block.lines.append(_dedent(lines[j], indent))
            j += 1
        else:
            block.error = block.error or "the block is not closed"
        blocks.append(block)
        inside.update(range(i, j + 1))
        i = j + 1
    for k, line in enumerate(lines):
        if MARKER.match(line) and k not in used_markers and k not in inside:
            blocks.append(Block(path, k + 1, "", error="a docs-check comment not followed "
                                                       "by a fenced block"))
    blocks.sort(key=lambda b: b.line)
    return blocks


def _marker_line(lines, fence):
    """The index of the docs-check comment right before the fence (blank lines between)."""
    k = fence - 1
    while k >= 0 and not lines[k].strip():
        k -= 1
    return k if k >= 0 and MARKER.match(lines[k]) else None


def _parse_options(text):
    options = {}
    for word in text.split():
        key, _, value = word.partition("=")
        if key == "timeout":
            try:
                options["timeout"] = float(value)
            except ValueError:
                return options, f"timeout={value} is not a number of seconds"
            if not options["timeout"] > 0:
                return options, f"timeout={value} is not above 0"
        elif key == "quotes" and value:
            options["quotes"] = value
        else:
            return options, f"unknown docs-check option '{word}' (timeout=S, quotes=PATH)"
    return options, ""


def _dedent(line, indent):
    stripped = len(line) - len(line.lstrip(" "))
    return line[min(indent, stripped):]


def parse_console(block):
    """The commands of a console block, each with its expected output and exit code."""
    commands, lines, k = [], block.lines, 0
    while k < len(lines):
        if not lines[k].startswith("$ "):
            if lines[k].strip():
                raise ValueError(f"line {block.line + 1 + k}: output before the first command")
            k += 1
            continue
        start, text = k, [lines[k][2:]]
        while text[-1].endswith("\\") and k + 1 < len(lines):
            k += 1
            text.append(lines[k])
        k += 1
        expected = []
        while k < len(lines) and not lines[k].startswith("$ "):
            expected.append(lines[k])
            k += 1
        while expected and not expected[-1].strip():
            expected.pop()
        code = 0
        if expected and EXIT.match(expected[-1]):
            code = int(EXIT.match(expected.pop())["code"])
        commands.append(Command(block.line + 1 + start, "\n".join(text), expected, code))
    if not commands:
        raise ValueError("a console block without a command")
    return commands


# Comparing output with the expected lines.


def _line_matcher(pattern):
    if ANY_TEXT not in pattern:
        return lambda line: line == pattern
    regex = re.compile(".*?".join(re.escape(part) for part in pattern.split(ANY_TEXT)))
    return lambda line: regex.fullmatch(line) is not None


def matches(expected, actual):
    """Whether the actual lines match the expected ones, with their elisions."""
    regex = "".join(r"(?:[^\n]*\n)*?" if line == ANY_LINES
                    else ".*?".join(re.escape(p) for p in line.split(ANY_TEXT)) + r"\n"
                    for line in expected)
    return re.fullmatch(regex, "".join(line + "\n" for line in actual)) is not None


def get_diff(expected, actual, label):
    """A unified diff of expected against actual lines, the elided lines shown as matched."""
    shown = _align(expected, actual) if len(expected) * len(actual) <= DIFF_CELLS else expected
    return "\n".join(difflib.unified_diff(shown, actual, f"expected ({label})", "actual",
                                          lineterm=""))


def _align(expected, actual):
    """The expected lines with every line that matches replaced by the line it matches.

    An edit distance over lines in which ``...`` absorbs actual lines for free and a
    pattern line costs nothing against an actual line it matches.
    """
    n, m = len(expected), len(actual)
    fits = [None if p == ANY_LINES else _line_matcher(p) for p in expected]
    cost = [[0] * (m + 1) for _ in range(n + 1)]
    for j in range(m + 1):
        cost[n][j] = m - j
    for i in range(n - 1, -1, -1):
        row, below = cost[i], cost[i + 1]
        row[m] = below[m] + (0 if fits[i] is None else 1)
        for j in range(m - 1, -1, -1):
            if fits[i] is None:
                row[j] = min(below[j], row[j + 1])
            else:
                best = min(below[j], row[j + 1]) + 1
                row[j] = min(best, below[j + 1]) if fits[i](actual[j]) else best
    shown, i, j = [], 0, 0
    while i < n:
        if fits[i] is None:
            if j < m and cost[i][j] == cost[i][j + 1]:
                shown.append(actual[j])
                j += 1
            else:
                i += 1
        elif j < m and fits[i](actual[j]) and cost[i][j] == cost[i + 1][j + 1]:
            shown.append(actual[j])
            i, j = i + 1, j + 1
        elif cost[i][j] == cost[i + 1][j] + 1:
            shown.append(expected[i])
            i += 1
        else:
            j += 1
    return shown


# Running the blocks.


def scratch_environment(root, scratch):
    """Link the checkout's inputs into the scratch directory; the environment to run in."""
    for name in sorted(os.listdir(root)):
        if name not in NOT_LINKED:
            os.symlink(os.path.join(root, name), os.path.join(scratch, name))
    for name in ("home", "tmp"):
        os.mkdir(os.path.join(scratch, ".docs-check-" + name))
    env = {k: v for k, v in os.environ.items() if not k.startswith("HRBENCH_")}
    env["PATH"] = os.pathsep.join([os.path.join(root, "build"),
                                   os.path.dirname(os.path.abspath(sys.executable)),
                                   env.get("PATH", "/usr/bin:/bin")])
    env["HOME"] = os.path.join(scratch, ".docs-check-home")
    env["TMPDIR"] = os.path.join(scratch, ".docs-check-tmp")
    env["PYTHONDONTWRITEBYTECODE"] = "1"  # no __pycache__ in the linked checkout
    return env


def run_command(text, cwd, env, timeout):
    """Run one command with bash: (merged output, exit code or None when timed out)."""
    proc = subprocess.Popen(["bash", "-c", text], cwd=cwd, env=env, stdin=subprocess.DEVNULL,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            start_new_session=True)
    try:
        output, _ = proc.communicate(timeout=timeout)
        code = proc.returncode
    except subprocess.TimeoutExpired:
        _kill_group(proc.pid)
        output, _ = proc.communicate()
        code = None
    _kill_group(proc.pid)  # what it left running in the background
    return output.decode("utf-8", errors="replace"), code


def _kill_group(pid):
    try:
        os.killpg(pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


def check_console(block, root, timeout):
    commands = parse_console(block)
    timeout = block.options.get("timeout", timeout)
    with tempfile.TemporaryDirectory(prefix="docs-check-") as scratch:
        env = scratch_environment(root, scratch)
        for command in commands:
            output, code = run_command(command.text, scratch, env, timeout)
            actual = output.split("\n")
            if actual and actual[-1] == "":
                actual.pop()
            while actual and not actual[-1].strip():
                actual.pop()
            where = f"{block.path}:{command.line}"
            if code is None:
                return (f"{where}: `{command.text}` did not end within {timeout:g} s; output "
                        "so far:\n" + "\n".join(actual))
            if not matches(command.expected, actual):
                return (f"{where}: `{command.text}` printed other output (exit code {code})\n"
                        + get_diff(command.expected, actual, where))
            if code != command.exit_code:
                return (f"{where}: `{command.text}` exited with {code}, the block says "
                        f"{command.exit_code}" + ("" if code == 0 else
                                                  f" (add [exit {code}] after its output)"))
    return ""


def check_quote(block, root):
    """The check of a block that quotes a file: None when the file does not exist."""
    if any(line.lstrip().startswith("$ ") for line in block.lines):
        return "a block that quotes a file holds a `$ ` line, which is never run"
    path = os.path.join(root, block.options["quotes"])
    if not os.path.isfile(path):
        return None
    with open(path, encoding="utf-8", errors="replace") as f:
        actual = f.read().split("\n")
    expected = [ANY_LINES, *block.lines, ANY_LINES]
    if matches(expected, actual):
        return ""
    return (f"{block.where}: not found in {block.options['quotes']}\n"
            + get_diff(expected, actual, block.where))


def check_block(block, root, timeout, require_quoted=False):
    """The outcome of one block, or None for a block with nothing to check."""
    start = time.monotonic()
    if block.error:
        return Outcome(block, "FAILED", message=f"{block.where}: {block.error}")
    if "quotes" in block.options:
        message = check_quote(block, root)
        if message is None and require_quoted:
            return Outcome(block, "FAILED", message=(
                f"{block.where}: quotes {block.options['quotes']}, which does not exist "
                "(run `make reproduce` first)"))
        if message is None:
            return Outcome(block, "not checked", message=f"quotes {block.options['quotes']}, "
                                                         "which does not exist")
        return Outcome(block, "FAILED" if message else "ok", message=message)
    if block.tag != "console":
        for k, line in enumerate(block.lines):
            if line.lstrip().startswith("$ "):
                return Outcome(block, "FAILED", message=(
                    f"{block.path}:{block.line + 1 + k}: a `$ ` line outside a console block "
                    "(a command with its output is a console block; a command alone needs "
                    "no `$ `)"))
        if block.options:
            return Outcome(block, "FAILED", message=f"{block.where}: timeout= applies only "
                                                    "to a console block")
        return None
    try:
        message = check_console(block, root, timeout)
    except ValueError as exc:
        message = f"{block.where}: {exc}"
    return Outcome(block, "FAILED" if message else "ok", time.monotonic() - start, message)


def print_outcome(outcome):
    seconds = f" ({outcome.seconds:.1f} s)" if outcome.block.tag == "console" else ""
    if outcome.status == "not checked":
        print(f"{outcome.block.where} not checked: {outcome.message}", flush=True)
        return
    print(f"{outcome.block.where} {outcome.status}{seconds}", flush=True)
    if outcome.message:
        print(outcome.message, flush=True)


def main(argv=None):
    parser = OneLineParser(
        prog="docs_check.py", description="Run the console blocks of README.md and "
        "docs/*.md and compare their output (docs/docs-check.md).")
    parser.add_argument("files", nargs="*", metavar="FILE.md",
                        help="the files to check (default: README.md and docs/*.md)")
    parser.add_argument("--root", default=ROOT,
                        help="the checkout whose files the commands read (default: this one)")
    parser.add_argument("--timeout", type=float, default=DEFAULT_TIMEOUT,
                        help="seconds each command may take (default: %(default)g)")
    parser.add_argument("--jobs", type=int, default=1, help="blocks run at once (default: 1)")
    parser.add_argument("--require-quoted", action="store_true",
                        help="fail a block whose quoted file does not exist, instead of "
                             "listing it as not checked (CI, after make reproduce)")
    args = parser.parse_args(argv)
    if args.timeout <= 0 or args.jobs < 1:
        parser.error("--timeout must be above 0 and --jobs at least 1")
    root = os.path.abspath(args.root)
    files = args.files or [os.path.join(root, "README.md"),
                           *sorted(glob.glob(os.path.join(root, "docs", "*.md")))]
    blocks = []
    for path in files:
        try:
            with open(path, encoding="utf-8") as f:
                text = f.read()
        except OSError as exc:
            parser.error(f"cannot read {path}: {exc.strerror}")
        shown = os.path.relpath(path, root) if not args.files else path
        blocks += parse_blocks(text, shown)

    counts = {"ok": 0, "FAILED": 0, "not checked": 0}
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        futures = [pool.submit(check_block, b, root, args.timeout, args.require_quoted)
                   for b in blocks]
        for future in futures:  # in file order, as each ends
            outcome = future.result()
            if outcome is not None:
                counts[outcome.status] += 1
                print_outcome(outcome)
    if counts["not checked"]:
        print(f"{counts['not checked']} not checked (the files they quote do not exist)")
    print(f"{counts['ok']} passed, {counts['FAILED']} failed")
    return 1 if counts["FAILED"] else 0


if __name__ == "__main__":
    sys.exit(main())
