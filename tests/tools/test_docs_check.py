"""Tests of tools/docs_check.py: console blocks run and compared, elisions, exit codes,
timeouts, and `$ ` lines outside console blocks, on small Markdown files in a scratch
checkout; then one real page of the docs against the engine of this checkout."""

import importlib.util
import os
import time

import pytest

from conftest import ROOT, TOOLS

FENCE = "```"


def load_docs_check():
    """tools/docs_check.py as a module (it is a script, not part of a package)."""
    spec = importlib.util.spec_from_file_location("docs_check_under_test",
                                                  os.path.join(TOOLS, "docs_check.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


docs_check = load_docs_check()


def check(tmp_path, capsys, text, *options):
    """Run the check on one page holding `text` in the checkout tmp_path: (exit code, output)."""
    page = tmp_path / "page.md"
    page.write_text(text)
    code = docs_check.main([str(page), "--root", str(tmp_path), *options])
    return code, capsys.readouterr().out


def console(*lines, marker=""):
    comment = [f"<!-- docs-check: {marker} -->"] if marker else [""]
    return "\n".join(["Some prose.", *comment, FENCE + "console", *lines, FENCE, ""])


PASSING = console("$ printf 'nodes 1022\\nlinks 5092\\n'", "nodes 1022", "links 5092")


class TestConsoleBlocks:
    def test_a_block_whose_output_matches_passes(self, tmp_path, capsys):
        code, out = check(tmp_path, capsys, PASSING)
        assert code == 0
        assert f"{tmp_path / 'page.md'}:3 ok (" in out
        assert out.splitlines()[-1] == "1 passed, 0 failed"

    def test_one_digit_changed_fails_naming_the_line_with_a_diff(self, tmp_path, capsys):
        code, out = check(tmp_path, capsys, PASSING.replace("links 5092\n", "links 5093\n"))
        assert code == 1
        assert f"{tmp_path / 'page.md'}:3 FAILED" in out
        assert f"{tmp_path / 'page.md'}:4: `printf" in out  # the command's line
        assert "-links 5093" in out and "+links 5092" in out
        assert " nodes 1022" in out  # the line that matches is context, not a change
        assert out.splitlines()[-1] == "0 passed, 1 failed"

    def test_output_is_stdout_and_stderr_in_order(self, tmp_path, capsys):
        text = console("$ echo one; echo two >&2; echo three", "one", "two", "three")
        assert check(tmp_path, capsys, text)[0] == 0

    def test_commands_share_their_directory_which_is_not_the_checkout(self, tmp_path, capsys):
        (tmp_path / "input.txt").write_text("from the checkout\n")
        text = console("$ cat input.txt > copy.txt", "$ cat copy.txt", "from the checkout")
        assert check(tmp_path, capsys, text)[0] == 0
        assert not (tmp_path / "copy.txt").exists()

    def test_a_continued_command_runs_as_one(self, tmp_path, capsys):
        text = console("$ echo a \\", "    b", "a b")
        assert check(tmp_path, capsys, text)[0] == 0


class TestElision:
    @pytest.mark.parametrize("actual", [[], ["x"], ["x", "y", "z"]])
    def test_a_dots_line_matches_zero_or_more_lines(self, actual):
        assert docs_check.matches(["first", "...", "last"], ["first", *actual, "last"])

    def test_elided_text_stays_within_its_line(self):
        assert docs_check.matches(["seconds [...] (cpu [...])"], ["seconds 0.0012 (cpu 0.001)"])
        assert docs_check.matches(["a[...]b"], ["ab"])
        assert not docs_check.matches(["a[...]b"], ["a", "b"])

    def test_nothing_else_varies(self):
        assert not docs_check.matches(["links 5092"], ["links 5093"])
        assert not docs_check.matches(["links [...] of 5092"], ["links 3 of 5093"])
        assert not docs_check.matches(["links..."], ["links 5092"])  # `...` inside a line
        assert not docs_check.matches(["a", "...", "b"], ["a", "x"])
        assert not docs_check.matches(["links"], ["links", "extra"])

    def test_elided_block_passes_and_changed_digit_outside_fails(self, tmp_path, capsys):
        lines = ["$ printf 'time 1.5 s\\nlinks 5092\\nmore\\nend\\n'", "time [...] s",
                 "links 5092", "...", "end"]
        assert check(tmp_path, capsys, console(*lines))[0] == 0
        lines[2] = "links 5093"
        code, out = check(tmp_path, capsys, console(*lines))
        assert code == 1 and "-links 5093" in out
        assert "-time [...] s" not in out  # a line that matches is shown as matched


class TestExitCodes:
    def test_the_exit_code_a_block_states_is_required(self, tmp_path, capsys):
        assert check(tmp_path, capsys, console("$ echo no; exit 3", "no", "[exit 3]"))[0] == 0
        code, out = check(tmp_path, capsys, console("$ echo no; exit 3", "no", "[exit 2]"))
        assert code == 1 and "exited with 3, the block says 2" in out

    def test_a_non_zero_exit_code_fails_when_the_block_states_none(self, tmp_path, capsys):
        code, out = check(tmp_path, capsys, console("$ false"))
        assert code == 1 and "exited with 1, the block says 0" in out

    def test_the_first_command_that_fails_ends_the_block(self, tmp_path, capsys):
        code, out = check(tmp_path, capsys, console("$ false", "$ echo never", "never"))
        assert code == 1 and "echo never" not in out


class TestTimeout:
    def test_a_command_that_hangs_is_stopped(self, tmp_path, capsys):
        start = time.monotonic()
        text = console("$ echo started; sleep 60 & sleep 60", "started", marker="timeout=0.5")
        code, out = check(tmp_path, capsys, text)
        assert code == 1 and "did not end within 0.5 s" in out and "started" in out
        assert time.monotonic() - start < 20  # the background sleep was killed too

    def test_the_default_timeout_is_an_option(self, tmp_path, capsys):
        code, out = check(tmp_path, capsys, console("$ sleep 60"), "--timeout", "0.5")
        assert code == 1 and "did not end within 0.5 s" in out


class TestBlocksNotRun:
    def test_a_dollar_line_outside_a_console_block_is_reported(self, tmp_path, capsys):
        text = "Text.\n\n```sh\nmake build\n$ build/hrbench scenes\nparallel\n```\n"
        code, out = check(tmp_path, capsys, text)
        assert code == 1
        assert f"{tmp_path / 'page.md'}:5: a `$ ` line outside a console block" in out

    def test_commands_without_output_need_no_check(self, tmp_path, capsys):
        code, out = check(tmp_path, capsys, "```sh\nmake build\n```\n")
        assert code == 0 and out.splitlines()[-1] == "0 passed, 0 failed"

    def test_a_quoted_report_is_compared_once_it_exists(self, tmp_path, capsys):
        text = ("<!-- docs-check: quotes=results/summary.txt -->\n```\n"
                "3 claims: reproduced [...]\nC1 ok\n```\n")
        code, out = check(tmp_path, capsys, text)
        assert code == 0 and "not checked: quotes results/summary.txt" in out
        (tmp_path / "results").mkdir()
        (tmp_path / "results" / "summary.txt").write_text("report\n3 claims: reproduced 3\n"
                                                          "C1 ok\nC2 ok\n")
        assert check(tmp_path, capsys, text)[0] == 0
        (tmp_path / "results" / "summary.txt").write_text("3 claims: reproduced 3\nC1 no\n")
        code, out = check(tmp_path, capsys, text)
        assert code == 1 and "-C1 ok" in out

    def test_a_missing_quoted_file_fails_where_it_is_required(self, tmp_path, capsys):
        text = "<!-- docs-check: quotes=results/summary.txt -->\n```\nC1 ok\n```\n"
        code, out = check(tmp_path, capsys, text, "--require-quoted")
        assert code == 1 and "which does not exist (run `make reproduce` first)" in out

    def test_bad_markers_fail(self, tmp_path, capsys):
        code, out = check(tmp_path, capsys, console("$ true", marker="skip"))
        assert code == 1 and "unknown docs-check option 'skip'" in out
        code, out = check(tmp_path, capsys, "<!-- docs-check: timeout=5 -->\n\nProse.\n")
        assert code == 1 and "not followed by a fenced block" in out


class TestUsage:
    def test_usage_errors_exit_2(self, tmp_path):
        with pytest.raises(SystemExit) as exc:
            docs_check.main([str(tmp_path / "missing.md")])
        assert exc.value.code == 2
        with pytest.raises(SystemExit) as exc:
            docs_check.main(["--timeout", "0"])
        assert exc.value.code == 2


def test_a_real_page_passes(capsys):
    """docs/dump-paths.md, whose blocks run the engine of this checkout in well under a second."""
    if not os.path.exists(os.path.join(ROOT, "build", "hrbench")):
        pytest.skip("build/hrbench is not built")
    assert docs_check.main([os.path.join(ROOT, "docs", "dump-paths.md")]) == 0, \
        capsys.readouterr().out
