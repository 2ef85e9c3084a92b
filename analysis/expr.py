"""A tiny, safe arithmetic expression evaluator for claim axes.

Claims name their measured quantities as short formulas over the fields of one run,
for example ``"links / nodes"``, ``"1/eps"`` or ``"g"``. This module parses such a formula
once, checks that it uses only arithmetic and known names, and evaluates it over a
mapping of numbers. It never calls :func:`eval`: the formula is parsed with :mod:`ast`
and walked node by node, and anything but numbers, names, ``+ - * / **``, parentheses
and a few named functions is rejected.
"""

import ast
import math
import operator

__all__ = ["Expression", "ExpressionError", "FUNCTIONS"]

#: Functions a formula may call, by name. All take and return one number.
FUNCTIONS = {
    "log": math.log,
    "log2": math.log2,
    "log10": math.log10,
    "sqrt": math.sqrt,
    "exp": math.exp,
    "abs": abs,
}

_BINARY = {
    ast.Add: operator.add,
    ast.Sub: operator.sub,
    ast.Mult: operator.mul,
    ast.Div: operator.truediv,
    ast.Pow: operator.pow,
}
_UNARY = {ast.UAdd: operator.pos, ast.USub: operator.neg}


class ExpressionError(ValueError):
    """A formula that does not parse, uses a forbidden construct or an unknown name."""


class Expression:
    """A parsed arithmetic formula over named numbers.

    Parameters
    ----------
    text : str
        The formula, e.g. ``"links / nodes"``. Allowed: numbers, names, the operators
        ``+ - * / **``, unary minus, parentheses and calls to the functions in
        :data:`FUNCTIONS` with one argument.

    Attributes
    ----------
    text : str
        The formula as given.
    names : frozenset of str
        The variable names the formula reads (function names excluded).

    Raises
    ------
    ExpressionError
        If the formula is empty, does not parse or uses a construct outside the list above.

    Examples
    --------
    >>> Expression("links / nodes")({"links": 10, "nodes": 4})
    2.5
    >>> sorted(Expression("1/eps").names)
    ['eps']
    """

    def __init__(self, text):
        if not isinstance(text, str) or not text.strip():
            raise ExpressionError("formula must be a non-empty string")
        self.text = text
        try:
            tree = ast.parse(text.strip(), mode="eval")
        except SyntaxError as exc:
            raise ExpressionError(f"cannot parse formula {text!r}: {exc.msg}") from None
        names = set()
        self._check(tree.body, names)
        self._tree = tree.body
        self.names = frozenset(names)

    def _check(self, node, names):
        # Accept only the node types the evaluator knows, and collect variable names.
        if isinstance(node, ast.Constant):
            if isinstance(node.value, bool) or not isinstance(node.value, (int, float)):
                raise ExpressionError(f"only numbers are allowed as constants in {self.text!r}")
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
                    f"unknown function in {self.text!r}; allowed functions: {allowed}")
            if len(node.args) != 1 or node.keywords:
                raise ExpressionError(
                    f"function {node.func.id} takes exactly one argument in {self.text!r}")
            self._check(node.args[0], names)
        else:
            raise ExpressionError(
                f"unsupported construct {type(node).__name__} in {self.text!r}; "
                "use numbers, names, + - * / ** and parentheses")

    def __call__(self, env):
        """Evaluate the formula.

        Parameters
        ----------
        env : mapping of str to float
            Values of the names the formula reads.

        Returns
        -------
        value : float
            The result; ``nan`` if the arithmetic is undefined (division by zero,
            logarithm of a non-positive number).

        Raises
        ------
        ExpressionError
            If a name the formula reads is missing from `env`.
        """
        missing = self.names - set(env)
        if missing:
            raise ExpressionError(
                f"formula {self.text!r} reads unknown name(s): {', '.join(sorted(missing))}")
        try:
            return float(self._eval(self._tree, env))
        except (ZeroDivisionError, ValueError, OverflowError):
            return math.nan

    def _eval(self, node, env):
        if isinstance(node, ast.Constant):
            return node.value
        if isinstance(node, ast.Name):
            return env[node.id]
        if isinstance(node, ast.BinOp):
            return _BINARY[type(node.op)](self._eval(node.left, env), self._eval(node.right, env))
        if isinstance(node, ast.UnaryOp):
            return _UNARY[type(node.op)](self._eval(node.operand, env))
        return FUNCTIONS[node.func.id](self._eval(node.args[0], env))

    def __repr__(self):
        return f"Expression({self.text!r})"
