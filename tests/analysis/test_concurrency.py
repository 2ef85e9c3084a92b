"""Two sweeps on one cache at the same time share the work: every point runs once."""

import json
import os
import re
import sqlite3
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_two_sweeps_on_one_cache_run_every_point_exactly_once(tmp_path, data_dir,
                                                              fake_hrbench):
    cache = tmp_path / "shared.sqlite"
    log = tmp_path / "runs.log"
    # Slow enough runs (0.5 s each, 11 points, 2 jobs each) that the sweeps overlap.
    env = dict(os.environ, FAKE_HRBENCH_DELAY="0.5", FAKE_HRBENCH_LOG=str(log),
               PYTHONPATH=str(ROOT))
    procs = []
    for name in ("a", "b"):
        argv = [sys.executable, "-m", "hrbench_analysis.reproduce", "--claims",
                str(data_dir / "small_claims.toml"), "--hrbench", str(fake_hrbench),
                "--results", str(tmp_path / name), "--cache", str(cache), "--jobs", "2",
                "--no-tiling"]
        procs.append(subprocess.Popen(argv, env=env, cwd=ROOT, stdout=subprocess.PIPE,
                                      stderr=subprocess.PIPE, text=True))
    outputs = [proc.communicate(timeout=120) for proc in procs]
    for proc, (_, err) in zip(procs, outputs, strict=True):
        assert proc.returncode == 0, err

    # Every point ran exactly once, over both sweeps.
    runs = log.read_text().splitlines()
    assert len(runs) == 11 and len(set(runs)) == 11
    ran = []
    for name in ("a", "b"):
        context = json.loads((tmp_path / name / "claims.json").read_text())["context"]
        match = re.fullmatch(r"11 \((\d+) cached, (\d+) run, 0 failed\)", context["points"])
        assert match, context["points"]
        ran.append(int(match.group(2)))
    assert sum(ran) == 11 and min(ran) > 0, ran     # both did part of the work

    # Both judged the same points the same way, and the cache is whole and unleased.
    claims = [json.loads((tmp_path / name / "claims.json").read_text())["claims"]
              for name in ("a", "b")]
    assert claims[0] == claims[1] and claims[0][0]["verdict"] == "reproduced"
    with sqlite3.connect(cache) as con:
        assert con.execute("PRAGMA integrity_check").fetchone()[0] == "ok"
        rows = con.execute("SELECT key, ok FROM points").fetchall()
        assert con.execute("SELECT COUNT(*) FROM leases").fetchone()[0] == 0
    assert len(rows) == 11 and all(ok for _, ok in rows)
