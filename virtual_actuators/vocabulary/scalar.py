"""The math a lowerable hook or formula uses: floats in Python, ops when traced.

Each function takes floats (then it is `math`'s, or Python's ``min``/``max``) or traced values
(`traced.Sym`: it appends the same operation to the traced program), to the same bits.
``select(condition, a, b)`` replaces ``a if condition else b`` on a traced condition; the
comparisons of traced values give 1.0 or 0.0.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from .traced import Sym

__all__ = [
    "acos", "asin", "atan2", "clip", "cos", "cross", "dot", "exp", "hypot", "logical_and",
    "logical_not", "logical_or", "maximum", "minimum", "select", "sin", "sqrt", "tan",
]  # fmt: skip


def _program(*values: object):
    for value in values:
        if isinstance(value, Sym):
            return value.program
    return None


def _unary(name: str, function):
    def apply(x: object) -> object:
        if isinstance(x, Sym):
            return x.program.unary(name, x)
        return function(x)

    apply.__name__ = name
    apply.__doc__ = f"``math.{name}`` of a float, or its op on a traced value."
    return apply


sin = _unary("sin", math.sin)
cos = _unary("cos", math.cos)
tan = _unary("tan", math.tan)
asin = _unary("asin", math.asin)
acos = _unary("acos", math.acos)
sqrt = _unary("sqrt", math.sqrt)
exp = _unary("exp", math.exp)


def _binary(name: str, function):
    def apply(a: object, b: object) -> object:
        program = _program(a, b)
        return function(a, b) if program is None else program.binary(name, a, b)

    apply.__name__ = name
    apply.__doc__ = f"``{name}(a, b)`` of two floats, or its op on traced values."
    return apply


atan2 = _binary("atan2", math.atan2)  # math.atan2(y, x)
hypot = _binary("hypot", math.hypot)  # CPython's algorithm: the same bits
minimum = _binary("min", min)  # Python's min(a, b): b if b < a else a
maximum = _binary("max", max)  # Python's max(a, b): b if b > a else a
logical_and = _binary("and", lambda a, b: bool(a) and bool(b))  # both evaluated; 1.0 or 0.0
logical_or = _binary("or", lambda a, b: bool(a) or bool(b))  # when traced


def clip(x: object, low: object, high: object) -> object:
    """``min(max(x, low), high)``."""
    return minimum(maximum(x, low), high)


def select(condition: object, a: object, b: object) -> object:
    """``a if condition else b``; traced: an op that picks by ``condition != 0``."""
    program = _program(condition, a, b)
    if program is None:
        return a if condition else b
    return program.select(condition, a, b)


def logical_not(a: object) -> object:
    """``not a`` (1.0 or 0.0 when traced)."""
    return (not a) if not isinstance(a, Sym) else a.program.unary("not", a)


def dot(a: Sequence, b: Sequence) -> object:
    """``sum(a_i b_i)`` left to right (as ``sum`` adds from 0: the first term plus 0.0)."""
    total: object = 0.0
    for x, y in zip(a, b, strict=True):
        total = total + x * y
    return total


def cross(a: Sequence, b: Sequence) -> tuple:
    """``a x b`` of two 3-vectors, as a tuple."""
    (a0, a1, a2), (b0, b1, b2) = a, b
    return (a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0)
