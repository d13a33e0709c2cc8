"""evaluate, cost, codegen, fit, rational and the data sets, against the command line."""

import json
import subprocess

import numpy as np
import pytest

import shaderfit

SEED = "r0 + (x - r0)*x^4"


def test_dataset_is_the_clis(seed_data, cli):
    out = subprocess.run([cli, "eval", "--dataset", "fresnel-seed", "--data-seed", "1",
                          "--target", "R", "--json", "-", SEED], capture_output=True, text=True,
                         check=True)
    cli_mse = json.loads(out.stdout)["results"][0]["all"]["mse"]
    ours = shaderfit.evaluate(SEED, seed_data.X, inputs=seed_data.inputs)
    assert np.mean((ours - seed_data.y) ** 2) == pytest.approx(cli_mse, rel=1e-12)
    assert seed_data.X.shape == (4096, 2) and seed_data.inputs == ["r0", "x"]
    assert set(seed_data.columns) >= {"r0", "cos_theta", "x", "R", "kind", "material"}
    assert "fresnel-seed" in shaderfit.datasets.names()
    other = shaderfit.datasets.fresnel_seed(seed=2)
    assert not np.array_equal(other.X, seed_data.X)


def test_evaluate_on_arrays_and_dataframes(seed_data):
    by_position = shaderfit.evaluate("x0 * x1", seed_data.X)
    np.testing.assert_array_equal(by_position, seed_data.X[:, 0] * seed_data.X[:, 1])
    with_params = shaderfit.evaluate("a * x", seed_data.X, inputs=["r0", "x"], params={"a": 2})
    np.testing.assert_array_equal(with_params, 2 * seed_data.X[:, 1])
    pd = pytest.importorskip("pandas")
    df = pd.DataFrame(seed_data.X, columns=["r0", "x"])
    np.testing.assert_array_equal(shaderfit.evaluate("x - r0", df), df.x - df.r0)


def test_cost_matches_the_cli(cli):
    ours = shaderfit.cost(SEED)
    out = subprocess.run([cli, "cost", SEED, "--json", "-"], capture_output=True, text=True,
                         check=True)
    assert ours == json.loads(out.stdout)
    assert ours["targets"]["sass"]["instructions"] == 4


def test_codegen_matches_the_cli(cli):
    for lang in ("glsl", "hlsl", "cuda", "cpp", "metal"):
        code = shaderfit.codegen(SEED, lang, name="fresnel")
        assert "fresnel(" in code
    code = shaderfit.codegen("r0 + (1 - r0 - s*x)*x^4", "hlsl", params={"s": 0.25})
    assert "0.25f" in code
    assert shaderfit.latex("x^4") == "x^{4}"


def test_fit_per_group(seed_data):
    kinds = np.asarray(seed_data.columns["kind"])
    r = shaderfit.fit("r0 + (1 - r0 - s*x)*x^4", seed_data.X, seed_data.y,
                      inputs=seed_data.inputs, params={"s": 1.0}, groups=kinds)
    assert set(r.parameters["s"]) == {"dielectric", "metal"}
    assert r.json["schema"] == "shaderfit.fit/1"
    one = shaderfit.fit("r0 + (1 - r0 - s*x)*x^4", seed_data.X, seed_data.y,
                        inputs=seed_data.inputs, params=["s"])
    assert isinstance(one.parameters["s"], float)


def test_rational():
    doc = shaderfit.rational("exp", domain=(0, 1), forms=["2/2"], fit="minimax")
    assert doc["schema"] == "shaderfit.rational/1"
