import json
import re

from hrbench_analysis.reproduce import main


def run(argv, capsys):
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def test_report_is_written_and_claim_reproduced(tmp_path, data_dir, fake_hrbench, capsys):
    results = tmp_path / "results"
    code, out, err = run(["--claims", str(data_dir / "small_claims.toml"), "--hrbench",
                          str(fake_hrbench), "--results", str(results), "--jobs", "2"], capsys)
    assert code == 0, err
    assert "T-elements" in out and "reproduced" in out
    # The tally closes the output; the table and the reasons fit 100 columns.
    lines = out.splitlines()
    assert lines[-1] == ("1 claim: reproduced 1, refuted 0, inconclusive 0, measured 0; "
                         "not as expected: none")
    assert all(len(line) <= 100 for line in lines if not line.startswith("report: "))
    for name in ("report.md", "report.html", "claims.json", "hrbench.sqlite",
                 "plots/tiling.png", "explorer.html"):
        assert (results / name).exists(), name
    claims = json.loads((results / "claims.json").read_text())["claims"]
    (obj,) = claims
    for key in ("id", "statement", "source", "expected_exponent", "measured_exponent",
                "interval_low", "interval_high", "verdict", "reason"):
        assert key in obj
    assert obj["verdict"] == "reproduced"
    assert obj["interval_low"] <= obj["measured_exponent"] <= obj["interval_high"]
    html = (results / "report.html").read_text()
    assert html.count("data:image/png;base64,") >= 3
    assert f"<b>{lines[-1]}</b>" in html
    assert f"**{lines[-1]}**" in (results / "report.md").read_text()
    # summary.txt keeps what the terminal showed: the table, the reasons and the tally.
    shown = [line for line in lines if not line.startswith("report: ")]
    assert (results / "summary.txt").read_text().splitlines() == shown
    assert obj["kind"] == "stated" and obj["alternatives"] and obj["can_fail"] is True


def test_refuted_claim_expected_to_hold_exits_1(tmp_path, data_dir, fake_hrbench, capsys):
    code, out, err = run(["--claims", str(data_dir / "false_claim.toml"), "--hrbench",
                          str(fake_hrbench), "--results", str(tmp_path), "--no-tiling"],
                         capsys)
    assert code == 1
    assert "refuted" in out and "F-cubic" in err


def test_refuted_claim_expected_not_to_hold_exits_0(tmp_path, data_dir, fake_hrbench,
                                                     capsys):
    claims = tmp_path / "c.toml"
    claims.write_text((data_dir / "false_claim.toml").read_text()
                      + "expected_to_hold = false\n")
    code, out, _ = run(["--claims", str(claims), "--hrbench", str(fake_hrbench),
                        "--results", str(tmp_path), "--no-tiling"], capsys)
    assert code == 0 and "refuted" in out


def test_short_sweep_is_inconclusive_and_exits_0(tmp_path, data_dir, fake_hrbench, capsys):
    code, out, _ = run(["--claims", str(data_dir / "short_claim.toml"), "--hrbench",
                        str(fake_hrbench), "--results", str(tmp_path), "--no-tiling"], capsys)
    assert code == 0
    assert "inconclusive" in out and "too few" in out


def test_failed_points_show_in_the_report(tmp_path, data_dir, fake_hrbench, capsys,
                                          monkeypatch):
    monkeypatch.setenv("FAKE_HRBENCH_FAIL_BELOW_EPS", "0.05")
    code, out, _ = run(["--claims", str(data_dir / "small_claims.toml"), "--hrbench",
                        str(fake_hrbench), "--results", str(tmp_path), "--no-tiling"], capsys)
    assert code == 0
    md = (tmp_path / "report.md").read_text()
    assert md.count("FAILED point") == 4 and "exit code 3" in md
    obj = json.loads((tmp_path / "claims.json").read_text())["claims"][0]
    assert len(obj["failed_points"]) == 4


def test_malformed_claims_file_exits_2_naming_file_and_line(tmp_path, data_dir,
                                                            fake_hrbench, capsys):
    code, _, err = run(["--claims", str(data_dir / "bad_values.toml"), "--hrbench",
                        str(fake_hrbench), "--results", str(tmp_path)], capsys)
    assert code == 2
    assert "bad_values.toml:25" in err and "V-bad" in err and "expected_exponent" in err


def test_missing_engine_exits_2(tmp_path, data_dir, capsys):
    code, _, err = run(["--claims", str(data_dir / "small_claims.toml"), "--hrbench",
                        str(tmp_path / "nope"), "--results", str(tmp_path)], capsys)
    assert code == 2 and "not found" in err


def test_usage_errors_exit_2(capsys):
    assert main(["--quick", "--full"]) == 2
    assert main(["--jobs", "0"]) == 2
    assert "--jobs must be at least 1" in capsys.readouterr().err


def test_figures_render_the_same_bytes_on_several_processes():
    from matplotlib.figure import Figure

    from hrbench_analysis.report.figure import ReportFigure, render_pngs

    figures = []
    for k in range(3):
        fig = Figure(figsize=(2, 2))
        fig.add_subplot().plot([0, 1, 2], [0, k, 2 * k])
        figures.append(ReportFigure(f"f{k}", f"figure {k}", "", fig))
    serial = render_pngs(figures, jobs=1)
    assert [png[:8] for png in serial] == [b"\x89PNG\r\n\x1a\n"] * 3
    assert len(set(serial)) == 3  # three different pictures, in order
    assert render_pngs(figures, jobs=2) == serial


def test_no_pictures_draws_no_figure_and_charts_only_no_runs_of_their_own(
        tmp_path, data_dir, fake_hrbench, capsys):
    claims = str(data_dir / "small_claims.toml")
    bare, charts = tmp_path / "bare", tmp_path / "charts"
    code, _, err = run(["--claims", claims, "--hrbench", str(fake_hrbench), "--results",
                        str(bare), "--no-pictures"], capsys)
    assert code == 0, err
    assert not list(bare.glob("plots/*.png")) and not (bare / "explorer.html").exists()
    assert "![" not in (bare / "report.md").read_text()
    assert "rendering 0 figures" in err and "drawing the charts" not in err
    code, _, err = run(["--claims", claims, "--hrbench", str(fake_hrbench), "--results",
                        str(charts), "--charts-only"], capsys)
    assert code == 0, err
    assert {p.name for p in charts.glob("plots/*.png")} == {"chart-t-elements.png",
                                                            "slopes-t-elements.png"}
    assert not (charts / "explorer.html").exists() and "solving" not in err


def test_every_stage_after_the_sweep_says_when_it_starts_and_ends(tmp_path, data_dir,
                                                                   fake_hrbench, capsys):
    code, out, err = run(["--claims", str(data_dir / "small_claims.toml"), "--hrbench",
                          str(fake_hrbench), "--results", str(tmp_path / "r")], capsys)
    assert code == 0, err
    for stage in ("fitting 1 claims", "listing the links of the tiling figure",
                  "drawing the charts", "writing the explorer page"):
        assert f"{stage} ...\n" in err and f"{stage}: done in " in err, stage
    # The fake engine cannot solve: the stage starts, and a warning ends it.
    assert "solving for the profile figure ...\nwarning: no profile figure" in err
    assert re.search(r"rendering \d+ figures and writing the report: done in ", err)
    # The report line names what its times time.
    assert re.search(r"\(sweep \d+\.\d s, then fits, figures and report \d+\.\d s: "
                     r"\d+\.\d s of wall time in all\)", out)
