"""The search's result: a Pareto front of members, cheapest first."""

from __future__ import annotations

import json
from typing import Iterator, Sequence

import numpy as np

from . import _shaderfit
from ._arrays import columns_of, _is_dataframe

# A member's figures, as the search's JSON names them (docs/search.md, "JSON").
METRICS = ("mse", "rmse", "max_abs", "max_rel", "rel", "log")
LANGUAGES = ("glsl", "hlsl", "cuda", "cpp", "metal")


class Cost(float):
    """A member's cost in the search's measure (SASS instructions by default), and, called with
    a target, its instruction count there: ``member.cost`` is 4.0, ``member.cost("ptx")`` 5."""

    _formula: _shaderfit.Formula

    def __new__(cls, value: float, formula: _shaderfit.Formula, uniform: Sequence[str] = ()):
        self = super().__new__(cls, value)
        self._formula = formula
        self._uniform = list(uniform)  # per-material inputs: the count is per pixel
        return self

    def __call__(self, target: str = "sass") -> int:
        doc = json.loads(self._formula.cost_json(target, self._uniform))
        return int(doc["targets"][target]["instructions"])

    def __reduce__(self):
        return (Cost, (float(self), self._formula, self._uniform))


def _columns_for(formula: _shaderfit.Formula, X, inputs: Sequence[str] | None):
    """X's columns in the order of the formula's variables: by name for a DataFrame (or with
    `inputs`), by position for a plain array."""
    variables = list(formula.variables)
    if _is_dataframe(X):
        columns, names = columns_of(X, inputs=variables if inputs is None else inputs)
    else:
        columns, names = columns_of(X, inputs=inputs)
        if inputs is None:
            if len(columns) != len(variables):
                raise ValueError(f"X has {len(columns)} columns; the formula's inputs are "
                                 f"{', '.join(variables)} ({len(variables)})")
            return columns
    by_name = dict(zip(names, columns))
    missing = [v for v in variables if v not in by_name]
    if missing:
        raise ValueError(f"X has no column {', '.join(missing)} (columns: {', '.join(names)})")
    return [by_name[v] for v in variables]


class Member:
    """One formula of a front.

    Attributes: ``formula`` (full precision; ``str(member)`` shows constants as float32 needs
    them), ``cost`` (see Cost), ``loss`` (the search's loss), each metric (``mse``, ``rmse``,
    ``max_abs``, ``max_rel``, ``rel``, ``log``), ``nodes``, ``time_s`` (when it was found),
    ``origin`` ("enumeration", "evolution", "start", "power_sum", "polynomial", "material",
    "reference", "rewrite" or "shape"), ``minor_step`` (not shown: see the min_step option),
    ``float32_stable``, ``float32_max_abs_diff``, ``float32_max_abs`` and ``float32_max_rel``
    (the error computed in float32 as a shader does), ``half_max_abs`` and ``half_max_rel`` (in
    half, docs/precision.md), ``parameters`` (fitted constants by name),
    ``inputs``, and ``json`` (the member as the CLI's JSON writes it). With a reference:
    ``max_abs`` includes the errors found between the samples (``checked_between_samples``,
    ``worst_point``), and with ``certify=True`` ``certified_max_abs`` bounds the error on the
    whole domain (None when not certified, inf when no finite bound was found) and
    ``certified_converged`` says whether the bound met its tolerance.
    """

    def __init__(self, document: dict, formula: _shaderfit.Formula):
        self.json = document
        self._formula = formula
        self.formula: str = document["formula"]
        self.formula_display: str = document.get("formula_display", self.formula)
        # With per-material inputs (search's uniform=): cost is per pixel, material_cost (SASS)
        # once per material.
        self.uniform: list = list(document.get("uniform") or [])
        self.material_cost = _number(document.get("material_cost", 0))
        self.cost = Cost(_number(document.get("cost")), formula, self.uniform)
        self.loss = _number(document.get("loss"))
        for m in METRICS:
            setattr(self, m, _number(document.get(m)))
        self.nodes = int(document.get("nodes") or 0)
        self.time_s = _number(document.get("time_s"))
        self.origin: str = document.get("origin", "")
        # Lowers the loss of the cheaper member shown before it by less than the minimum step
        # (the min_step option): in the front, but not printed nor taken as the knee.
        self.minor_step: bool = bool(document.get("minor_step", False))
        self.float32_stable = bool(document.get("float32_stable", True))
        self.float32_max_abs_diff = _number(document.get("float32_max_abs_diff"))
        self.float32_max_abs = _number(document.get("float32_max_abs"))
        self.float32_max_rel = _number(document.get("float32_max_rel"))
        self.half_max_abs = _number(document.get("half_max_abs"))
        self.half_max_rel = _number(document.get("half_max_rel"))
        self.checked_between_samples = "max_abs_checked" in document
        self.worst_point = list(document.get("worst_point") or [])
        # None: not certified; inf: no finite bound was found (the JSON's null).
        self.certified_max_abs = None
        if "certified_max_abs" in document:
            bound = document["certified_max_abs"]
            self.certified_max_abs = float("inf") if bound is None else float(bound)
        self.certified_converged = bool(document.get("certified_converged", False))
        self.certify_note: str = document.get("certify_note", "")
        self.parameters: dict = dict(document.get("fitted_parameters") or {})
        self.inputs: list = list(formula.variables)

    @property
    def metrics(self) -> dict:
        return {m: getattr(self, m) for m in METRICS}

    def predict(self, X, inputs: Sequence[str] | None = None) -> np.ndarray:
        """The formula on every row of X, in float64 (the library's CPU evaluator)."""
        return self._formula.evaluate(_columns_for(self._formula, X, inputs))

    def code(self, lang: str = "glsl", name: str = "shaderfit_formula",
             precision: str = "float") -> str:
        """A source file with the formula as one function (glsl, hlsl, cuda, cpp or metal), its
        constants baked in, that the language's compiler accepts as printed (in two parts with
        per-material inputs); ``precision="half"`` prints the half form (docs/precision.md)."""
        return self._formula.code(lang, name, self.uniform, precision)

    def latex(self, digits: int = 0) -> str:
        return self._formula.latex(digits)

    def sympy(self):
        """The formula as a sympy expression (needs sympy)."""
        from ._sympy import to_sympy

        return to_sympy(self.formula, self.inputs)

    def __str__(self) -> str:
        return self.formula_display

    def __repr__(self) -> str:
        return f"<Member cost={float(self.cost):g} loss={self.loss:.4g}: {self.formula_display}>"

    def _repr_latex_(self) -> str:
        return f"${self.latex()}$"


def _number(v) -> float:
    return float("nan") if v is None else float(v)


class Front(Sequence):
    """A search's Pareto front, cheapest member first (the error falls along it).

    ``front[i]`` and iteration give Members; ``best()`` picks one; ``to_pandas()`` and
    ``to_json()`` give the whole; ``interrupted`` says whether Ctrl-C ended the search;
    ``summary`` and ``options`` are those of the JSON (the options with "auto" resolved).
    """

    def __init__(self, run: _shaderfit.SearchRun):
        self._text = run.json()
        self._summary_text = run.summary_text()
        self._build(run.formulas())

    def _build(self, formulas) -> None:
        document = json.loads(self._text)
        self.members = [Member(m, f) for m, f in zip(document["front"], formulas)]
        self.inputs: list = list(document.get("inputs") or [])
        self.summary: dict = document.get("summary", {})
        self.options: dict = document.get("options", {})
        self.data: dict = document.get("data", {})
        self.interrupted: bool = bool(self.summary.get("interrupted", False))
        self.termination: str = self.summary.get("termination", "")

    def __getstate__(self):
        return {"text": self._text, "summary_text": self._summary_text,
                "formulas": [m._formula for m in self.members]}

    def __setstate__(self, state):
        self._text = state["text"]
        self._summary_text = state["summary_text"]
        self._build(state["formulas"])

    def __len__(self) -> int:
        return len(self.members)

    def __getitem__(self, i):
        return self.members[i]

    def __iter__(self) -> Iterator[Member]:
        return iter(self.members)

    def choose(self, max_cost: float | None = None, max_error: float | None = None):
        """(member, why): the member best() returns, and one line saying why."""
        if max_error is not None:
            rule = f"error={float(max_error)!r}"
        elif max_cost is not None:
            rule = f"cost={float(max_cost)!r}"
        else:
            rule = "knee"
        # The knee passes over the minor steps the front does not show; a limit takes the best
        # of every member.
        members = self.members
        if rule == "knee":
            members = [m for m in members if not m.minor_step]
        if max_cost is not None and max_error is not None:
            members = [m for m in members if float(m.cost) <= max_cost]
            if not members:
                raise ValueError(f"max_cost: no member of the front costs at most {max_cost:g}")
        if not members:
            raise ValueError("the front is empty")
        index, why = _shaderfit.choose([float(m.cost) for m in members],
                                       [m.loss for m in members],
                                       [m.origin for m in members], rule,
                                       self.options.get("loss", "error"))
        return members[index], why

    def best(self, max_cost: float | None = None, max_error: float | None = None) -> Member:
        """The member to use: with neither limit, the knee of the front (where spending more
        cost stops buying much accuracy); with max_cost, the most accurate member that costs at
        most that; with max_error, the cheapest whose loss is at most that (among those within
        max_cost, when both are given). Where no member meets a limit, the nearest one."""
        return self.choose(max_cost, max_error)[0]

    def to_json(self) -> str:
        """The result as ``shaderfit search --json`` writes it (docs/search.md, "JSON")."""
        return self._text

    def to_pandas(self):
        """One row per member (needs pandas)."""
        import pandas as pd

        rows = []
        for m in self.members:
            row = {"formula": m.formula_display, "cost": float(m.cost), "loss": m.loss}
            row.update(m.metrics)
            row.update(nodes=m.nodes, time_s=m.time_s, origin=m.origin,
                       float32_stable=m.float32_stable, minor_step=m.minor_step,
                       formula_exact=m.formula)
            rows.append(row)
        return pd.DataFrame(rows)

    def __repr__(self) -> str:
        return self._summary_text
