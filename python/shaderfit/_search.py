"""shaderfit.search: the Pareto front of error against GPU cost for samples of a function."""

from __future__ import annotations

import sys
from typing import Any, Callable, Sequence

import numpy as np

from . import _shaderfit
from ._arrays import columns_of, name_of, vector_of, _is_dataframe
from ._errors import Error, renamed
from ._front import Front
from ._options import Options

Progress = Callable[[dict], None]


def _interactive() -> bool:
    if hasattr(sys, "ps1") or "ipykernel" in sys.modules:
        return True
    return bool(getattr(sys.stderr, "isatty", lambda: False)())


class _Bar:
    """A tqdm bar over the time budget (or the evaluation budget, whichever is further)."""

    def __init__(self, time_s: float, evals: int | None):
        try:
            from tqdm.auto import tqdm
        except ImportError:
            raise ImportError("progress=True draws a bar with tqdm, which is not installed "
                              "(pip install tqdm); or pass a callable") from None

        self.time_s, self.evals = time_s, evals
        # The phase and counts go where tqdm puts the description, which it prints as given.
        self.bar = tqdm(total=1000, desc="", leave=False,
                        bar_format="search {percentage:3.0f}% |{bar}| {desc}")
        self.shown = 0

    def __call__(self, p: dict) -> None:
        done = p["elapsed_s"] / self.time_s
        if self.evals:
            done = max(done, p["candidates"] / self.evals)
        n = min(1000, int(done * 1000))
        if n > self.shown:
            self.bar.update(n - self.shown)
            self.shown = n
        self.bar.set_description_str(f"{p['phase']}, front {p['front_size']}, "
                                     f"{p['candidates_per_s']:.3g} candidates/s", refresh=False)

    def close(self) -> None:
        self.bar.close()


def _progress_for(progress, time_s: float, evals: int | None):
    """(callback, closer): the user's callback; a tqdm bar for progress=True, or for None when
    tqdm is installed and the session is interactive; else none."""
    if callable(progress):
        return progress, None
    if progress is None:
        progress = _interactive()
        if progress:
            try:
                import tqdm  # noqa: F401
            except ImportError:
                progress = False
    if not progress:
        return None, None
    bar = _Bar(time_s, evals)
    return bar, bar


def _domain_texts(domain) -> list[str]:
    """``{"x": (-1, 1)}``, ``{"t": (0, 1.5, 90)}``, ``"x=-1:1"`` or a list of such strings as
    the library's "name=lo:hi[:count]" texts."""
    if domain is None:
        return []
    if isinstance(domain, str):
        return [domain]
    if isinstance(domain, dict):
        out = []
        for name, bounds in domain.items():
            if isinstance(bounds, str):
                out.append(f"{name}={bounds}")
                continue
            try:
                parts = list(bounds)
            except TypeError:
                raise TypeError(f"domain[{name!r}]: expected (lo, hi) or (lo, hi, count), "
                                f"got {bounds!r}") from None
            if len(parts) not in (2, 3):
                raise TypeError(f"domain[{name!r}]: expected (lo, hi) or (lo, hi, count), "
                                f"got {bounds!r}")
            text = f"{name}={float(parts[0])!r}:{float(parts[1])!r}"
            if len(parts) == 3:
                text += f":{int(parts[2])}"
            out.append(text)
        return out
    return [str(d) for d in domain]


def load_problem(*, data=None, dataset: str | None = None, dataset_seed: int = 1,
                 reference: str | None = None, reference_file=None, function: str | None = None,
                 domain=None, define: Sequence[str] | str = (), samples: int = 0,
                 drop_nonfinite: bool = False, drop_missing: bool = False,
                 inputs: Sequence[str] | None = None, target: str | None = None,
                 scene: str | None = None, term: str | None = None):
    """What to approximate, stated as the command line states it (docs/reference.md): a CSV
    file (``data``), a built-in data set, or a ``reference`` formula (or a GLSL/HLSL function:
    ``reference_file`` and ``function``) sampled by shaderfit on ``domain``, or at the shading
    samples of a ``scene`` ("sphere", "plane"; ``term``: the factor it stands for, F, V, D or
    FV; docs/scenes.md). ``drop_missing=True`` drops a CSV's rows with an empty or
    non-number cell in a column of numbers (otherwise an error naming the cell)."""
    import os
    defines = [define] if isinstance(define, str) else list(define)
    try:
        return _shaderfit.load_problem(
            os.fspath(data) if data is not None else "", dataset or "", int(dataset_seed),
            reference or "", os.fspath(reference_file) if reference_file is not None else "",
            function or "", _domain_texts(domain), defines, int(samples), bool(drop_nonfinite),
            bool(drop_missing), list(inputs or []), target or "", scene or "", term or "")
    except Error as e:
        raise _problem_error(e) from None


# The library's names for what load_problem's keywords set, and the keywords.
_PROBLEM_FIELDS = {
    "ProblemSource::csv_path": "data", "ProblemSource::dataset": "dataset",
    "ProblemSource::dataset_seed": "dataset_seed", "ProblemSource::reference": "reference",
    "ProblemSource::domain": "domain", "ProblemSource::inputs": "inputs",
    "ProblemSource::target": "target", "ProblemSource::samples": "samples",
    "ProblemSource::drop_nonfinite": "drop_nonfinite", "ReferenceText::function": "function",
    "ProblemSource::drop_missing_rows": "drop_missing",
    "CsvOptions::drop_missing_rows": "drop_missing",
    "ReferenceText::definitions": "define", "ProblemSource::scene": "scene",
    "SceneSpec::kind": "scene", "SceneSpec::term": "term",
}


def _problem_error(e: Error) -> Error:
    """The error with the library's field names written as the keywords that set them."""
    message = e.message
    for field, keyword in _PROBLEM_FIELDS.items():
        message = message.replace(field, keyword)
    return Error(message, _PROBLEM_FIELDS.get(e.source, e.source), e.line, e.column)


_PROBLEM_KEYWORDS = ("data", "dataset", "dataset_seed", "reference", "reference_file", "function",
                     "domain", "define", "samples", "drop_nonfinite", "drop_missing", "target",
                     "scene", "term")


def search(X=None, y=None, *, inputs: Sequence[str] | None = None, time: float = 10,
           seed: int = 1, threads: int = 0, ops=None, loss: str = "mse", weights=None,
           baselines: Sequence[str] = (), progress: bool | Progress | None = None,
           on_member: Callable[[dict], None] | None = None, **options: Any) -> Front:
    """Symbolic regression: the Pareto front of formulas, error against GPU cost.

    The data: X and y, or a problem stated by keywords (docs/reference.md) instead:
    ``reference="acos(x)", domain={"x": (-1, 1)}`` (a formula, sampled by shaderfit; also
    ``define=["t = ..."]``, ``samples=N``, ``drop_nonfinite=True``), ``reference_file=PATH,
    function=NAME`` (a GLSL or HLSL function), ``data=PATH`` (a CSV file) or ``dataset=NAME``;
    ``inputs`` and ``target`` then choose columns (inferred otherwise). With a reference every
    front member's max error is also searched for between the samples, and ``certify=True``
    adds a rigorous bound over the whole domain (``member.certified_max_abs``).
    X: a 2-D array (float32 or float64, C or Fortran order) or a DataFrame, whose column names
    become the inputs; ``inputs`` names a plain array's columns (x0, x1, ... without it).
    y: the target, one value per row. weights: one per row (default 1).
    time: seconds; seed: the run's seed (one thread and a budget of evaluations give the same
    front every time); threads: 0 for all cores; ops: operators ("+,-,*,/,^", a list, or "auto"),
    None for the default: a built-in data set's own, else chosen from the data (auto);
    loss: mse, rmse, max_abs, max_rel, rel or log; or display, on a ``scene``: the error of
    the displayed pixels (docs/scenes.md);
    baselines: your own formulas (over the inputs) to start from.
    Any other search option by its library name (``shaderfit.search_options()`` lists them),
    e.g. ``max_nodes=30, max_candidates=10**6, stop_at=(1e-4, 6)``.
    progress: a callable given a dict (elapsed_s, candidates, candidates_per_s, front_size,
    phase) about every progress_interval_s seconds; True for a tqdm bar; None (default) for a
    bar when tqdm is installed and the session is interactive. on_member: a callable given
    each new front member as a dict (formula, formula_display, cost, loss, time_s, origin).

    The search runs with the GIL released; Ctrl-C stops it and returns the front found so far
    (``front.interrupted`` is True). Raises shaderfit.Error (a ValueError) for bad data or
    option values, TypeError for an unknown option or a value of the wrong type.
    """
    stated = {k: options.pop(k) for k in _PROBLEM_KEYWORDS if k in options}
    problem = None
    if stated:
        if X is not None or y is not None:
            raise TypeError("give the data either as X and y or as a problem (reference=..., "
                            "data=..., dataset=...), not both")
        problem = load_problem(inputs=inputs, **stated)
        if ops is None and problem.operators:
            ops = problem.operators
            options.setdefault("evolve_ops", problem.evolution_operators or None)
    elif X is None or y is None:
        raise TypeError("no data: give X and y, or a problem (reference=... with domain=..., "
                        "data=PATH or dataset=NAME)")
    keywords = dict(seed=seed, threads=threads, loss=loss, **options)
    if "time_limit_s" not in options:
        keywords["time"] = time
    if ops is not None:
        keywords["ops"] = ops
    if baselines:
        keywords["baselines"] = [baselines] if isinstance(baselines, str) else list(baselines)
    parsed = Options(keywords)
    if problem is not None:
        columns, names, target, rows, source, target_name = [], [], None, \
            len(problem.columns()[problem.target]), problem.description, problem.target
    else:
        columns, names = columns_of(X, inputs)
        rows = columns[0].shape[0] if columns else 0
        target = vector_of(y, rows, "y")
        source, target_name = ("DataFrame" if _is_dataframe(X) else "array"), name_of(y)
    w = None if weights is None else vector_of(weights, rows, "weights")
    time_s = float(options.get("time_limit_s", time))
    evals = options.get("max_candidates", options.get("evals"))
    callback, bar = _progress_for(progress, time_s, evals)
    try:
        run = _shaderfit.search(columns, names, target if target is not None else np.zeros(0), w,
                                parsed.items(), on_member, callback, source, target_name, problem)
    except Error as e:
        raise renamed(e, parsed.keyword_for) from None
    finally:
        if bar is not None:
            bar.close()
    return Front(run)


def search_options() -> list[dict]:
    """Every search option: name, kind, role, help, choices and default (as text)."""
    return [dict(f) for f in _shaderfit.option_fields()]
