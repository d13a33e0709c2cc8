"""Formulas as sympy expressions (sympy is optional)."""

from __future__ import annotations

from typing import Sequence


def to_sympy(text: str, inputs: Sequence[str]):
    import sympy
    from sympy.parsing.sympy_parser import (convert_xor, parse_expr,
                                            standard_transformations)

    def select(a, b, c):
        return sympy.Piecewise((b, a), (c, True))

    names = {n: sympy.Symbol(n, real=True) for n in inputs}
    functions = {
        "sqrt": sympy.sqrt, "rsqrt": lambda a: 1 / sympy.sqrt(a), "rcp": lambda a: 1 / a,
        "exp2": lambda a: 2**a, "log2": lambda a: sympy.log(a, 2), "exp": sympy.exp,
        "log": sympy.log, "abs": sympy.Abs, "saturate": lambda a: sympy.Min(sympy.Max(a, 0), 1),
        "sin": sympy.sin, "cos": sympy.cos, "sign": sympy.sign, "min": sympy.Min,
        "max": sympy.Max, "pow": sympy.Pow, "fma": lambda a, b, c: a * b + c,
        "copysign": lambda a, b: sympy.Abs(a) * sympy.Piecewise((1, b >= 0), (-1, True)),
        "select": select, "pi": sympy.pi, "asin": sympy.asin, "acos": sympy.acos,
        "atan": sympy.atan, "atan2": sympy.atan2, "tanh": sympy.tanh, "erf": sympy.erf,
    }
    return parse_expr(text, local_dict={**functions, **names},
                      transformations=standard_transformations + (convert_xor,))
