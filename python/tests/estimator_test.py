"""ShaderFitRegressor: the seed task, feature names, parameters, and scikit-learn's checks."""

import numpy as np
import pytest

import shaderfit

sklearn = pytest.importorskip("sklearn")

# A budget of evaluations with one thread: fits are reproducible, as the checks require.
EXACT = dict(time=120, threads=1, options={"max_candidates": 30_000}, progress=False)


def test_seed_task_through_the_estimator(seed_data, seed_mse):
    model = shaderfit.ShaderFitRegressor(time=20, threads=2, max_cost=4, progress=False,
                                         options={"stop_at": (seed_mse, 4)})
    model.fit(seed_data.X, seed_data.y)
    assert float(model.best_.cost) <= 4 and model.best_.mse <= seed_mse
    assert model.n_features_in_ == 2
    assert model.best_.inputs == ["x0", "x1"]
    prediction = model.predict(seed_data.X)
    assert np.mean((prediction - seed_data.y) ** 2) == pytest.approx(model.best_.mse, rel=1e-12)
    assert model.score(seed_data.X, seed_data.y) > 0.99
    assert "cost" in model.why_


def test_dataframe_feature_names(seed_data):
    pd = pytest.importorskip("pandas")
    df = pd.DataFrame(seed_data.X, columns=["r0", "x"])
    model = shaderfit.ShaderFitRegressor(**EXACT).fit(df, seed_data.y)
    assert list(model.feature_names_in_) == ["r0", "x"]
    assert model.best_.inputs == ["r0", "x"]
    assert set(model.front_.inputs) == {"r0", "x"}
    np.testing.assert_array_equal(model.predict(df), model.best_.predict(df))


def test_params_and_clone():
    from sklearn.base import clone

    model = shaderfit.ShaderFitRegressor(time=3, ops="auto", max_cost=6,
                                         options={"max_nodes": 20})
    params = model.get_params()
    assert params["time"] == 3 and params["ops"] == "auto" and params["max_cost"] == 6
    assert params["options"] == {"max_nodes": 20}
    copy = clone(model).set_params(time=5)
    assert copy.time == 5 and model.time == 3


def test_unknown_option_in_options_raises(seed_data):
    model = shaderfit.ShaderFitRegressor(time=1, options={"max_node": 3})
    with pytest.raises(TypeError, match="unknown option 'max_node'"):
        model.fit(seed_data.X, seed_data.y)


def test_in_a_pipeline_with_cross_validation(seed_data):
    from sklearn.model_selection import cross_val_score

    scores = cross_val_score(shaderfit.ShaderFitRegressor(**EXACT), seed_data.X[:1024],
                             seed_data.y[:1024], cv=3)
    assert np.all(scores > 0.9)


def _run_checks(estimator):
    """[(name, status, exception)] of scikit-learn's checks, with the API of 1.6+ or older."""
    import inspect
    from sklearn.utils.estimator_checks import check_estimator

    if "on_fail" in inspect.signature(check_estimator).parameters:
        return [(r["check_name"], r["status"], r["exception"])
                for r in check_estimator(estimator, on_fail=None)]
    from unittest import SkipTest

    results = []
    for est, check in check_estimator(estimator, generate_only=True):
        name = getattr(check, "func", check).__name__
        try:
            check(est)
            results.append((name, "passed", None))
        except SkipTest as e:
            results.append((name, "skipped", e))
        except Exception as e:  # noqa: BLE001 - every failure is reported below
            results.append((name, "failed", e))
    return results


def test_scikit_learn_estimator_checks():
    """check_estimator in full; scikit-learn itself skips check_array_api_input unless
    SCIPY_ARRAY_API is set."""
    results = _run_checks(shaderfit.ShaderFitRegressor(**EXACT))
    failed = [(name, str(e)[:200]) for name, status, e in results if status == "failed"]
    skipped = {name for name, status, _ in results if status == "skipped"}
    assert not failed
    assert skipped <= {"check_array_api_input"}
    assert len(results) > 40
