"""The built-in data sets as arrays."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from . import _shaderfit


class Dataset(NamedTuple):
    """X (rows x inputs, float64), y, the inputs' names, the target's name, and every column of
    the data set by name (numbers as float64 arrays, text as lists of str)."""

    X: np.ndarray
    y: np.ndarray
    inputs: list
    target: str
    columns: dict


def builtin(name: str, seed: int = 1, rows: int = 4096, inputs=("r0", "x"),
            target: str = "R") -> Dataset:
    """A built-in data set (``names()`` lists them), drawn from ``seed`` as the CLI's
    ``--dataset NAME --data-seed SEED`` draws it."""
    columns = _shaderfit.dataset(name, seed, rows)
    X = np.column_stack([columns[n] for n in inputs])
    return Dataset(X, np.asarray(columns[target]), list(inputs), target, columns)


def fresnel_seed(seed: int = 1, rows: int = 4096, half_range: bool = False) -> Dataset:
    """Seed post 001's Fresnel data: inputs r0 and x = 1 - cos(theta), target R (exact
    unpolarized Fresnel reflectance); ``columns`` also holds cos_theta, ior_n, ior_k, kind and
    material. The same rows as ``shaderfit search --dataset fresnel-seed --data-seed SEED``."""
    return builtin("fresnel-seed-half" if half_range else "fresnel-seed", seed, rows)


def names() -> list:
    return list(_shaderfit.dataset_names())
