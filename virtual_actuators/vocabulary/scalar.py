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


def atan2(y: object, x: object) -> object:
    """``math.atan2(y, x)``, or its op."""
    program = _program(y, x)
    return math.atan2(y, x) if program is None else program.binary("atan2", y, x)


def hypot(x: object, y: object) -> object:
    """``math.hypot(x, y)`` of two numbers, or its op (CPython's algorithm: the same bits)."""
    program = _program(x, y)
    return math.hypot(x, y) if program is None else program.binary("hypot", x, y)


def minimum(a: object, b: object) -> object:
    """Python's ``min(a, b)``: ``b if b < a else a``, or its op."""
    program = _program(a, b)
    return min(a, b) if program is None else program.binary("min", a, b)


def maximum(a: object, b: object) -> object:
    """Python's ``max(a, b)``: ``b if b > a else a``, or its op."""
    program = _program(a, b)
    return max(a, b) if program is None else program.binary("max", a, b)


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


def logical_and(a: object, b: object) -> object:
    """``a and b`` evaluated both ways (1.0 or 0.0 when traced)."""
    program = _program(a, b)
    return bool(a) and bool(b) if program is None else program.binary("and", a, b)


def logical_or(a: object, b: object) -> object:
    """``a or b`` evaluated both ways (1.0 or 0.0 when traced)."""
    program = _program(a, b)
    return bool(a) or bool(b) if program is None else program.binary("or", a, b)


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
