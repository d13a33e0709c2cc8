"""shaderfit.search through Python: the seed task, data layouts, callbacks, Ctrl-C, the GIL."""

import json
import os
import pickle
import signal
import subprocess
import threading
import time

import numpy as np
import pytest

import shaderfit

# A budget of evaluations with one thread makes a run reproducible from its seed.
EXACT = dict(threads=1, time=120, max_candidates=60_000, progress=False)


def test_seed_task_finds_the_seed_formula_or_better_for_seeds_1_to_10(seed_mse):
    for seed in range(1, 11):
        data = shaderfit.datasets.fresnel_seed(seed=seed)
        mse = float(np.mean((shaderfit.evaluate("r0 + (x - r0)*x^4", data.X, inputs=data.inputs)
                             - data.y) ** 2))
        front = shaderfit.search(data.X, data.y, inputs=data.inputs, time=20, seed=seed,
                                 threads=2, stop_at=(mse, 4), progress=False)
        ok = [m for m in front if float(m.cost) <= 4 and m.mse <= mse]
        assert ok, f"seed {seed}: no member with cost <= 4 and mse <= {mse}\n{front!r}"
        assert front.termination == "target reached"


def test_front_members_carry_every_figure(seed_data):
    front = shaderfit.search(seed_data.X, seed_data.y, inputs=seed_data.inputs, **EXACT)
    assert len(front) >= 3
    costs = [float(m.cost) for m in front]
    assert costs == sorted(costs)
    losses = [m.loss for m in front]
    assert all(a > b for a, b in zip(losses, losses[1:]))
    m = front[-1]
    for name in ("mse", "rmse", "max_abs", "max_rel", "rel", "log", "time_s",
                 "float32_max_abs_diff"):
        assert isinstance(getattr(m, name), float)
    assert m.origin in ("enumeration", "evolution", "start")
    assert isinstance(m.float32_stable, bool)
    assert m.inputs == ["r0", "x"]
    assert m.cost("sass") >= 0 and m.cost("ptx") >= 0 and m.cost("generic") >= 0
    assert str(m) == m.formula_display


def test_a_search_ranked_by_rdna2_counts_rdna2(seed_data):
    front = shaderfit.search(seed_data.X, seed_data.y, inputs=seed_data.inputs, cost="rdna2",
                             **EXACT)
    assert all(float(m.cost) == m.cost("rdna2") for m in front)
    assert shaderfit.cost("x > 0.5 ? x*x : sqrt(x)")["targets"]["rdna2"]["instructions"] == 4


def test_same_seed_and_budget_give_the_same_front(seed_data):
    a = shaderfit.search(seed_data.X, seed_data.y, inputs=seed_data.inputs, seed=3, **EXACT)
    b = shaderfit.search(seed_data.X, seed_data.y, inputs=seed_data.inputs, seed=3, **EXACT)
    assert [m.formula for m in a] == [m.formula for m in b]


def test_float32_float64_c_and_fortran_order(seed_data):
    X64 = np.ascontiguousarray(seed_data.X)
    fronts = {}
    for name, X in {"f64 C": X64, "f64 F": np.asfortranarray(X64),
                    "f32 C": X64.astype(np.float32),
                    "f32 F": np.asfortranarray(X64.astype(np.float32))}.items():
        front = shaderfit.search(X, seed_data.y, inputs=seed_data.inputs, **EXACT)
        fronts[name] = [m.formula for m in front]
    # The same values in either order: the same front; float32 data is other data.
    assert fronts["f64 C"] == fronts["f64 F"]
    assert fronts["f32 C"] == fronts["f32 F"]
    # A strided view (every other row) is read in place, as its copy would be.
    view = shaderfit.search(X64[::2], seed_data.y[::2], inputs=seed_data.inputs, **EXACT)
    copy = shaderfit.search(X64[::2].copy(), seed_data.y[::2].copy(), inputs=seed_data.inputs,
                            **EXACT)
    assert [m.formula for m in view] == [m.formula for m in copy]


def test_dataframe_column_names_become_the_inputs(seed_data):
    pd = pytest.importorskip("pandas")
    df = pd.DataFrame({"r0": seed_data.X[:, 0], "x": seed_data.X[:, 1],
                       "unused": np.zeros(len(seed_data.y))})
    y = pd.Series(seed_data.y, name="R")
    front = shaderfit.search(df[["r0", "x"]], y, **EXACT)
    assert front.inputs == ["r0", "x"]
    assert front.data["target"] == "R"
    assert "r0" in front[-1].formula
    # inputs= picks columns of a DataFrame by name.
    picked = shaderfit.search(df, y, inputs=["r0", "x"], **EXACT)
    assert [m.formula for m in picked] == [m.formula for m in front]
    # predict takes a DataFrame's columns by name, whatever their order.
    m = front[-1]
    np.testing.assert_array_equal(m.predict(df[["x", "unused", "r0"]]), m.predict(df))


def test_plain_arrays_are_named_x0_x1(seed_data):
    front = shaderfit.search(seed_data.X, seed_data.y, **EXACT)
    assert front.inputs == ["x0", "x1"]


def test_predict_equals_the_cli_eval(seed_data, cli, tmp_path):
    front = shaderfit.search(seed_data.X, seed_data.y, inputs=seed_data.inputs, **EXACT)
    csv = tmp_path / "seed.csv"
    with open(csv, "w") as f:
        f.write("r0,x,R\n")
        for (r0, x), r in zip(seed_data.X, seed_data.y):
            f.write(f"{float(r0)!r},{float(x)!r},{float(r)!r}\n")
    members = [front[len(front) // 2], front[-1]]
    out = subprocess.run([cli, "eval", "--data", str(csv), "--target", "R", "--json", "-"]
                         + [m.formula for m in members], capture_output=True, text=True,
                         check=True)
    results = json.loads(out.stdout)["results"]
    for m, r in zip(members, results):
        p = m.predict(seed_data.X)
        assert np.mean((p - seed_data.y) ** 2) == pytest.approx(r["all"]["mse"], rel=1e-12)
        assert np.max(np.abs(p - seed_data.y)) == pytest.approx(r["all"]["max_abs"], rel=1e-12)
        assert m.mse == pytest.approx(r["all"]["mse"], rel=1e-12)


def test_to_json_is_the_cli_schema(seed_data, cli):
    front = shaderfit.search(seed_data.X, seed_data.y, inputs=seed_data.inputs, **EXACT)
    ours = json.loads(front.to_json())
    out = subprocess.run([cli, "search", "--dataset", "fresnel-seed", "--inputs", "r0,x",
                          "--target", "R", "--evals", "20000", "--threads", "1", "--quiet",
                          "--json", "-"], capture_output=True, text=True, check=True)
    theirs = json.loads(out.stdout)
    assert set(ours) == set(theirs)
    assert set(ours["options"]) == set(theirs["options"])
    assert set(ours["front"][-1]) == set(theirs["front"][-1])


def test_best_and_choose(seed_data):
    front = shaderfit.search(seed_data.X, seed_data.y, inputs=seed_data.inputs, **EXACT)
    limit = front[len(front) // 2].loss
    knee, why = front.choose()
    assert knee in front.members and "knee" in why
    cheap = front.best(max_cost=4)
    assert float(cheap.cost) <= 4
    assert all(m.loss >= cheap.loss for m in front if float(m.cost) <= 4)
    good = front.best(max_error=limit)
    assert good.loss <= limit
    assert all(float(m.cost) >= float(good.cost) for m in front if m.loss <= limit)
    both = front.best(max_cost=float(front[-1].cost), max_error=limit)
    assert both is good


def test_member_code_latex_sympy_and_pandas(seed_data):
    front = shaderfit.search(seed_data.X, seed_data.y, inputs=seed_data.inputs, **EXACT)
    m = front.best(max_cost=4)
    for lang in ("glsl", "hlsl", "cuda", "cpp", "metal"):
        code = m.code(lang, name="fresnel")
        assert "fresnel" in code and "r0" in code
    assert "r_{0}" in m.latex()
    sympy = pytest.importorskip("sympy")
    e = m.sympy()
    r0, x = sympy.Symbol("r0", real=True), sympy.Symbol("x", real=True)
    value = float(e.subs({r0: 0.04, x: 0.5}))
    assert value == pytest.approx(float(m.predict(np.array([[0.04, 0.5]]))[0]), rel=1e-12)
    pd = pytest.importorskip("pandas")
    table = front.to_pandas()
    assert isinstance(table, pd.DataFrame) and len(table) == len(front)
    assert {"formula", "cost", "mse", "max_abs", "time_s", "float32_stable"} <= set(table)


def test_front_pickles(seed_data):
    front = shaderfit.search(seed_data.X, seed_data.y, inputs=seed_data.inputs, **EXACT)
    again = pickle.loads(pickle.dumps(front))
    assert [m.formula for m in again] == [m.formula for m in front]
    np.testing.assert_array_equal(again[-1].predict(seed_data.X), front[-1].predict(seed_data.X))
    assert again[-1].cost("sass") == front[-1].cost("sass")


def test_callbacks_see_members_and_progress(seed_data):
    members, progress = [], []
    front = shaderfit.search(seed_data.X, seed_data.y, inputs=seed_data.inputs, time=0.6,
                             threads=1, progress=progress.append, on_member=members.append,
                             progress_interval_s=0.05)
    assert members and progress
    assert {"formula", "cost", "loss", "time_s", "origin"} <= set(members[0])
    assert {"elapsed_s", "candidates", "front_size", "phase"} <= set(progress[-1])
    assert len(front) >= 1


def test_an_exception_in_a_callback_stops_the_search(seed_data):
    def fail(_):
        raise RuntimeError("stop here")

    t0 = time.monotonic()
    with pytest.raises(RuntimeError, match="stop here"):
        shaderfit.search(seed_data.X, seed_data.y, inputs=seed_data.inputs, time=30, threads=1,
                         on_member=fail, progress=False)
    assert time.monotonic() - t0 < 10


def test_ctrl_c_returns_the_front_found_so_far(seed_data):
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    t0 = time.monotonic()
    front = shaderfit.search(seed_data.X, seed_data.y, inputs=seed_data.inputs, time=60,
                             threads=1, progress=False)
    elapsed = time.monotonic() - t0
    timer.join()
    assert front.interrupted and front.termination == "interrupted"
    assert len(front) >= 1
    assert elapsed < 15


def test_the_search_releases_the_gil(seed_data):
    count = 0
    stop = threading.Event()

    def spin():
        nonlocal count
        while not stop.is_set():
            count += 1

    t = threading.Thread(target=spin)
    t.start()
    shaderfit.search(seed_data.X, seed_data.y, inputs=seed_data.inputs, time=0.5, threads=1,
                     progress=False)
    stop.set()
    t.join()
    assert count > 10_000
