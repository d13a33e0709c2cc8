"""The other commands on arrays: evaluate, cost, codegen, fit and rational."""

from __future__ import annotations

import json
from typing import Mapping, Sequence

import numpy as np

from . import _shaderfit
from ._arrays import columns_of, name_of, vector_of, _is_dataframe
from ._front import _columns_for


def _parameters(params) -> tuple[list[str], list[float]]:
    """Names and values from a mapping {name: value}, or names alone from a list."""
    if params is None:
        return [], []
    if isinstance(params, str):
        params = [params]
    if isinstance(params, Mapping):
        return [str(k) for k in params], [float(v) for v in params.values()]
    return [str(p) for p in params], []


def formula(text: str, inputs: Sequence[str] | None = None, params=None) -> _shaderfit.Formula:
    """A parsed formula: every identifier that is not a parameter is an input (in order of
    use) unless ``inputs`` lists them."""
    names, values = _parameters(params)
    return _shaderfit.parse(text, list(inputs or []), names, values)


def evaluate(text: str, X, *, inputs: Sequence[str] | None = None, params=None) -> np.ndarray:
    """The formula on every row of X, in float64, as ``shaderfit eval`` computes it. A
    DataFrame's columns are taken by the names the formula uses; a plain array's by position
    (named x0, x1, ... or by ``inputs``)."""
    if _is_dataframe(X):
        f = formula(text, inputs, params)
        return f.evaluate(_columns_for(f, X, None))
    columns, names = columns_of(X, inputs)
    return formula(text, names, params).evaluate(columns)


def cost(text: str, *, inputs: Sequence[str] | None = None, params=None,
         target: str = "sass") -> dict:
    """Instruction counts per target (sass, ptx, generic) and the listing for ``target``: the
    shaderfit.cost/1 document of ``shaderfit cost --json`` (docs/cost-model.md)."""
    return json.loads(formula(text, inputs, params).cost_json(target))


def codegen(text: str, lang: str = "glsl", *, name: str = "shaderfit_formula",
            inputs: Sequence[str] | None = None, params=None) -> str:
    """The formula as a source file in glsl, hlsl, cuda, cpp or metal that compiles as printed;
    parameters given with values are baked in as constants."""
    return formula(text, inputs, params).code(lang, name)


def latex(text: str, *, inputs: Sequence[str] | None = None, params=None, digits: int = 0) -> str:
    return formula(text, inputs, params).latex(digits)


class FitResult:
    """A fit's result: ``parameters`` (name -> value; name -> {group: value} for per-group
    ones), ``mse``, ``blocks`` (one per group), ``formula`` (with the values in it when there is
    one block), and ``json`` (the shaderfit.fit/1 document of ``shaderfit fit --json``)."""

    def __init__(self, document: dict, group_column: str = ""):
        self.json = document
        blocks = document.get("blocks") or []
        self.blocks = blocks
        names = document.get("parameters") or []
        names = [p["name"] if isinstance(p, dict) else p for p in names]
        self.parameters: dict = {}
        for b in blocks:
            values = b.get("parameters") or {}
            for k, v in (values.items() if isinstance(values, dict) else zip(names, values)):
                if len(blocks) == 1:
                    self.parameters[k] = v
                else:
                    label = b.get("label", "")
                    if group_column and label.startswith(group_column + "="):
                        label = label[len(group_column) + 1:]
                    self.parameters.setdefault(k, {})[label] = v
        self.mse = document.get("mse")
        self.formula = document.get("formula")

    def __repr__(self) -> str:
        return f"<FitResult parameters={self.parameters}>"


def fit(text: str, X, y, *, params=None, groups=None, per_group: Sequence[str] | None = None,
        inputs: Sequence[str] | None = None, weights=None, loss: str = "mse",
        solver: str = "auto", constraints: Sequence[str] = (), transform: str = "",
        baselines: Sequence[str] = (), max_iterations: int = 100, threads: int = 0) -> FitResult:
    """The free parameters of a fixed formula, fitted to y: globally, or per group.

    params: the parameters' names, or {name: start}. groups: one label per row; the parameters
    in ``per_group`` (all of them when it is None) then take one value per group. loss: mse,
    log or max_abs (minimax). constraints, transform, baselines: as ``shaderfit fit`` reads them
    (docs/fit.md).
    """
    columns, names = columns_of(X, inputs)
    rows = columns[0].shape[0] if columns else 0
    target = vector_of(y, rows, "y")
    target_name = name_of(y, "y")
    if target_name in names:
        target_name = "__target"
    param_names, starts = _parameters(params)
    texts = [f"{n}={v!r}" for n, v in zip(param_names, starts)] if starts else param_names
    labels = None
    group_name = "group"
    while group_name in names:
        group_name = "_" + group_name
    spec: list[str] = []
    if groups is not None:
        labels = [str(g) for g in np.asarray(groups).ravel().tolist()]
        if len(labels) != rows:
            raise ValueError(f"groups has {len(labels)} labels for {rows} rows of X")
        spec = [f"{p}:{group_name}" for p in (param_names if per_group is None else per_group)]
    w = None if weights is None else vector_of(weights, rows, "weights")
    text_doc = _shaderfit.fit(text, columns, names, target, target_name, w, labels, group_name,
                              texts, spec, loss, solver, list(constraints), transform,
                              list(baselines), max_iterations, threads)
    return FitResult(json.loads(text_doc), group_name if labels is not None else "")


def rational(target: str, *, variable: str = "x", domain: str | Sequence[float] = "",
             conditions: Sequence[str] = (), forms: Sequence[str] = (),
             transforms: Sequence[str] = (), parameters: Sequence[str] = (), count: int = 0,
             fit: str = "none", relative_minimax: bool = False, rank_by: str = "rmse") -> dict:
    """Rational approximations from Schlick's kernel conditions, optionally minimax-tuned:
    the shaderfit.rational/1 document of ``shaderfit rational --json`` (docs/rational.md).
    target: a built-in name or a formula in ``variable``; domain: (lo, hi) or "lo,hi"."""
    if not isinstance(domain, str):
        lo, hi = domain
        domain = f"{float(lo)!r},{float(hi)!r}"
    return json.loads(_shaderfit.rational(target, variable, domain, list(conditions),
                                          list(forms), list(transforms), list(parameters),
                                          count, fit, relative_minimax, rank_by))
