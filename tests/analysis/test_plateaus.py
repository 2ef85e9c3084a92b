"""One point per plateau of a staircase (claims key ``plateaus``): slopes.plateau_ends, the
verdict on the kept points, and the key's checks in claims files."""

import json
import math

import numpy as np
import pytest

from hrbench_analysis.claimfile import ClaimsFileError, load_claims
from hrbench_analysis.reproduce import main
from hrbench_analysis.slopes import plateau_ends, point_window_slopes
from hrbench_analysis.verdict import get_verdict


def staircase(k, offset, per_decade=100, decades=3.5):
    """A quadtree-like sweep of 1/eps: the elements N step by 4 once per factor 4 of x,
    at a phase `offset`, and y = N^k times a factor that grows by up to 4 along each
    plateau (as the links do at fixed elements)."""
    x = np.geomspace(1.0, 10 ** decades, int(per_decade * decades) + 1)
    u = np.log(x * offset) / np.log(4.0)
    level = 4.0 ** np.ceil(u)                     # the staircase: 4x steps
    phase = u - np.floor(u)                       # 0 .. 1 along each plateau
    y = level ** k * 4.0 ** (-(1 - phase))        # climbs by 4 within a plateau
    return x, level, y


def test_plateau_ends_hand_computed():
    value = [1, 2, 4, 8, 16, 32, 64, 128]
    level = [1, 1, 1, 4, 4, 4, 16, 16]
    assert plateau_ends(value, level).tolist() == [2, 5]            # the final one is cut
    assert plateau_ends(value, level, keep="first").tolist() == [3, 6]
    # A sub-step (one point at level 2) is not a plateau; an open plateau keeps nothing.
    assert plateau_ends([1, 2, 4, 4.1, 8, 16], [1, 1, 1, 2, 4, 4]).tolist() == [2]
    # A falling sweep (eps from 1 down) is as good as a rising one.
    assert plateau_ends([1, 0.5, 0.25, 0.125], [1, 1, 4, 4]).tolist() == [1]
    with pytest.raises(ValueError, match="keep"):
        plateau_ends([1, 2], [1, 1], keep="middle")


def test_point_windows_are_runs_of_points():
    x = np.array([1.0, 4, 16, 64])
    w = point_window_slopes(x, x ** 2, 3)
    assert w.slope.tolist() == pytest.approx([2.0, 2.0])
    assert w.n.tolist() == [3, 3]


@pytest.mark.parametrize("offset", [1.0, 1.3, 2.1, 3.7])
@pytest.mark.parametrize("k", [1.0, 2.0])
def test_staircase_with_4x_steps_is_reproduced(k, offset):
    x, level, y = staircase(k, offset)
    i = plateau_ends(x, level)
    assert 5 <= i.size <= 6                       # one point per factor 4 of 3.5 decades
    # The plateaus' ends of this synthetic staircase lie exactly on the law; a scatter
    # of 1% makes them a measurement (exact points are an identity: unfalsifiable).
    scatter = 1 + 0.01 * np.cos(2.3 * np.arange(i.size))
    result = get_verdict(x[i], y[i] * scatter, k, 0.1, min_points=4, one_per_step=True)
    assert result.verdict == "reproduced", result.reason
    assert result.interval.low <= k <= result.interval.high
    assert abs(result.fit.exponent - k) < 0.02


@pytest.mark.parametrize("offset", [1.0, 2.1])
def test_staircase_on_x_to_the_1_5_is_refuted(offset):
    x, level, y = staircase(1.5, offset)
    i = plateau_ends(x, level)
    for k in (1.0, 2.0):
        result = get_verdict(x[i], y[i], k, 0.15, min_points=4, one_per_step=True)
        assert result.verdict == "refuted", result.reason
        assert result.interval.low <= 1.5 <= result.interval.high


def test_too_few_plateaus_are_inconclusive():
    x, level, y = staircase(1.0, 1.0, decades=2.0)
    i = plateau_ends(x, level)
    result = get_verdict(x[i], y[i], 1.0, 0.1, min_points=3, min_decades=0.5,
                         one_per_step=True)
    assert result.verdict == "inconclusive"
    assert "too few plateaus" in result.reason


CLAIM = """
[source]
key = "t"
citation = "A. Author: Title, 2000"

[[claim]]
id = "P1"
statement = "N = Theta(eps^-1)"
scene = "parallel3d"
params = {{ l = 3, d = 1 }}
sweep.param = "eps"
sweep.range = {{ from = 0.2, to = 0.001, per_decade = 100 }}
x = "1/eps"
y = "N"
expected_exponent = 1
tolerance = 0.1
step_octaves = 2
{plateaus}
"""


def load(tmp_path, plateaus):
    path = tmp_path / "c.toml"
    path.write_text(CLAIM.format(plateaus=plateaus))
    return load_claims(path)


def test_plateaus_key_is_read(tmp_path):
    (claim,) = load(tmp_path, 'plateaus = { of = "N" }')
    assert claim.plateaus.of.text == "N"
    assert claim.plateaus.keep == "last"
    assert claim.plateaus.min_octaves == 1.0          # half of step_octaves = 2
    (claim,) = load(tmp_path, 'plateaus = { of = "nodes", keep = "first", min_octaves = 0.5 }')
    assert (claim.plateaus.keep, claim.plateaus.min_octaves) == ("first", 0.5)
    (claim,) = load(tmp_path, "")
    assert claim.plateaus is None


@pytest.mark.parametrize("text, message", [
    ('plateaus = "N"', "key 'plateaus' must be a table"),
    ('plateaus = { keep = "last" }', "'plateaus.of' must be a formula"),
    ('plateaus = { of = "N +" }', "key 'plateaus.of'"),
    ('plateaus = { of = "N", keep = "middle" }', "'plateaus.keep' must be"),
    ('plateaus = { of = "N", min_octaves = -1 }', "'plateaus.min_octaves' must be"),
    ('plateaus = { of = "N", min_octaves = true }', "'plateaus.min_octaves' must be"),
    ('plateaus = { of = "N", every = 2 }', "unknown key 'plateaus.every'"),
])
def test_plateaus_key_errors(tmp_path, text, message):
    with pytest.raises(ClaimsFileError, match=message.replace("(", r"\(")) as info:
        load(tmp_path, text)
    assert "claim 'P1'" in str(info.value)
    assert math.isfinite(len(str(info.value)))


def test_sweep_keeps_the_last_point_of_each_plateau(tmp_path, data_dir, fake_hrbench):
    # Through the sweep (fake engine, eps falling): the kept points are those of the full
    # sweep just before N changes, the final plateau (not closed by a step) left out.
    text = (data_dir / "small_claims.toml").read_text().replace(
        "per_decade = 5", "per_decade = 10").replace("min_points = 8", "min_points = 3")
    got = {}
    for name, key in (("all", ""), ("kept", 'plateaus = { of = "N", min_octaves = 0 }')):
        path = tmp_path / f"{name}.toml"
        path.write_text(text + key + "\n")
        main(["--claims", str(path), "--hrbench", str(fake_hrbench), "--results",
              str(tmp_path / name), "--cache", str(tmp_path / "cache.sqlite"),
              "--no-pictures"])
        (claim,) = json.loads((tmp_path / name / "claims.json").read_text())["claims"]
        got[name] = claim
    x, n = got["all"]["data"]["x"], got["all"]["data"]["y"]        # x = 1/eps, rising
    want = [i for i in range(len(x) - 1) if n[i + 1] != n[i]]
    assert want and len(want) < len(x) - 1
    assert got["kept"]["data"]["x"] == [x[i] for i in want]
    assert got["kept"]["data"]["y"] == [n[i] for i in want]
    assert f"the last of each: {len(want)} of {len(x)} points" in got["kept"]["reason"]
