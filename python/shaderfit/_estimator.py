"""shaderfit.ShaderFitRegressor: the search as a scikit-learn estimator."""

from __future__ import annotations

from typing import Any, Mapping

import numpy as np

try:  # scikit-learn is optional: without it the class still works, without its checks
    from sklearn.base import BaseEstimator, RegressorMixin
    from sklearn.utils.validation import check_is_fitted

    try:
        from sklearn.utils.validation import validate_data as _validate_data  # >= 1.6
    except ImportError:  # older scikit-learn: the method on BaseEstimator
        def _validate_data(estimator, *args, **kwargs):
            return estimator._validate_data(*args, **kwargs)
    _HAVE_SKLEARN = True
    _BASES = (RegressorMixin, BaseEstimator)
except ImportError:  # exercised only without scikit-learn
    _HAVE_SKLEARN = False
    _BASES = (object,)

from ._arrays import _is_dataframe
from ._search import search


class ShaderFitRegressor(*_BASES):
    """Symbolic regression with shaderfit, as a scikit-learn regressor.

    Parameters: ``time`` (seconds per fit), ``seed``, ``threads`` (0: all cores), ``ops``
    (None: the library's default operators, or "auto", or a list), ``loss`` (the search's),
    ``max_cost`` and ``max_error`` (how ``best_`` is chosen, below), ``options`` (any other
    search option by its library name, as a dict) and ``progress`` (as search()'s).

    ``best_``, the member ``predict`` uses, is chosen from the front as ``Front.best`` does:
    with neither limit the knee of the front (where more cost stops buying much accuracy); with
    ``max_cost`` the most accurate member that costs at most that; with ``max_error`` the
    cheapest whose loss is at most that. Fitted attributes: ``front_`` (the Front), ``best_``,
    ``why_`` (one line on why best_), ``n_features_in_`` and, for a DataFrame,
    ``feature_names_in_`` (which become the formula's inputs).
    """

    def __init__(self, time: float = 10.0, seed: int = 1, threads: int = 0, ops=None,
                 loss: str = "mse", max_cost: float | None = None,
                 max_error: float | None = None, options: Mapping[str, Any] | None = None,
                 progress=None):
        self.time = time
        self.seed = seed
        self.threads = threads
        self.ops = ops
        self.loss = loss
        self.max_cost = max_cost
        self.max_error = max_error
        self.options = options
        self.progress = progress

    def _inputs(self):
        names = getattr(self, "feature_names_in_", None)
        if names is not None:
            return [str(n) for n in names]
        return [f"x{i}" for i in range(self.n_features_in_)]

    def fit(self, X, y, sample_weight=None):
        if _HAVE_SKLEARN:
            X, y = _validate_data(self, X, y, dtype=[np.float64, np.float32], y_numeric=True,
                                  ensure_min_samples=2)
        else:
            if _is_dataframe(X):
                self.feature_names_in_ = np.asarray([str(c) for c in X.columns], dtype=object)
            X, y = np.asarray(X, dtype=np.float64), np.asarray(y, dtype=np.float64).ravel()
            if X.ndim != 2:
                raise ValueError(f"X must be 2-D (rows, inputs); got shape {X.shape}")
            self.n_features_in_ = X.shape[1]
        inputs = self._inputs()
        self.front_ = search(X, y, inputs=inputs, time=self.time, seed=self.seed,
                             threads=self.threads, ops=self.ops, loss=self.loss,
                             weights=sample_weight, progress=self.progress,
                             **dict(self.options or {}))
        if len(self.front_) == 0:
            raise RuntimeError("the search found no formula; give it more time")
        self.best_, self.why_ = self.front_.choose(self.max_cost, self.max_error)
        return self

    def predict(self, X):
        if _HAVE_SKLEARN:
            check_is_fitted(self, "best_")
            X = _validate_data(self, X, reset=False, dtype=[np.float64, np.float32])
        elif not hasattr(self, "best_"):
            raise AttributeError("this ShaderFitRegressor is not fitted yet; call fit first")
        return self.best_.predict(np.asarray(X), inputs=self._inputs())

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.regressor_tags.poor_score = True  # a short search on noise fits noise badly
        tags.non_deterministic = False
        return tags

    def _more_tags(self):  # scikit-learn < 1.6
        return {"poor_score": True}

    if not _HAVE_SKLEARN:
        def score(self, X, y, sample_weight=None):
            """R² of predict(X) against y, as scikit-learn's regressors define it."""
            y = np.asarray(y, dtype=np.float64).ravel()
            w = np.ones_like(y) if sample_weight is None else np.asarray(sample_weight, float)
            residual = np.sum(w * (y - self.predict(X)) ** 2)
            total = np.sum(w * (y - np.average(y, weights=w)) ** 2)
            return 1.0 - residual / total if total > 0 else 0.0
