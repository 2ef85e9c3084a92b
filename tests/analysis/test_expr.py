import math

import pytest

from analysis.expr import Expression, ExpressionError


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
