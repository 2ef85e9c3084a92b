"""Claims on a mesh file: the keys `scene = "mesh"` and `mesh`, the command line, and a cache
key that follows the file's bytes."""

import hashlib
import json
import shutil
import subprocess
from pathlib import Path

import pytest

from hrbench_analysis.claimfile import ClaimsFileError, load_claims, missing_capability
from hrbench_analysis.engine import engine_version, get_capabilities, option_argv
from hrbench_analysis.reproduce import main
from hrbench_analysis.sweep_plan import expand_claim

ROOT = Path(__file__).resolve().parents[2]
HRBENCH = ROOT / "build" / "hrbench"
needs_engine = pytest.mark.skipif(not HRBENCH.exists(), reason="build/hrbench not built")

CLAIM = '''[source]
key = "test"
citation = "hrbench test data"

[[claim]]
id = "M1"
statement = "N = Theta(eps^-1) on two unit squares loaded from a file"
scene = "mesh"
mesh = "two_plates.obj"
params = {}
sweep.param = "eps"
sweep.range = { from = 0.5, to = 0.0005, per_decade = 6 }
x = "1/eps"
y = "N"
expected_exponent = 1
tolerance = 0.2
regime = { x_min = 10 }
min_decades = 1
'''


@pytest.fixture
def mesh_dir(tmp_path):
    for name in ("two_plates.obj", "two_plates.mtl"):
        shutil.copy(ROOT / "tests" / "data" / name, tmp_path / name)
    return tmp_path


def write(folder, text, name="claims.toml"):
    path = folder / name
    path.write_text(text)
    return path


def test_mesh_claim_resolves_its_file_and_hashes_its_bytes(mesh_dir):
    (claim,) = load_claims(write(mesh_dir, CLAIM))
    obj = mesh_dir / "two_plates.obj"
    assert claim.scene == "mesh" and claim.params == {}
    assert claim.mesh == str(obj.resolve())
    assert claim.mesh_sha256 == hashlib.sha256(obj.read_bytes()).hexdigest()


def test_mesh_path_is_relative_to_the_claims_file(mesh_dir):
    (mesh_dir / "claims").mkdir()
    text = CLAIM.replace('mesh = "two_plates.obj"', 'mesh = "../two_plates.obj"')
    (claim,) = load_claims(write(mesh_dir / "claims", text))
    assert claim.mesh == str((mesh_dir / "two_plates.obj").resolve())


@pytest.mark.parametrize("old, new, key, match", [
    ('mesh = "two_plates.obj"\n', "", "scene", "needs the key 'mesh'"),
    ('scene = "mesh"', 'scene = "parallel3d"', "mesh", "needs scene = 'mesh'"),
    ("params = {}", "params = { l = 1 }", "params", "no scene parameters"),
    ('"two_plates.obj"', '"absent.obj"', "mesh",
     "'absent.obj': cannot read the mesh file: No such file"),
    ("params = {}", 'params = {}\noptions = { mesh = "x.obj" }', "options.mesh",
     "not allowed there"),
    ("params = {}", "params = {}\noptions = { triangulate = false }", "options.triangulate",
     "leave a switch out"),
])
def test_bad_mesh_keys_name_the_key(mesh_dir, old, new, key, match):
    with pytest.raises(ClaimsFileError, match=match) as info:
        load_claims(write(mesh_dir, CLAIM.replace(old, new, 1)))
    assert info.value.key == key
    assert info.value.line is not None and info.value.line > 0


def test_switch_options_are_flags_without_a_value():
    assert option_argv({"triangulate": True, "scale": 0.001}) == [
        "--scale", "0.001", "--triangulate"]
    with pytest.raises(TypeError):
        option_argv({"triangulate": False})


@needs_engine
def test_points_pass_the_path_and_key_the_bytes(mesh_dir):
    version = engine_version(HRBENCH)
    path = write(mesh_dir, CLAIM)
    (claim,) = load_claims(path)
    points = expand_claim(claim, "quick", HRBENCH, version)
    argv = points[0].argv
    assert argv[1] == "run" and argv[argv.index("--mesh") + 1] == claim.mesh
    assert dict(points[0].key.options) == {"mesh": f"sha256:{claim.mesh_sha256}"}
    # The same file under another name keeps its keys; other bytes change them.
    shutil.copy(mesh_dir / "two_plates.obj", mesh_dir / "copy.obj")
    (moved,) = load_claims(write(mesh_dir, CLAIM.replace("two_plates.obj", "copy.obj")))
    assert ([p.key.text() for p in expand_claim(moved, "quick", HRBENCH, version)]
            == [p.key.text() for p in points])
    with open(mesh_dir / "copy.obj", "a") as fh:
        fh.write("# changed\n")
    (changed,) = load_claims(write(mesh_dir, CLAIM.replace("two_plates.obj", "copy.obj")))
    changed_keys = {p.key.text() for p in expand_claim(changed, "quick", HRBENCH, version)}
    assert not changed_keys & {p.key.text() for p in points}


def test_engine_without_mesh_input_skips_the_claim(mesh_dir, fake_hrbench):
    (claim,) = load_claims(write(mesh_dir, CLAIM))
    caps = get_capabilities(fake_hrbench)
    assert caps.option("mesh") is None
    assert missing_capability(claim, "quick", caps) == "engine lacks scene 'mesh'"


@needs_engine
def test_mesh_claim_runs_the_file_on_the_engine(mesh_dir, capsys):
    # The file holds the plates of `parallel3d l=1 d=1`: the same counts at every point.
    (claim,) = load_claims(write(mesh_dir, CLAIM))
    code = main(["--claims", str(write(mesh_dir, CLAIM)), "--hrbench", str(HRBENCH),
                 "--results", str(mesh_dir / "results"), "--cache",
                 str(mesh_dir / "cache.sqlite"), "--no-tiling", "--quick"])
    out, err = capsys.readouterr()
    assert code in (0, 1), out + err
    (record,) = json.loads((mesh_dir / "results" / "claims.json").read_text())["claims"]
    assert record["mesh"] == {"file": "two_plates.obj", "sha256": claim.mesh_sha256}
    assert abs(record["measured_exponent"] - 1) < 0.05
    for x, n in list(zip(record["data"]["x"], record["data"]["y"], strict=True))[::6]:
        run = subprocess.run([str(HRBENCH), "run", "parallel3d", "l=1", "d=1", "--eps",
                              repr(1 / x), "--count-only", "--json"],
                             capture_output=True, text=True, check=True)
        assert json.loads(run.stdout)["nodes"] == n


@needs_engine
def test_a_switch_given_to_an_option_with_a_value_is_a_reason_to_skip(mesh_dir):
    caps = get_capabilities(HRBENCH)
    text = CLAIM.replace("params = {}", "params = {}\noptions = { rays_per_side = true }")
    (claim,) = load_claims(write(mesh_dir, text))
    assert missing_capability(claim, "quick", caps) == (
        "engine's option --rays-per-side takes a value, not a switch")
