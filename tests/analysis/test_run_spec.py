"""hrbench_analysis.engine.RunSpec: one value for a run, its cache key and every command
line derived from it."""

import pytest

from hrbench_analysis.engine import (
    RunSpec,
    links_argv,
    run_argv,
    save_argv,
    solve_argv,
    sweep_argv,
)
from hrbench_analysis.lemmas import STATISTICS_MODE, StatisticsJob

RUN = RunSpec.of("parallel", {"l": 8, "d": 1}, 0.05, "garmann", min_area=1e-6, max_depth=30,
                 options={"rays_per_side": 4, "triangulate": True, "method": "enumerate"})


def test_the_key_text_is_the_cache_key_of_before():
    # The key of a cached point: a change of this text would orphan every cache.
    assert RUN.key("0.1.0").text() == (
        '{"eps": "0.05", "max_depth": 30, "min_area": "1e-06", "mode": "count-only", '
        '"options": {"method": "enumerate", "rays_per_side": "4", "triangulate": "true"}, '
        '"oracle": "garmann", "params": {"d": "1.0", "l": "8.0"}, "scene": "parallel", '
        '"version": "0.1.0"}')
    assert RUN.key("0.1.0", STATISTICS_MODE).mode == STATISTICS_MODE


def test_a_mesh_is_its_path_on_the_command_line_and_its_bytes_in_the_key():
    run = RunSpec.of("mesh", {}, 0.1, "bf", options={"mesh": "box.obj", "clusters": True},
                     command="solve", mesh_sha256="ab" * 32)
    assert run.argv("hrbench") == ["hrbench", "solve", "--eps", "0.1", "--oracle", "bf",
                                   "--clusters", "--mesh", "box.obj", "--json"]
    key = run.key("v")
    assert key.mode == "solve"
    assert key.options == (("clusters", "true"), ("mesh", "sha256:" + "ab" * 32))


def test_every_command_line_comes_from_the_same_run():
    words = ["python3", "engine.py"]
    common = ["parallel", "d=1", "l=8", "--eps", "0.05", "--oracle", "garmann", "--min-area",
              "1e-06", "--max-depth", "30", "--method", "enumerate", "--rays-per-side", "4",
              "--triangulate"]
    assert RUN.argv(words) == [*words, "run", *common, "--count-only", "--json"]
    assert RUN.links_argv(words, "l.csv") == [*words, "links", *common, "--out", "l.csv"]
    assert RUN.save_argv(words) == [*words, "save", "parallel", "d=1", "l=8"]
    assert RUN.save_argv(words, ("triangulate",)) == [*words, "save", "parallel", "d=1",
                                                       "l=8", "--triangulate"]
    # The functions of loose values give the same command lines.
    loose = ({"l": 8, "d": 1}, 0.05, "garmann")
    limits = {"min_area": 1e-6, "max_depth": 30, "options": dict(RUN.options)}
    assert run_argv(words, "parallel", *loose, **limits) == RUN.argv(words)
    assert solve_argv(words, "parallel", *loose, **limits) == [
        *words, "solve", *common, "--json"]
    assert links_argv(words, "parallel", loose[0], 0.05, "l.csv", **limits) == \
        RUN.links_argv(words, "l.csv")
    assert save_argv(words, "parallel", loose[0]) == RUN.save_argv(words)
    # The statistics of a point: its scene and its links, less the method.
    job = StatisticsJob.of(RUN, words)
    assert job.save_argv == tuple(RUN.save_argv(words))
    assert "--method" not in job.links_argv
    assert job.links_argv == tuple(RUN.without_options("method").links_argv(words))


@pytest.mark.parametrize("param, flag", [("eps", "--eps"), ("min_area", "--min-area")])
def test_a_series_differing_in_the_swept_value_shares_one_run(param, flag):
    run = RUN.without_options("method")
    series = [RunSpec.of("parallel", {"l": 8, "d": 1}, **{
        "eps": 0.05, "oracle": "garmann", "min_area": 1e-6, "max_depth": 30,
        "options": dict(run.options), param: value}) for value in (0.5, 0.25)]
    shared = {r.shared("hrbench", param) for r in series}
    assert len(shared) == 1
    (one,) = shared
    argv = series[0].argv("hrbench")
    at = argv.index(flag)
    assert one.argv([0.5, 0.25]) == [*argv[:at], *argv[at + 2:-2], "--sweep",
                                     f"{param}=0.5,0.25", "--count-only", "--json"]
    assert one.argv() == [*argv[:at], *argv[at + 2:-2], "--sweep", param, "--count-only",
                          "--json"]
    assert sweep_argv("hrbench", "parallel", {"l": 8, "d": 1}, 0.05, "garmann",
                      (param, [0.5, 0.25]), min_area=1e-6, max_depth=30,
                      options=dict(run.options)) == one.argv([0.5, 0.25])


def test_bad_values_are_named():
    with pytest.raises(TypeError, match="params must be a dict"):
        RunSpec.of("parallel", [("l", 8)], 0.1)
    with pytest.raises(TypeError, match=r"options\['x'\] must be"):
        RunSpec.of("parallel", {}, 0.1, options={"x": None})
    with pytest.raises(ValueError, match="command must be one of"):
        RunSpec.of("parallel", {}, 0.1, command="links")
