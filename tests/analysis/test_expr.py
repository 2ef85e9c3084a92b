import math

import pytest

from hrbench_analysis.expr import Expression, ExpressionError


def test_arithmetic_over_named_values():
    env = {"links": 10.0, "nodes": 4.0, "eps": 0.25, "l": 64.0, "d": 2.0}
    assert Expression("links / nodes")(env) == 2.5
    assert Expression("1/eps")(env) == 4.0
    assert Expression("-(l/d) + 2**3")(env) == -24.0
    assert Expression("log10(l * 100 / 64)")(env) == pytest.approx(2.0)


def test_names_lists_variables_but_not_functions():
    assert Expression("sqrt(L) / N").names == {"L", "N"}


def test_undefined_arithmetic_gives_nan():
    assert math.isnan(Expression("1/eps")({"eps": 0.0}))


@pytest.mark.parametrize("text", [
    "__import__('os').system('true')",
    "nodes.real",
    "(lambda: 1)()",
    "nodes if eps else links",
    "[nodes]",
    "'text'",
    "nodes < links",
    "open('x')",
    "log(1, 2)",
    "",
    "1 +",
])
def test_rejects_everything_but_arithmetic(text):
    with pytest.raises(ExpressionError):
        Expression(text)


def test_missing_name_is_named_in_the_error():
    with pytest.raises(ExpressionError, match="links"):
        Expression("links / nodes")({"nodes": 1.0})


# --- Bounded work -------------------------------------------------------------------------


def test_tower_of_powers_overflows_in_float64_at_once():
    import time
    start = time.perf_counter()
    assert Expression("N**N**N")({"N": 1000}) == math.inf
    assert Expression("9**9**9")({}) == math.inf        # never a Python big integer
    assert Expression("N**N**N")({"N": 10**15}) == math.inf
    assert Expression("-exp(links)")({"links": 1e8}) == -math.inf
    assert time.perf_counter() - start < 0.5


def test_values_are_float64_even_for_integer_counters():
    value = Expression("links / nodes")({"links": 10, "nodes": 4})
    assert value == 2.5 and type(value) is float
    assert Expression("N**2")({"N": 3}) == 9.0


@pytest.mark.parametrize("text, env", [
    ("1/eps", {"eps": 0.0}),
    ("0**-1", {}),
    ("log(x)", {"x": 0.0}),
    ("log10(x)", {"x": -1.0}),
    ("sqrt(x)", {"x": -1.0}),
    ("exp(x) - exp(x)", {"x": 1e4}),
])
def test_undefined_arithmetic_is_nan_not_an_exception(text, env):
    assert math.isnan(Expression(text)(env))


def test_arrays_are_evaluated_element_by_element():
    import numpy as np
    out = Expression("L / N")({"L": np.array([2.0, 9.0]), "N": np.array([1.0, 3.0])})
    assert out.tolist() == [2.0, 3.0]


def test_a_10000_character_formula_is_refused_by_its_length():
    text = "N+" * 5000 + "N"
    with pytest.raises(ExpressionError, match=r"too long: at most 1000 characters") as info:
        Expression(text)
    assert len(str(info.value)) < 200  # the message shows the start, not the whole formula


def _balanced(depth):
    # A balanced sum of 2**depth names: 2**(depth+1) - 1 nodes, depth + 1 levels.
    return "N" if depth == 0 else f"({_balanced(depth - 1)}+{_balanced(depth - 1)})"


@pytest.mark.parametrize("text, match", [
    ("(" * 300 + "N" + ")" * 300, "too many nested parentheses"),
    ("-" * 500 + "N", "nested too deeply: at most 100 levels"),
    ("f(" * 150 + "N" + ")" * 150, "too many nested parentheses|nested too deeply"),
    ("+".join(["N"] * 150), "nested too deeply"),     # a chain of 150 additions
    (_balanced(7), "too large: at most 200"),         # 255 nodes, 8 levels
    ("1" * 400, "not finite in float64"),
    ("1e999", "not finite in float64"),
    ("N\x00", "cannot parse"),
    ("N + \ud800", "cannot parse"),
    ("1j", "only numbers"),
])
def test_oversized_deep_or_odd_formulas_are_refused(text, match):
    with pytest.raises(ExpressionError, match=match):
        Expression(text)


def test_formulas_within_the_limits_are_accepted():
    Expression("(" * 50 + "N" + ")" * 50)            # parentheses add no nesting
    Expression("+".join(["N"] * 100))                # 199 nodes, 100 levels
    assert Expression("log(" * 30 + "N" + ")" * 30)({"N": 10.0}) is not None
