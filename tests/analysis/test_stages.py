"""Progress lines of long stages (hrbench_analysis.stages)."""

import io
import time

from hrbench_analysis.stages import Stage


def test_a_stage_prints_its_start_a_line_while_it_runs_and_its_end():
    out = io.StringIO()
    with Stage("solving", stream=out, every=0.05) as stage:
        time.sleep(0.3)
    lines = out.getvalue().splitlines()
    assert lines[0] == "solving ..." and lines[-1].startswith("solving: done in ")
    # A thread prints while the block waits (on one engine run, say): 0.3 s at 0.05 s.
    assert sum(line.startswith("solving: ") for line in lines[1:-1]) >= 3
    assert stage.seconds >= 0.3


def test_without_a_thread_the_steps_print_and_count():
    out = io.StringIO()
    with Stage("rendering 3 figures", total=3, stream=out, every=0.0, beat=False) as stage:
        for _ in range(3):
            stage.advance()
    lines = out.getvalue().splitlines()
    assert [line.split(", ")[0] for line in lines[1:4]] == [
        "rendering 3 figures: 1/3", "rendering 3 figures: 2/3", "rendering 3 figures: 3/3"]


def test_a_failed_stage_does_not_say_done_and_a_log_takes_the_lines():
    said = []
    try:
        with Stage("building", log=said.append, detail=lambda: "step 3/9", every=0.02):
            time.sleep(0.1)
            raise ValueError("failed")
    except ValueError:
        pass
    assert said[0] == "building ..." and not any("done" in line for line in said)
    assert any(line.startswith("building: step 3/9, ") for line in said[1:])
