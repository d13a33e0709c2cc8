"""Inputs as the library takes them: one 1-D float32 or float64 column per input.

A column of a 2-D array or a DataFrame is passed as a view (no copy); the module then converts
each column once into the float64 columns of the search's problem. Only columns of another
numeric dtype (integers, booleans) are converted here first.
"""

from __future__ import annotations

import re
from typing import Sequence

import numpy as np

_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")


def _is_dataframe(x) -> bool:
    return type(x).__name__ == "DataFrame" and hasattr(x, "columns") and hasattr(x, "dtypes")


def _numeric(values: np.ndarray, what: str) -> np.ndarray:
    """`values` as float32 or float64 (a view when it already is one of them)."""
    kind = values.dtype.kind
    if values.dtype in (np.float32, np.float64):
        return values
    if kind in "biu":
        return values.astype(np.float64)
    if kind == "f":  # float16, longdouble
        return values.astype(np.float64)
    if kind == "O":
        try:
            return values.astype(np.float64)
        except (TypeError, ValueError):
            pass
    raise TypeError(f"{what} is not numeric (dtype {values.dtype})")


def check_names(names: Sequence[str], what: str = "inputs") -> list[str]:
    names = [str(n) for n in names]
    for n in names:
        if not _IDENTIFIER.match(n):
            raise ValueError(
                f"{what}: '{n}' is not a name formulas can use (letters, digits and _, "
                f"not starting with a digit); name the columns with inputs=[...]")
    seen = set()
    for n in names:
        if n in seen:
            raise ValueError(f"{what}: '{n}' is given twice")
        seen.add(n)
    return names


def columns_of(X, inputs: Sequence[str] | None = None, what: str = "X"):
    """(columns, names): X's columns as 1-D float32/float64 arrays, and their names.

    X is a 2-D array (any order, float32 or float64 used as they are) or a pandas DataFrame,
    whose column names become the names (``inputs`` then picks columns by name). A plain
    array's columns are named by ``inputs``, or x0, x1, ... without it.
    """
    if _is_dataframe(X):
        all_names = [str(c) for c in X.columns]
        names = list(inputs) if inputs is not None else all_names
        for n in names:
            if n not in all_names:
                raise ValueError(f"inputs: no column '{n}' in the DataFrame "
                                 f"(columns: {', '.join(all_names)})")
        by_name = dict(zip(all_names, X.columns))
        columns = [_numeric(np.asarray(X[by_name[n]].to_numpy()), f"column '{n}'")
                   for n in names]
        return columns, check_names(names)
    if isinstance(X, (str, bytes)) or X is None:
        raise TypeError(f"{what} must be a 2-D array or a DataFrame, not {type(X).__name__}")
    array = np.asarray(X)
    if array.ndim != 2:
        hint = "; use X.reshape(-1, 1) for one input" if array.ndim == 1 else ""
        raise ValueError(f"{what} must be 2-D (rows, inputs); got shape {array.shape}{hint}")
    array = _numeric(array, what)
    if inputs is None:
        names = [f"x{i}" for i in range(array.shape[1])]
    else:
        names = list(inputs)
        if len(names) != array.shape[1]:
            raise ValueError(f"inputs: {len(names)} names for the {array.shape[1]} columns of {what}")
    return [array[:, j] for j in range(array.shape[1])], check_names(names)


def vector_of(y, rows: int | None, what: str = "y") -> np.ndarray:
    """y as a 1-D float32/float64 array (a view where it can be) of `rows` values."""
    if _is_dataframe(y):
        if y.shape[1] != 1:
            raise ValueError(f"{what} must be one column; got {y.shape[1]}")
        y = y.iloc[:, 0]
    if isinstance(y, (str, bytes)) or y is None:
        raise TypeError(f"{what} must be a 1-D array, not {type(y).__name__}")
    array = np.asarray(y.to_numpy() if hasattr(y, "to_numpy") else y)
    if array.ndim == 2 and array.shape[1] == 1:
        array = array[:, 0]
    if array.ndim != 1:
        raise ValueError(f"{what} must be 1-D; got shape {array.shape}")
    array = _numeric(array, what)
    if rows is not None and array.shape[0] != rows:
        raise ValueError(f"{what} has {array.shape[0]} values for {rows} rows of X")
    return array


def name_of(y, default: str = "y") -> str:
    """A Series' name, else `default`."""
    name = getattr(y, "name", None)
    return str(name) if isinstance(name, str) and name else default
