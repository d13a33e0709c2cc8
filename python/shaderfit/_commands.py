"""The other commands on arrays: evaluate, cost, codegen, fit and rational."""

from __future__ import annotations

import json
from typing import Mapping, Sequence

import numpy as np

from . import _shaderfit
from ._arrays import columns_of, name_of, vector_of, _is_dataframe
from ._errors import Error
from ._front import _columns_for
from ._search import _domain_texts


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


def evaluate(text: str, X, *, inputs: Sequence[str] | None = None, params=None,
             precision: str = "double") -> np.ndarray:
    """The formula on every row of X, as ``shaderfit eval`` computes it: in float64, or with
    ``precision`` "float" or "half" every operation rounded as a shader does (docs/precision.md).
    A DataFrame's columns are taken by the names the formula uses; a plain array's by position
    (named x0, x1, ... or by ``inputs``)."""
    if _is_dataframe(X):
        f = formula(text, inputs, params)
        return f.evaluate(_columns_for(f, X, None), precision)
    columns, names = columns_of(X, inputs)
    return formula(text, names, params).evaluate(columns, precision)


def cost(text: str, *, inputs: Sequence[str] | None = None, params=None,
         target: str = "sass", uniform: Sequence[str] = ()) -> dict:
    """Instruction counts per target (sass, ptx, generic, sass-half2, rdna2, rdna3) and the
    listing for ``target``: the shaderfit.cost/1 document of ``shaderfit cost --json``
    (docs/cost-model.md). With ``uniform`` (per-material inputs) the counts are per pixel, with
    ``per_material`` beside."""
    return json.loads(formula(text, inputs, params).cost_json(target, list(uniform)))


def codegen(text: str, lang: str = "glsl", *, name: str = "shaderfit_formula",
            inputs: Sequence[str] | None = None, params=None, uniform: Sequence[str] = (),
            precision: str = "float") -> str:
    """The formula as a source file in glsl, hlsl, cuda, cpp or metal that compiles as printed;
    parameters given with values are baked in as constants. With ``uniform`` (per-material
    inputs) the code is in two parts: the values computed once per material, then the pixel.
    ``precision="half"`` prints the half form (GLSL float16_t, HLSL and Metal half, CUDA
    __half with a __half2 twin; docs/precision.md)."""
    return formula(text, inputs, params).code(lang, name, list(uniform), precision)


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


# The library's names for what fit's and rational's keywords set, and the keywords.
_FIELD_KEYWORDS = {
    "FitSetup::reference_source": "reference_file", "FitSetup::reference_path": "reference_file",
    "FitSetup::definitions": "define", "FitSetup::parameters": "params",
    "FitSetup::formula": "text", "FitSetup::target": "y",
    "RationalSetup::reference_source": "reference_file",
    "RationalSetup::reference_path": "reference_file",
}


def _keyword_error(e: Error) -> Error:
    """The error with FitSetup's and RationalSetup's fields written as the keywords that set
    them (``FitSetup::reference`` as ``reference``)."""
    def keyword(field: str) -> str:
        if field in _FIELD_KEYWORDS:
            return _FIELD_KEYWORDS[field]
        for prefix in ("FitSetup::", "RationalSetup::"):
            if field.startswith(prefix):
                return field[len(prefix):]
        return field
    message = e.message
    for field in sorted(_FIELD_KEYWORDS, key=len, reverse=True):
        message = message.replace(field, _FIELD_KEYWORDS[field])
    for prefix in ("FitSetup::", "RationalSetup::"):
        message = message.replace(prefix, "")
    return Error(message, keyword(e.source), e.line, e.column)


def _shader(reference_file, function: str | None) -> tuple[str, str, str]:
    """The source text, path and function of ``reference_file`` (empty strings without one)."""
    if reference_file is None:
        return "", "", function or ""
    import os
    path = os.fspath(reference_file)
    try:
        with open(path, encoding="utf-8") as f:
            text = f.read()
    except OSError as e:
        raise Error(f"cannot read the reference file: {e.strerror}", path) from None
    return text, path, function or ""


def fit(text: str, X=None, y=None, *, params=None, groups=None,
        per_group: Sequence[str] | None = None, inputs: Sequence[str] | None = None,
        weights=None, loss: str = "mse", solver: str = "auto", constraints: Sequence[str] = (),
        transform: str = "", baselines: Sequence[str] = (), max_iterations: int = 100,
        threads: int = 0, reference: str | None = None, domain=None,
        define: Sequence[str] | str = (), samples: int = 0, reference_file=None,
        function: str | None = None) -> FitResult:
    """The free parameters of a fixed formula, fitted to y: globally, or per group.

    params: the parameters' names, or {name: start}. groups: one label per row; the parameters
    in ``per_group`` (all of them when it is None) then take one value per group. loss: mse,
    log or max_abs (minimax). constraints, transform, baselines: as ``shaderfit fit`` reads them
    (docs/fit.md).
    Instead of y, a ``reference`` in the reference language (docs/reference.md: ``"acos(x)"``,
    ``"erf(x / sqrt(2))"``, a built-in's name) over X's columns, or a GLSL or HLSL function
    (``reference_file=PATH, function=NAME``) whose parameters are columns; instead of X, a
    ``domain`` sampled by shaderfit (``{"x": (0, 1)}`` for the default design, ``(0, 1, 64)``
    for 64 midpoints; ``samples`` sizes the design). ``define``: derived columns
    ``"name = formula"`` in the reference language.
    """
    source, path, function = _shader(reference_file, function)
    defines = [define] if isinstance(define, str) else list(define)
    domain_texts = _domain_texts(domain)
    if y is None and not reference and not source:
        raise TypeError("no reference: give y, reference=FORMULA or reference_file=PATH")
    if y is not None and (reference or source):
        raise TypeError("give either y or a reference (reference=..., reference_file=...), "
                        "not both")
    if domain_texts and X is not None:
        raise TypeError("give either X or a domain to sample, not both")
    if X is None and not domain_texts:
        raise TypeError("no data: give X, or a domain to sample")
    columns, names, rows = [], [], 0
    if X is not None:
        columns, names = columns_of(X, inputs)
        rows = columns[0].shape[0] if columns else 0
    target = None if y is None else vector_of(y, rows, "y")
    target_name = "y" if y is None else name_of(y, "y")
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
    try:
        text_doc = _shaderfit.fit(text, columns, names, target, target_name, w, labels,
                                  group_name, texts, spec, loss, solver, list(constraints),
                                  transform, list(baselines), max_iterations, threads,
                                  reference or "", defines, domain_texts, int(samples), source,
                                  path, function)
    except Error as e:
        raise _keyword_error(e) from None
    return FitResult(json.loads(text_doc), group_name if labels is not None else "")


def rational(target: str = "", *, variable: str = "x", domain="",
             conditions: Sequence[str] = (), forms: Sequence[str] = (),
             transforms: Sequence[str] = (), parameters: Sequence[str] = (), count: int = 0,
             fit: str = "none", relative_minimax: bool = False, rank_by: str = "rmse",
             reference_file=None, function: str | None = None) -> dict:
    """Rational approximations from Schlick's kernel conditions, optionally minimax-tuned:
    the shaderfit.rational/1 document of ``shaderfit rational --json`` (docs/rational.md).
    target: a built-in name or a formula in ``variable`` in the reference language
    (docs/reference.md: ``"acos(x)"``, ``"erf(x)"``); or ``reference_file=PATH, function=NAME``,
    a GLSL or HLSL function whose parameter without a value in ``parameters`` is the variable.
    domain: (lo, hi), "lo,hi", "x=lo:hi" or {"x": (lo, hi)}."""
    if isinstance(domain, dict):
        domain = ",".join(_domain_texts(domain))
    elif not isinstance(domain, str):
        lo, hi = domain
        domain = f"{float(lo)!r},{float(hi)!r}"
    source, path, function = _shader(reference_file, function)
    try:
        return json.loads(_shaderfit.rational(target, variable, domain, list(conditions),
                                              list(forms), list(transforms), list(parameters),
                                              count, fit, relative_minimax, rank_by, source, path,
                                              function))
    except Error as e:
        raise _keyword_error(e) from None
