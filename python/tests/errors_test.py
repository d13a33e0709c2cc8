"""Every bad input raises a Python exception whose message names it; none ends the interpreter."""

import numpy as np
import pytest

import shaderfit

FAST = dict(threads=1, time=5, max_candidates=2000, progress=False)


@pytest.fixture
def Xy(seed_data):
    return seed_data.X[:256], seed_data.y[:256]


def raises(kind, match, f, *args, **kwargs):
    with pytest.raises(kind, match=match) as info:
        f(*args, **kwargs)
    return info.value


def test_wrong_shapes(Xy):
    X, y = Xy
    raises(ValueError, r"X must be 2-D \(rows, inputs\); got shape \(256,\); use X.reshape",
           shaderfit.search, X[:, 0], y, **FAST)
    raises(ValueError, r"X must be 2-D", shaderfit.search, X[None], y, **FAST)
    raises(ValueError, r"y has 255 values for 256 rows of X", shaderfit.search, X, y[:-1], **FAST)
    raises(ValueError, r"y must be 1-D; got shape \(256, 2\)", shaderfit.search, X,
           np.column_stack([y, y]), **FAST)
    raises(ValueError, r"weights has 3 values for 256 rows", shaderfit.search, X, y,
           weights=[1, 2, 3], **FAST)
    raises(ValueError, r"inputs: 3 names for the 2 columns of X", shaderfit.search, X, y,
           inputs=["a", "b", "c"], **FAST)
    raises(ValueError, r"inputs: 'my col' is not a name formulas can use", shaderfit.search, X,
           y, inputs=["r0", "my col"], **FAST)
    raises(ValueError, r"inputs: 'r0' is given twice", shaderfit.search, X, y,
           inputs=["r0", "r0"], **FAST)
    raises(ValueError, r"data: the data has 1 row; a search needs at least 2",
           shaderfit.search, X[:1], y[:1], **FAST)


def test_nan_and_inf_in_the_data(Xy):
    X, y = Xy
    y = y.copy()
    y[3] = np.nan
    e = raises(shaderfit.Error, r"data: the target is NaN in row 4 \(rows counted from 1\)",
               shaderfit.search, X, y, **FAST)
    assert isinstance(e, ValueError) and e.source == "data"
    X = X.copy()
    X[7, 1] = np.inf
    raises(shaderfit.Error, r"input 'x' is \+inf in row 8", shaderfit.search, X, Xy[1],
           inputs=["r0", "x"], **FAST)
    raises(shaderfit.Error, r"every weight is zero", shaderfit.search, *Xy,
           weights=np.zeros(256), **FAST)
    raises(shaderfit.Error, r"weights must be finite and >= 0", shaderfit.search, *Xy,
           weights=-np.ones(256), **FAST)


def test_unknown_options_and_operators(Xy):
    raises(TypeError, r"search\(\) got an unknown option 'max_node' \(options: time, ops",
           shaderfit.search, *Xy, max_node=3, **FAST)
    e = raises(shaderfit.Error, r"^ops: unknown operator 'foo' \(known: ", shaderfit.search,
               *Xy, ops="+,foo", **FAST)
    assert e.source == "ops"
    raises(shaderfit.Error, r"^operators: unknown operator 'tan'", shaderfit.search, *Xy,
           operators=["+", "tan"], **FAST)
    raises(shaderfit.Error, r"^loss: unknown loss 'l1' \(known: mse, rmse", shaderfit.search,
           *Xy, loss="l1", **FAST)
    raises(TypeError, r"search\(\) got max_candidates twice: as .evals. and as", shaderfit.search, *Xy,
           time_limit_s=1, evals=5, max_candidates=5)


def test_option_values_out_of_range_and_of_the_wrong_type(Xy):
    raises(shaderfit.Error, r"^max_power: must be in \[2, 16\]", shaderfit.search, *Xy,
           max_power=40, **FAST)
    raises(shaderfit.Error, r"^time: the time budget must be positive \(got -1\)",
           shaderfit.search, *Xy, time=-1, threads=1, progress=False)
    raises(shaderfit.Error, r"^time_limit_s: the time budget must be positive",
           shaderfit.search, *Xy, time_limit_s=0.0, threads=1, progress=False)
    raises(shaderfit.Error, r"^screen_rows: must be a multiple of 8", shaderfit.search, *Xy,
           screen_rows=20, **FAST)
    raises(TypeError, r"time: expected a number, got str 'ten'", shaderfit.search, *Xy,
           time="ten")
    raises(TypeError, r"max_nodes: expected an integer, got float 2.5", shaderfit.search, *Xy,
           max_nodes=2.5, **FAST)
    raises(TypeError, r"symmetry: expected True or False, got int 1", shaderfit.search, *Xy,
           symmetry=1, **FAST)
    raises(TypeError, r"stop_at: expected \(max_loss, max_cost\)", shaderfit.search, *Xy,
           stop_at=0.1, **FAST)
    raises(shaderfit.Error, r"^threads: threads must be >= 0", shaderfit.search, *Xy,
           threads=-2, time=1, progress=False)


def test_bad_baselines(Xy):
    e = raises(shaderfit.Error, r"baselines", shaderfit.search, *Xy, inputs=["r0", "x"],
               baselines=["r0 + (x - r0"], **FAST)
    assert e.line == 1


def test_non_numeric_columns(seed_data):
    pd = pytest.importorskip("pandas")
    df = pd.DataFrame({"r0": seed_data.X[:, 0], "kind": seed_data.columns["kind"]})
    raises(TypeError, r"column 'kind' is not numeric \(dtype (object|str)",
           shaderfit.search, df, seed_data.y, **FAST)
    raises(ValueError, r"inputs: no column 'x' in the DataFrame \(columns: r0, kind\)",
           shaderfit.search, df, seed_data.y, inputs=["r0", "x"], **FAST)
    raises(TypeError, r"X is not numeric \(dtype", shaderfit.search,
           np.array([["a", "b"], ["c", "d"]]), [1.0, 2.0], **FAST)
    raises(TypeError, r"X must be a 2-D array or a DataFrame, not str", shaderfit.search,
           "data.csv", [1.0], **FAST)
    raises(TypeError, r"X is not numeric \(dtype complex128\)", shaderfit.search,
           np.ones((4, 2), dtype=complex), np.ones(4), **FAST)


def test_commands_on_bad_input(seed_data):
    X, y = seed_data.X, seed_data.y
    e = raises(shaderfit.Error, r"^formula:1:", shaderfit.evaluate, "r0 + * x", X,
               inputs=["r0", "x"])
    assert e.line == 1 and e.column > 0
    raises(shaderfit.Error, r"unknown", shaderfit.evaluate, "r0 + q", X, inputs=["r0", "x"])
    raises(ValueError, r"X has 3 columns; the formula.s inputs are r0, x \(2\)", shaderfit.search(
        X, y, inputs=["r0", "x"], **FAST)[0].predict, X[:, :1].repeat(3, axis=1))
    raises(shaderfit.Error, r"unknown language 'wgsl' \(known: glsl, hlsl, cuda, cpp, metal\)",
           shaderfit.codegen, "x * x", "wgsl")
    raises(shaderfit.Error,
           r"unknown target 'gcn' \(known: sass, ptx, generic, sass-half2, rdna2, rdna3\)",
           shaderfit.cost, "x * x", target="gcn")
    raises(shaderfit.Error, r"unknown loss 'l1'", shaderfit.fit, "a * x", X[:, 1:], y,
           inputs=["x"], params=["a"], loss="l1")
    raises(shaderfit.Error, r"unknown fit 'best'", shaderfit.rational, "exp", fit="best")
    raises(shaderfit.Error, r"unknown data set 'nope'", shaderfit.datasets.builtin, "nope")


def test_errors_pickle():
    import pickle

    e = shaderfit.Error("must be in [2, 16]", "max_power")
    again = pickle.loads(pickle.dumps(e))
    assert str(again) == str(e) == "max_power: must be in [2, 16]"
