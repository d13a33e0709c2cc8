"""shaderfit.search: the Pareto front of error against GPU cost for samples of a function."""

from __future__ import annotations

import sys
from typing import Any, Callable, Sequence

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


def search(X, y, *, inputs: Sequence[str] | None = None, time: float = 10, seed: int = 1,
           threads: int = 0, ops=None, loss: str = "mse", weights=None,
           baselines: Sequence[str] = (), progress: bool | Progress | None = None,
           on_member: Callable[[dict], None] | None = None, **options: Any) -> Front:
    """Symbolic regression: the Pareto front of formulas, error against GPU cost.

    X: a 2-D array (float32 or float64, C or Fortran order) or a DataFrame, whose column names
    become the inputs; ``inputs`` names a plain array's columns (x0, x1, ... without it).
    y: the target, one value per row. weights: one per row (default 1).
    time: seconds; seed: the run's seed (one thread and a budget of evaluations give the same
    front every time); threads: 0 for all cores; ops: operators ("+,-,*,/,^", a list, or "auto"),
    None for the library's default; loss: mse, rmse, max_abs, max_rel, rel or log;
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
    keywords = dict(seed=seed, threads=threads, loss=loss, **options)
    if "time_limit_s" not in options:
        keywords["time"] = time
    if ops is not None:
        keywords["ops"] = ops
    if baselines:
        keywords["baselines"] = [baselines] if isinstance(baselines, str) else list(baselines)
    parsed = Options(keywords)
    columns, names = columns_of(X, inputs)
    rows = columns[0].shape[0] if columns else 0
    target = vector_of(y, rows, "y")
    w = None if weights is None else vector_of(weights, rows, "weights")
    source = "DataFrame" if _is_dataframe(X) else "array"
    time_s = float(options.get("time_limit_s", time))
    evals = options.get("max_candidates", options.get("evals"))
    callback, bar = _progress_for(progress, time_s, evals)
    try:
        run = _shaderfit.search(columns, names, target, w, parsed.items(), on_member, callback,
                                source, name_of(y))
    except Error as e:
        raise renamed(e, parsed.keyword_for) from None
    finally:
        if bar is not None:
            bar.close()
    return Front(run)


def search_options() -> list[dict]:
    """Every search option: name, kind, role, help, choices and default (as text)."""
    return [dict(f) for f in _shaderfit.option_fields()]
