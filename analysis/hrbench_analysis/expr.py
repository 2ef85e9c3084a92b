"""A tiny, safe arithmetic expression evaluator for claim axes.

Claims name their measured quantities as short formulas over the fields of one run,
for example ``"links / nodes"``, ``"1/eps"`` or ``"g"``. This module parses such a formula
once, checks that it uses only arithmetic and known names, and evaluates it over a
mapping of numbers. It never calls :func:`eval`: the formula is parsed with :mod:`ast`
and walked node by node, and anything but numbers, names, ``+ - * / **``, parentheses
and a few named functions is rejected.

The work is bounded: a formula has at most :data:`MAX_LENGTH` characters,
:data:`MAX_NODES` nodes (numbers, names, operators, calls) and :data:`MAX_DEPTH` levels
of nesting, and it is evaluated in float64 (numpy), never with Python integers, so that
``N**N**N`` overflows to ``inf`` in microseconds instead of computing a big integer.
"""

import ast
import math
import warnings

import numpy as np

from .errors import AnalysisError

__all__ = ["Expression", "ExpressionError", "FUNCTIONS", "MAX_LENGTH", "MAX_NODES",
           "MAX_DEPTH"]

#: Most characters of a formula.
MAX_LENGTH = 1000
#: Most nodes of a formula's syntax tree: numbers, names, operators and calls.
MAX_NODES = 200
#: Most levels of nesting of a formula's syntax tree (operators, calls, unary signs).
MAX_DEPTH = 100


def _log(func):
    # A logarithm that gives nan, not -inf or a warning, for a non-positive argument.
    def log(x):
        x = np.asarray(x, dtype=np.float64)
        return np.where(x > 0, func(np.where(x > 0, x, 1.0)), np.nan)
    return log


#: Functions a formula may call, by name. All take and return one number (float64).
FUNCTIONS = {
    "log": _log(np.log),
    "log2": _log(np.log2),
    "log10": _log(np.log10),
    "sqrt": np.sqrt,
    "exp": np.exp,
    "abs": np.abs,
}


def _divide(a, b):
    # a / b, nan where b is 0 (division by zero is undefined, not infinite).
    b = np.asarray(b, dtype=np.float64)
    return np.where(b != 0, np.divide(a, np.where(b != 0, b, 1.0)), np.nan)


def _power(a, b):
    # a ** b in float64, nan where 0 is raised to a negative power.
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    return np.where((a == 0) & (b < 0), np.nan, np.power(a, b))


_BINARY = {
    ast.Add: np.add,
    ast.Sub: np.subtract,
    ast.Mult: np.multiply,
    ast.Div: _divide,
    ast.Pow: _power,
}
_UNARY = {ast.UAdd: np.positive, ast.USub: np.negative}


class ExpressionError(AnalysisError, ValueError):
    """A formula that does not parse, is too large, uses a forbidden construct or an
    unknown name."""


def _shown(text, limit=60):
    # The formula for a message: repr, cut to `limit` characters.
    if len(text) <= limit:
        return repr(text)
    return f"{text[:limit]!r}... ({len(text)} characters)"


class Expression:
    """A parsed arithmetic formula over named numbers.

    Parameters
    ----------
    text : str
        The formula, e.g. ``"links / nodes"``. Allowed: numbers, names, the operators
        ``+ - * / **``, unary minus, parentheses and calls to the functions in
        :data:`FUNCTIONS` with one argument; at most :data:`MAX_LENGTH` characters,
        :data:`MAX_NODES` nodes and :data:`MAX_DEPTH` levels of nesting. Numbers must
        be finite in float64.

    Attributes
    ----------
    text : str
        The formula as given.
    names : frozenset of str
        The variable names the formula reads (function names excluded).

    Raises
    ------
    ExpressionError
        If the formula is empty, too long, too large or too deeply nested, does not
        parse, or uses a construct outside the list above.

    Examples
    --------
    >>> Expression("links / nodes")({"links": 10, "nodes": 4})
    2.5
    >>> sorted(Expression("1/eps").names)
    ['eps']
    >>> Expression("N**N**N")({"N": 1000})
    inf
    """

    def __init__(self, text):
        if not isinstance(text, str) or not text.strip():
            raise ExpressionError("formula must be a non-empty string")
        if len(text) > MAX_LENGTH:
            raise ExpressionError(f"formula {_shown(text)} is too long: at most {MAX_LENGTH} "
                                  "characters")
        self.text = text
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # e.g. SyntaxWarning for "1is 1"
                tree = ast.parse(text.strip(), mode="eval")
        except SyntaxError as exc:
            raise ExpressionError(f"cannot parse formula {_shown(text)}: {exc.msg}") from None
        except (ValueError, RecursionError, MemoryError) as exc:
            # null bytes, lone surrogates, nesting beyond the parser's limits
            raise ExpressionError(f"cannot parse formula {_shown(text)}: "
                                  f"{type(exc).__name__}") from None
        self._size_iv(tree.body)
        names = set()
        self._check(tree.body, names)
        self._tree = tree.body
        self.names = frozenset(names)

    def _size_iv(self, root):
        # Count nodes and nesting without recursion, before the recursive walks.
        nodes, stack = 0, [(root, 1)]
        while stack:
            node, depth = stack.pop()
            nodes += 1
            if nodes > MAX_NODES:
                raise ExpressionError(f"formula {_shown(self.text)} is too large: at most "
                                      f"{MAX_NODES} numbers, names, operators and calls")
            if depth > MAX_DEPTH:
                raise ExpressionError(f"formula {_shown(self.text)} is nested too deeply: at "
                                      f"most {MAX_DEPTH} levels")
            if isinstance(node, ast.BinOp):
                stack += [(node.left, depth + 1), (node.right, depth + 1)]
            elif isinstance(node, ast.UnaryOp):
                stack.append((node.operand, depth + 1))
            elif isinstance(node, ast.Call):
                stack += [(arg, depth + 1) for arg in node.args]
            elif isinstance(node, (ast.Constant, ast.Name)):
                pass
            else:
                stack += [(child, depth + 1) for child in ast.iter_child_nodes(node)]

    def _check(self, node, names):
        # Accept only the node types the evaluator knows, and collect variable names.
        if isinstance(node, ast.Constant):
            if isinstance(node.value, bool) or not isinstance(node.value, (int, float)):
                raise ExpressionError(
                    f"only numbers are allowed as constants in {_shown(self.text)}")
            try:
                finite = math.isfinite(float(node.value))
            except OverflowError:
                finite = False
            if not finite:
                raise ExpressionError(f"a number in {_shown(self.text)} is not finite in "
                                      "float64 (largest 1.8e308)")
        elif isinstance(node, ast.Name):
            names.add(node.id)
        elif isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
            self._check(node.left, names)
            self._check(node.right, names)
        elif isinstance(node, ast.UnaryOp) and type(node.op) in _UNARY:
            self._check(node.operand, names)
        elif isinstance(node, ast.Call):
            if not isinstance(node.func, ast.Name) or node.func.id not in FUNCTIONS:
                allowed = ", ".join(sorted(FUNCTIONS))
                raise ExpressionError(
                    f"unknown function in {_shown(self.text)}; allowed functions: {allowed}")
            if len(node.args) != 1 or node.keywords:
                raise ExpressionError(
                    f"function {node.func.id} takes exactly one argument in "
                    f"{_shown(self.text)}")
            self._check(node.args[0], names)
        else:
            raise ExpressionError(
                f"unsupported construct {type(node).__name__} in {_shown(self.text)}; "
                "use numbers, names, + - * / ** and parentheses")

    def __call__(self, env):
        """Evaluate the formula in float64.

        Parameters
        ----------
        env : mapping of str to float or array_like
            Values of the names the formula reads; arrays of one shape evaluate the
            formula element by element.

        Returns
        -------
        value : float or ndarray
            A float for scalar values. ``nan`` where the arithmetic is undefined
            (division by zero, zero to a negative power, logarithm of a non-positive
            number, square root of a negative one, ``inf - inf``); ``inf`` or ``-inf``
            where a value overflows float64 (``N**N**N``, ``exp(links)``).

        Raises
        ------
        ExpressionError
            If a name the formula reads is missing from `env`, or its value is not a
            number.
        """
        missing = self.names - set(env)
        if missing:
            raise ExpressionError(
                f"formula {_shown(self.text)} reads unknown name(s): "
                f"{', '.join(sorted(missing))}")
        values = {}
        for name in self.names:
            try:
                values[name] = np.asarray(env[name], dtype=np.float64)
            except (TypeError, ValueError, OverflowError):
                raise ExpressionError(f"formula {_shown(self.text)}: {name} = "
                                      f"{env[name]!r} is not a number") from None
        with np.errstate(all="ignore"):
            value = self._eval(self._tree, values)
        value = np.asarray(value, dtype=np.float64)
        return float(value) if value.ndim == 0 else value

    def _eval(self, node, env):
        if isinstance(node, ast.Constant):
            return np.float64(node.value)
        if isinstance(node, ast.Name):
            return env[node.id]
        if isinstance(node, ast.BinOp):
            return _BINARY[type(node.op)](self._eval(node.left, env), self._eval(node.right, env))
        if isinstance(node, ast.UnaryOp):
            return _UNARY[type(node.op)](self._eval(node.operand, env))
        return FUNCTIONS[node.func.id](self._eval(node.args[0], env))

    def __repr__(self):
        return f"Expression({self.text!r})"
