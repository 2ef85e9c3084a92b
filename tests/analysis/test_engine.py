"""hrbench_analysis.engine: capabilities, checks of claims against them, command lines, processes.

The capabilities come from the fake engine (``data/fake_hrbench.py``, its own families
and oracles) or from a document written here after the format's specification.
"""

import copy
import json
from pathlib import Path
from types import SimpleNamespace

import pytest

from hrbench_analysis.claimfile import missing_capability, oracle_error
from hrbench_analysis.engine import (
    CapabilitiesError,
    EngineError,
    find_engine,
    format_number,
    get_capabilities,
    links_argv,
    option_argv,
    parse_capabilities,
    run_argv,
    run_engine,
    run_links,
)
from hrbench_analysis.reproduce import main

HRBENCH = Path(__file__).resolve().parents[2] / "build" / "hrbench"
needs_engine = pytest.mark.skipif(not HRBENCH.exists(), reason="build/hrbench not built")

#: A capabilities document as the format's specification shows it (shortened).
SPEC = {
    "schema_version": 1,
    "engine": "hrbench",
    "version": "0.3.0",
    "run_schema_version": 1,
    "commands": [{"name": "run", "doc": "count"}, {"name": "links", "doc": "list links"},
                 {"name": "capabilities", "doc": "this"}],
    "families": [
        {"name": "parallel", "dimension": 2, "doc": "two facing plates",
         "params": [{"name": "l", "default": 64.0, "default_from": None, "low": 0.0,
                     "high": None, "low_open": True, "high_open": False, "integer": False,
                     "doc": "length of plate P"},
                    {"name": "l2", "default": None, "default_from": "l", "low": 0.0,
                     "high": None, "low_open": True, "high_open": False, "integer": False,
                     "doc": "length of plate Q"}]},
        {"name": "enclosure", "dimension": 2, "doc": "n-gon",
         "params": [{"name": "n", "default": 6, "default_from": None, "low": 3,
                     "high": 100000, "low_open": False, "high_open": False, "integer": True,
                     "doc": "walls"}]},
        {"name": "parallel3d", "dimension": 3, "doc": "two rectangles", "params": []},
    ],
    "oracles": [{"name": "garmann", "dimensions": [2, 3], "parameters": ["eps"], "doc": "g"},
                {"name": "hanrahan", "dimensions": [2], "parameters": ["eps"], "doc": "h"}],
    "methods": [{"name": "enumerate", "doc": "e"}, {"name": "translation", "doc": "t"}],
    "options": [{"name": "eps", "flag": "--eps", "value": "E", "choices": None,
                 "commands": ["run", "links"], "doc": "threshold"},
                {"name": "method", "flag": "--method", "value": "M",
                 "choices": ["enumerate", "translation"], "commands": ["run"], "doc": "m"},
                {"name": "json", "flag": "--json", "value": None, "choices": None,
                 "commands": ["run", "capabilities"], "doc": "JSON"}],
    "counters": [{"name": "nodes", "kind": "scalar", "category": "tree", "unit": "elements",
                  "doc": "every element"},
                 {"name": "links", "kind": "scalar", "category": "links", "unit": "links",
                  "doc": "linked pairs"},
                 {"name": "nodes_per_depth", "kind": "histogram", "category": "tree",
                  "unit": "elements", "doc": "per depth"},
                 {"name": "rays", "kind": "scalar", "category": "visibility", "unit": "rays",
                  "doc": "cast"}],
    "a_later_key": "ignored",
}


def claim(scene="parallel", oracle="garmann", params=None, options=None):
    """A stand-in for a Claim: what the checks read (options sorted, as Claim gives them)."""
    return SimpleNamespace(scene=scene, oracle=oracle, params=params or {},
                           options_for=lambda mode: dict(sorted((options or {}).items())))


# --- The capabilities --------------------------------------------------------------------


def test_spec_document_is_read_field_by_field():
    caps = parse_capabilities(json.dumps(SPEC))
    assert (caps.schema_version, caps.engine, caps.version, caps.run_schema_version) == (
        1, "hrbench", "0.3.0", 1)
    assert caps.command_names == ("run", "links", "capabilities")
    assert caps.commands[1].doc == "list links"

    assert caps.family_names == ("parallel", "enclosure", "parallel3d")
    parallel = caps.family("parallel")
    assert parallel.dimension == 2 and parallel.doc == "two facing plates"
    assert parallel.param_names == ("l", "l2")
    length, length2 = parallel.params
    assert (length.default, length.default_from, length.low, length.high) == (
        64.0, None, 0.0, None)
    assert (length.low_open, length.high_open, length.integer) == (True, False, False)
    assert length.doc == "length of plate P"
    assert length2.default is None and length2.default_from == "l"
    walls = caps.family("enclosure").params[0]
    assert walls.integer and (walls.low, walls.high) == (3, 100000)
    assert caps.family("parallel3d").dimension == 3 and caps.family("parallel3d").params == ()
    assert caps.family("room") is None

    assert caps.oracle_names == ("garmann", "hanrahan")
    assert caps.oracle("garmann").dimensions == (2, 3)
    assert caps.oracle("hanrahan").dimensions == (2,)
    assert caps.oracle("hanrahan").parameters == ("eps",)
    assert caps.oracle("bf") is None

    assert caps.method_names == ("enumerate", "translation")
    method = caps.option("method")
    assert (method.flag, method.value, method.choices, method.commands) == (
        "--method", "M", ("enumerate", "translation"), ("run",))
    assert not method.is_switch and caps.option("json").is_switch
    assert caps.option("eps").choices is None and caps.option("visibility") is None

    assert caps.scalar_counters == ("nodes", "links", "rays")
    assert caps.histogram_counters == ("nodes_per_depth",)
    rays = caps.counters[-1]
    assert (rays.name, rays.kind, rays.category, rays.unit, rays.doc) == (
        "rays", "scalar", "visibility", "rays", "cast")


def test_fake_engine_lists_its_own_capabilities(fake_hrbench):
    caps = get_capabilities(fake_hrbench)
    assert caps.version == "0.0.1" and caps.run_schema_version == 1
    assert caps.family_names == ("parallel", "box3d")
    assert caps.family("parallel").param_names == ("l", "d", "offset", "l2")
    assert caps.oracle_names == ("garmann", "hanrahan")
    assert caps.scalar_counters[:3] == ("nodes", "leaves", "links")
    assert caps.histogram_counters == ("nodes_per_depth", "links_per_depth")
    assert caps.option("out").commands == ("links",)


def _broken(change):
    doc = copy.deepcopy(SPEC)
    change(doc)
    return json.dumps(doc)


@pytest.mark.parametrize("text, match", [
    ("hrbench: usage", "'capabilities --json' is not valid JSON"),
    ("[1, 2]", "did not print a JSON object"),
    (_broken(lambda d: d.update(schema_version=2)), "schema_version 2; this analysis reads 1"),
    (_broken(lambda d: d.pop("counters")), "capabilities: missing key 'counters'"),
    (_broken(lambda d: d["counters"][0].update(kind="matrix")),
     r"counters\[0\]\.kind must be one of 'scalar', 'histogram', got 'matrix'"),
    (_broken(lambda d: d["families"][0].update(dimension=4)),
     r"families\[0\]\.dimension must be 2 or 3, got 4"),
    (_broken(lambda d: d["families"][0]["params"][0].update(low="0")),
     r"families\[0\]\.params\[0\]\.low must be a number or null, got '0'"),
    (_broken(lambda d: d["oracles"].append(dict(d["oracles"][0]))),
     r"oracles\[2\]: duplicate name 'garmann'"),
    (_broken(lambda d: d["options"][1].update(choices="enumerate")),
     r"options\[1\]\.choices must be a list or null"),
    (_broken(lambda d: d["oracles"][0].update(dimensions=[2, "3"])),
     r"oracles\[0\]\.dimensions must list 2 and/or 3"),
])
def test_malformed_capabilities_are_one_line_errors_naming_the_engine(text, match):
    with pytest.raises(CapabilitiesError, match=match) as info:
        parse_capabilities(text, engine="build/hrbench")
    message = str(info.value)
    assert message.startswith("engine build/hrbench: ") and "\n" not in message


def test_engine_without_capabilities_command(fake_hrbench, monkeypatch):
    monkeypatch.setenv("FAKE_HRBENCH_CAPABILITIES", "missing")
    with pytest.raises(CapabilitiesError) as info:
        get_capabilities(fake_hrbench)
    message = str(info.value)
    assert f"engine {fake_hrbench} has no usable 'capabilities --json' command" in message
    assert "exit code 2: hrbench: unknown command 'capabilities'" in message
    assert "\n" not in message


def test_missing_engine(tmp_path):
    with pytest.raises(EngineError, match="not found or not executable"):
        find_engine(tmp_path / "nowhere")
    (tmp_path / "plain").write_text("not executable")
    with pytest.raises(EngineError, match="not found or not executable"):
        get_capabilities(tmp_path / "plain")


# --- Checking claims against the capabilities ---------------------------------------------


#: SPEC with the form-factor estimates of an engine that has them (hanrahan reads one).
ESTIMATES = [{"name": "clamped-cosine", "formula_2d": "f2", "formula_3d": "f3",
              "source": "RenderPark", "oracles": ["hanrahan"], "default": True},
             {"name": "centre-cosine", "formula_2d": "c2", "formula_3d": "c3",
              "source": "hrbench", "oracles": ["hanrahan"], "default": False}]


def spec_with_estimates():
    doc = copy.deepcopy(SPEC)
    doc["ff_estimates"] = copy.deepcopy(ESTIMATES)
    doc["oracles"][1]["parameters"] = ["eps", "ff_estimate"]
    doc["options"].append({"name": "ff_estimate", "flag": "--ff-estimate", "value": "NAME",
                           "choices": ["clamped-cosine", "centre-cosine"],
                           "commands": ["run", "links"], "doc": "estimate"})
    return doc


def test_form_factor_estimates_are_read_and_optional():
    assert parse_capabilities(json.dumps(SPEC)).ff_estimates == ()  # an engine without them
    caps = parse_capabilities(json.dumps(spec_with_estimates()))
    assert [e.name for e in caps.ff_estimates] == ["clamped-cosine", "centre-cosine"]
    clamped = caps.ff_estimate("clamped-cosine")
    assert (clamped.formula_2d, clamped.formula_3d, clamped.source, clamped.oracles,
            clamped.default) == ("f2", "f3", "RenderPark", ("hanrahan",), True)
    assert caps.ff_estimate("solid-angle") is None
    assert caps.oracle("hanrahan").parameters == ("eps", "ff_estimate")
    bad = spec_with_estimates()
    bad["ff_estimates"][0]["default"] = "yes"
    with pytest.raises(CapabilitiesError,
                       match=r"ff_estimates\[0\]\.default must be true or false"):
        parse_capabilities(json.dumps(bad))
    del bad["ff_estimates"][0]["default"]
    with pytest.raises(CapabilitiesError, match="missing key 'default'"):
        parse_capabilities(json.dumps(bad))


def test_an_option_read_by_other_oracles_only_is_an_error():
    caps = parse_capabilities(json.dumps(spec_with_estimates()))
    estimate = {"ff_estimate": "centre-cosine"}
    assert oracle_error(claim(oracle="hanrahan", options=estimate), caps) is None
    assert oracle_error(claim(oracle="garmann", options=estimate), caps) == (
        "option ff_estimate is read by the oracles hanrahan only, not by 'garmann'")
    assert oracle_error(claim(oracle="garmann"), caps) is None
    # An engine that lists no oracle reading it lacks the option: a reason to skip.
    old = parse_capabilities(json.dumps(SPEC))
    assert oracle_error(claim(oracle="hanrahan", options=estimate), old) is None
    assert missing_capability(claim(oracle="hanrahan", options=estimate), "quick", old) == (
        "engine lacks option --ff-estimate")
    assert missing_capability(claim(oracle="hanrahan", options={"ff_estimate": "hsa"}),
                              "quick", caps) == (
        "engine lacks --ff-estimate hsa (choices: clamped-cosine, centre-cosine)")


@needs_engine
def test_the_engines_capabilities_list_its_form_factor_estimates():
    caps = get_capabilities(HRBENCH)
    assert [e.name for e in caps.ff_estimates] == ["clamped-cosine", "centre-cosine",
                                                   "solid-angle"]
    assert [e.name for e in caps.ff_estimates if e.default] == ["clamped-cosine"]
    for e in caps.ff_estimates:
        assert e.oracles == ("hanrahan", "bf")
        assert "sqrt(4 r^2" in e.formula_2d and "pi r^2" in e.formula_3d and e.source
    assert "RenderPark" in caps.ff_estimate("clamped-cosine").source
    assert "not verified" in caps.ff_estimate("centre-cosine").source
    assert "TR-281-90" in caps.ff_estimate("solid-angle").source
    assert [o.name for o in caps.oracles if "ff_estimate" in o.parameters] == ["hanrahan", "bf"]
    option = caps.option("ff_estimate")
    assert option.flag == "--ff-estimate"
    assert option.choices == tuple(e.name for e in caps.ff_estimates)
    assert option.commands == ("run", "links", "check-links", "solve")
    assert option_argv({"ff_estimate": "centre-cosine"}) == ["--ff-estimate", "centre-cosine"]


def test_unknown_oracle_is_an_error_listing_the_engines_oracles():
    caps = parse_capabilities(json.dumps(SPEC))
    assert oracle_error(claim(oracle="garmann"), caps) is None
    assert oracle_error(claim(oracle="bf"), caps) == (
        "oracle 'bf' is not offered by the engine; its oracles: garmann, hanrahan")


@pytest.mark.parametrize("kwargs, reason", [
    ({}, None),
    ({"params": {"l": 8, "l2": 4}, "options": {"method": "translation"}}, None),
    ({"scene": "room"}, "engine lacks scene 'room'"),
    # A parameter the family lacks is an error, not a reason to skip (param_errors).
    ({"params": {"l": 8, "d": 1}}, None),
    ({"scene": "parallel3d", "oracle": "hanrahan"},
     "engine's oracle 'hanrahan' does not work on 3D scenes such as 'parallel3d' "
     "(dimensions 2)"),
    ({"options": {"visibility": "fraction", "threads": 2}},
     "engine lacks options --threads, --visibility"),
    ({"options": {"method": "translaton"}},
     "engine lacks --method translaton (choices: enumerate, translation)"),
])
def test_what_the_engine_lacks_is_a_reason_to_skip(kwargs, reason):
    caps = parse_capabilities(json.dumps(SPEC))
    assert missing_capability(claim(**kwargs), "quick", caps) == reason


def test_option_of_another_command_counts_as_lacking():
    doc = copy.deepcopy(SPEC)
    doc["options"].append({"name": "out", "flag": "--out", "value": "F", "choices": None,
                           "commands": ["links"], "doc": "file"})
    caps = parse_capabilities(json.dumps(doc))
    assert missing_capability(claim(options={"out": "x"}), "quick", caps) == (
        "engine lacks option --out")


# --- Command lines -----------------------------------------------------------------------


def test_run_argv_holds_everything_in_a_fixed_order():
    argv = run_argv("build/hrbench", "parallel", {"l": 64, "d": 0.25}, 0.1, "hanrahan",
                    min_area=1e-6, max_depth=30.0,
                    options={"visibility": "fraction", "rays_per_side": 4})
    assert argv == ["build/hrbench", "run", "parallel", "d=0.25", "l=64", "--eps", "0.1",
                    "--oracle", "hanrahan", "--min-area", "1e-06", "--max-depth", "30",
                    "--rays-per-side", "4", "--visibility", "fraction",
                    "--count-only", "--json"]
    assert run_argv("e", "room", {}, 0.5, "garmann") == [
        "e", "run", "room", "--eps", "0.5", "--oracle", "garmann", "--count-only", "--json"]


def test_links_argv(tmp_path):
    assert links_argv("e", "parallel", {"l": 16.0, "d": 1.0}, 0.3, tmp_path / "l.csv") == [
        "e", "links", "parallel", "d=1", "l=16", "--eps", "0.3", "--oracle", "garmann",
        "--out", str(tmp_path / "l.csv")]


def test_numbers_on_the_command_line_are_exact():
    assert format_number(0.1) == "0.1" and format_number(64) == "64"
    third = 1 / 3
    assert float(format_number(third)) == third
    assert option_argv({"n": 3, "x": 2.0, "s": "a"}) == ["--n", "3", "--s", "a", "--x", "2"]


@pytest.mark.parametrize("call, match", [
    (lambda: option_argv({"threads": False}), r"options\['threads'\] must be a string, an "
                                              "integer, a float or True \\(a flag\\), got False"),
    (lambda: option_argv([("threads", 2)]), "options must be a dict"),
    (lambda: run_argv("e", "parallel", {"l": "8"}, 0.1, "garmann"),
     r"params\['l'\] must be a number, got '8'"),
])
def test_bad_arguments_are_named(call, match):
    with pytest.raises(TypeError, match=match):
        call()


# --- Processes ---------------------------------------------------------------------------


def test_run_engine_reports_exit_code_and_last_message(fake_hrbench, tmp_path):
    run = run_engine([fake_hrbench, "run", "nowhere"])
    assert run.exit_code == 2 and run.message == "hrbench: unknown scene 'nowhere'"
    assert run.argv == (str(fake_hrbench), "run", "nowhere") and run.wall_seconds >= 0
    missing = run_engine([tmp_path / "nowhere", "--version"])
    assert missing.exit_code == 127 and "cannot run" in missing.message


def test_run_links_failure_names_the_command(fake_hrbench, tmp_path):
    with pytest.raises(EngineError, match="links box3d d=1 l=1 --eps 0.5 .* failed with exit "
                                          "code 2: hrbench: unknown scene 'box3d'"):
        run_links(fake_hrbench, "box3d", {"l": 1, "d": 1}, 0.5, tmp_path / "l.csv")


# --- The command line refuses what the engine cannot run, before any run -------------------


def reproduce(tmp_path, claims, fake_hrbench, capsys, *extra):
    code = main(["--claims", str(claims), "--hrbench", str(fake_hrbench), "--results",
                 str(tmp_path / "results"), "--no-tiling", *extra])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture
def run_log(tmp_path, monkeypatch):
    """The file to which the fake engine appends every run."""
    log = tmp_path / "runs.log"
    monkeypatch.setenv("FAKE_HRBENCH_LOG", str(log))
    return log


def write_variant(tmp_path, data_dir, old, new):
    path = tmp_path / "claims.toml"
    text = (data_dir / "small_claims.toml").read_text()
    assert old in text
    path.write_text(text.replace(old, new))
    return path


def test_unknown_oracle_exits_2_before_any_run(tmp_path, data_dir, fake_hrbench, capsys,
                                               run_log):
    claims = write_variant(tmp_path, data_dir, 'scene = "parallel"',
                           'scene = "parallel"\noracle = "bf"')
    code, out, err = reproduce(tmp_path, claims, fake_hrbench, capsys)
    assert code == 2
    (line,) = err.strip().splitlines()
    assert line == (f"error: {claims}:6: claim 'T-elements': oracle 'bf' is not offered by "
                    "the engine; its oracles: garmann, hanrahan")
    assert not run_log.exists()
    assert not (tmp_path / "results" / "hrbench.sqlite").exists()


def test_unknown_formula_name_exits_2_before_any_run(tmp_path, data_dir, fake_hrbench, capsys,
                                                     run_log):
    claims = write_variant(tmp_path, data_dir, 'y = "N"', 'y = "N / volume"')
    code, _, err = reproduce(tmp_path, claims, fake_hrbench, capsys)
    assert code == 2
    (line,) = err.strip().splitlines()
    assert f"{claims}:15: claim 'T-elements': key 'y' reads unknown name(s) volume" in line
    assert not run_log.exists()


@pytest.mark.parametrize("how, match", [
    ("missing", "has no usable 'capabilities --json' command (exit code 2"),
    ("garbage", "'capabilities --json' is not valid JSON"),
])
def test_engine_without_capabilities_exits_2_with_one_line(tmp_path, data_dir, fake_hrbench,
                                                           capsys, monkeypatch, run_log,
                                                           how, match):
    monkeypatch.setenv("FAKE_HRBENCH_CAPABILITIES", how)
    code, _, err = reproduce(tmp_path, data_dir / "small_claims.toml", fake_hrbench, capsys)
    assert code == 2
    (line,) = err.strip().splitlines()
    assert line.startswith("error: engine ") and str(fake_hrbench) in line and match in line
    assert not run_log.exists()


def test_oracle_without_the_scenes_dimension_is_skipped(tmp_path, data_dir, fake_hrbench,
                                                        capsys, run_log):
    claims = write_variant(tmp_path, data_dir, 'scene = "parallel"',
                           'scene = "box3d"\noracle = "hanrahan"')
    code, out, err = reproduce(tmp_path, claims, fake_hrbench, capsys)
    assert code == 0, err
    assert ("warning: claim T-elements skipped: engine's oracle 'hanrahan' does not work on "
            "3D scenes such as 'box3d' (dimensions 2)") in err
    assert "T-elements: skipped" in out
    assert not run_log.exists()


def test_option_value_the_engine_lacks_is_skipped(tmp_path, data_dir, fake_hrbench, capsys,
                                                  run_log):
    claims = write_variant(tmp_path, data_dir, "min_points = 8",
                           'min_points = 8\noptions = { method = "recursion" }')
    code, out, err = reproduce(tmp_path, claims, fake_hrbench, capsys)
    assert code == 0, err
    assert "engine lacks --method recursion (choices: enumerate, translation)" in err
    assert not run_log.exists()
