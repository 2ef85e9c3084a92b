"""Scene identity: an outside engine's scene_sha256 against hrbench's own
(docs/engine-contract.md#scene-identity). hrbench is build/hrbench under the repository root."""

import json
import sqlite3
import subprocess
from pathlib import Path

import pytest

from hrbench_analysis.reproduce import main
from hrbench_analysis.scene_identity import reference_engine

HRBENCH = Path("build") / "hrbench"


def run(argv, capsys):
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def reproduce(tmp_path, data_dir, fake_hrbench, capsys):
    return run(["--claims", str(data_dir / "short_claim.toml"), "--hrbench", str(fake_hrbench),
                "--results", str(tmp_path / "results"), "--no-pictures"], capsys)


def hrbench_digest(*scene):
    out = subprocess.run([str(HRBENCH), "save", *scene], check=True, capture_output=True,
                         text=True).stdout
    return json.loads(out)["scene_sha256"]


pytestmark = pytest.mark.skipif(not HRBENCH.exists(), reason="needs build/hrbench")


def test_the_documented_digest_agrees_with_hrbench(tmp_path, data_dir, fake_hrbench, capsys,
                                                   monkeypatch):
    # The fake engine computes the digest from docs/scene-format.md in Python: hrbench
    # gives the same, so the claim is judged.
    monkeypatch.setenv("FAKE_HRBENCH_SCENE_SHA256", "canonical")
    code, out, err = reproduce(tmp_path, data_dir, fake_hrbench, capsys)
    assert code == 0, err
    assert "S-short" in out
    assert "error" not in err
    # The agreement is said, not left to be inferred from silence.
    assert "scenes: the engine's scene_sha256 agrees with hrbench's for 1 scene\n" in err


def test_a_run_on_other_geometry_is_refused(tmp_path, data_dir, fake_hrbench, capsys,
                                            monkeypatch):
    monkeypatch.setenv("FAKE_HRBENCH_SCENE_SHA256", "0" * 64)
    code, _, err = reproduce(tmp_path, data_dir, fake_hrbench, capsys)
    assert code == 2
    line = [x for x in err.splitlines() if "scene_sha256" in x]
    assert len(line) == 1
    expected = hrbench_digest("parallel", "d=1", "l=8")
    assert (f"claim 'S-short': the engine refined other patches than hrbench for parallel d=1 "
            f"l=8 (first at eps=0.5): scene_sha256 {'0' * 64} (engine) differs from "
            f"{expected} (hrbench build/hrbench save)") in line[0]
    # Refused once the claim's first point was stored: of its 8 points, that one ran and
    # at most one more, started beside it on the second job.
    assert line[0].endswith("found on the claim's first point, which the sweep ran first, "
                            "and the sweep stopped there")
    with sqlite3.connect(tmp_path / "results" / "hrbench.sqlite") as db:
        assert db.execute("SELECT count(*) FROM points").fetchone()[0] <= 2
        assert db.execute("SELECT count(*) FROM leases").fetchone()[0] == 0


def test_an_engine_without_digests_is_said_to_go_unchecked(tmp_path, data_dir, fake_hrbench,
                                                           capsys):
    code, _, err = reproduce(tmp_path, data_dir, fake_hrbench, capsys)
    assert code == 0, err
    assert ("scenes: the engine reports no scene_sha256: its scenes are not checked against "
            "hrbench's") in err


def test_without_hrbench_the_check_is_skipped_with_a_warning(tmp_path, data_dir, fake_hrbench,
                                                             capsys, monkeypatch):
    claims = (data_dir / "short_claim.toml").resolve()
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("PATH", str(tmp_path))
    monkeypatch.setenv("FAKE_HRBENCH_SCENE_SHA256", "0" * 64)
    code, _, err = run(["--claims", str(claims), "--hrbench", str(fake_hrbench),
                        "--results", str(tmp_path / "results"), "--no-pictures"], capsys)
    assert code == 0, err
    assert ("the engine reports scene_sha256, but no hrbench (build/hrbench, or hrbench on the "
            "PATH) is at hand to compare it with; the scene is not checked") in err


def test_hrbench_reports_the_digest_in_run_solve_and_save():
    digest = hrbench_digest("parallel3d")
    for command in (["run", "parallel3d", "--eps", "0.5", "--json"],
                    ["solve", "parallel3d", "--eps", "0.5", "--emission", "1", "--json"]):
        out = subprocess.run([str(HRBENCH), *command], check=True, capture_output=True,
                             text=True).stdout
        assert json.loads(out)["scene_sha256"] == digest
    assert digest == "08f184efc2701867f8585bb1ccb33c2ce1dadb3a79a7f8973ab01e357f36a6e4"


def test_hrbench_itself_is_not_checked_against_itself(tmp_path, data_dir, capsys):
    # The engine is build/hrbench: nothing to compare, and nothing to warn about.
    assert reference_engine(str(HRBENCH)) == (str(HRBENCH), True)
    assert reference_engine(["python3", "engine.py"]) == (str(HRBENCH), False)
    code, out, err = run(["--claims", str(data_dir / "short_claim.toml"), "--hrbench",
                          str(HRBENCH), "--results", str(tmp_path / "results"),
                          "--no-pictures"], capsys)
    assert code == 0, err
    assert "scene_sha256" not in err
