"""Increments over whole octaves (claims key ``increments``): sweep.octave_increments by
hand, the test it gives an O(x log x) count with an O(x) term against x^1.15, and the
key's checks in claims files."""

import math

import numpy as np
import pytest

from hrbench_analysis.claimfile import ClaimsFileError, load_claims
from hrbench_analysis.sweep import octave_increments
from hrbench_analysis.verdict import get_verdict


def rows_of(x, y, law=None, series=""):
    law = [None] * len(x) if law is None else law
    return [(float(a), float(b), float(a), series, None, c)
            for a, b, c in zip(x, y, law, strict=True)]


def test_increments_hand_computed():
    # y = 3 ln x - 7: the increment is 3 per e-fold at every x, whatever the constant.
    x = [8, 12, 16, 24, 32, 64]
    got, dropped = octave_increments(rows_of(x, [3 * math.log(v) - 7 for v in x]), 1)
    assert dropped == []
    # 8 -> 16, 12 -> 24, 16 -> 32, 32 -> 64; 24 has none: 64 lies 0.42 octave past 48,
    # more than a quarter octave (a pair across the phases of a binary staircase).
    assert [(round(r[0], 6), round(r[1], 12)) for r in got] == [
        (round(math.sqrt(v * w), 6), 3.0) for v, w in ((8, 16), (12, 24), (16, 32), (32, 64))]
    # Two octaves apart: 8 -> 32, 16 -> 64; 12 has none (64 lies 0.42 octave past 48).
    got, _ = octave_increments(rows_of(x, [2 * math.log(v) for v in x]), 2)
    assert [(r[0], round(r[1], 12)) for r in got] == [(16.0, 2.0), (32.0, 2.0)]
    # Within a quarter octave the nearest is taken: 10 -> 21 (0.07 octave past 20).
    got, _ = octave_increments(rows_of([10, 21], [1, 2]), 1)
    assert [round(r[1], 12) for r in got] == [round(1 / math.log(2.1), 12)]


def test_increments_take_the_law_along_and_keep_series_apart():
    x = [4, 8, 16]
    rows = (rows_of(x, [1, 2, 3], law=[10, 20, 40], series="a")
            + rows_of(x, [5, 5, 9], law=[1, 1, 1], series="b"))
    got, dropped = octave_increments(rows, 1)
    ln2 = math.log(2)
    assert [(r[3], round(r[1] * ln2, 12), round(r[5] * ln2, 12)) for r in got] == [
        ("a", 1.0, 10.0), ("a", 1.0, 20.0), ("b", 4.0, 0.0)]
    # y did not grow from 4 to 8 in series b: named, left out of the fit.
    assert len(dropped) == 1
    assert "from x=4 to x=8 is not positive (0)" in dropped[0]["stderr"]
    assert dropped[0]["value"] == pytest.approx(math.sqrt(32))


def linking(k, a=5.5, b=-13.0, power=None):
    # A count a k ln k + b k (or k^power), with the +-3% of a binary staircase of period
    # one octave, sampled where k and 4k are both swept (2 binary digits).
    stair = 1 + 0.03 * np.cos(2 * np.pi * np.log2(k))
    count = k ** power if power else a * k * np.log(k) + b * k
    return count * stair


def test_k_log_k_with_a_linear_term_is_reproduced_and_k_to_the_1_15_refuted():
    k = np.array([m * 2.0 ** j for j in range(7, 17) for m in (1, 1.5)])
    per_patch = linking(k) / k
    rows = rows_of(k, per_patch, law=k ** 0.15)
    inc, dropped = octave_increments(rows, 2)
    assert dropped == []
    x, y, law = (np.array([r[i] for r in inc]) for i in (0, 1, 5))
    result = get_verdict(x, y, 0.0, 0.05, bound="upper", min_decades=1, n_boot=400,
                         laws=[("patches ** 0.15", law)])
    assert result.verdict == "reproduced", result.reason
    assert [a.verdict for a in result.alternatives] == ["refuted", "refuted"]
    # The same count fitted directly against k log k drifts above 1 + 0.03.
    direct = get_verdict(k * np.log(k), linking(k), 1.0, 0.03, bound="upper",
                         x_min=15000, min_decades=1, alternatives=False, n_boot=400)
    assert direct.verdict != "reproduced"
    # And a count of k^1.15 is refuted through its increments.
    faster = octave_increments(rows_of(k, linking(k, power=1.15) / k), 2)[0]
    result = get_verdict([r[0] for r in faster], [r[1] for r in faster], 0.0, 0.05,
                         bound="upper", min_decades=1, n_boot=400)
    assert result.verdict == "refuted", result.reason


CLAIM = """
[source]
key = "t"
citation = "test"

[[claim]]
id = "I1"
statement = "L = O(k log k)"
scene = "parallel"
params = {{ l = 1, d = 1 }}
sweep.param = "l"
sweep.range = {{ from = 1, to = 64, per_decade = 10, binary_digits = 2 }}
eps = 0.5
x = "N"
y = "L / N"
expected_exponent = 0
tolerance = 0.05
bound = "upper"
{key}
"""


def load(tmp_path, key):
    path = tmp_path / "c.toml"
    path.write_text(CLAIM.format(key=key))
    return load_claims(path)


def test_increments_key_is_read(tmp_path):
    (claim,) = load(tmp_path, "increments = 2")
    assert claim.increments == 2
    (claim,) = load(tmp_path, "")
    assert claim.increments is None


@pytest.mark.parametrize("text, message", [
    ("increments = 0", "key 'increments' must be a whole number of octaves from 1 to 16"),
    ("increments = true", "key 'increments' must be a whole number"),
    ("increments = 1.5", "key 'increments' must be a whole number"),
    ('increments = 1\nplateaus = { of = "N" }', "keys 'increments' and 'plateaus' exclude"),
])
def test_increments_key_errors(tmp_path, text, message):
    with pytest.raises(ClaimsFileError, match=message) as info:
        load(tmp_path, text)
    assert "claim 'I1'" in str(info.value)
