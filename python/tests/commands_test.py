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


def test_fit_to_a_reference_formula_on_a_domain():
    # Abramowitz and Stegun 4.4.45's form for acos on [0, 1]; the minimax fit is no worse than
    # their constants (6.75e-5).
    r = shaderfit.fit("s*(a + b*x + c*x^2 + d*x^3)", reference="acos(x)", domain={"x": (0, 1)},
                      define=["s = sqrt(1 - x)"], params=["a", "b", "c", "d"], loss="max_abs")
    assert r.json["reference"] == "acos(x)"
    assert r.blocks[0]["rows"] == 10001
    p = r.parameters
    x = np.linspace(0, 1, 100_001)
    approx = np.sqrt(1 - x) * (p["a"] + x * (p["b"] + x * (p["c"] + x * p["d"])))
    assert np.max(np.abs(approx - np.arccos(x))) < 6.75e-5
    # samples sizes the design; a domain with a count is a regular grid.
    assert shaderfit.fit("a*x", reference="erf(x)", domain={"x": (0, 1)}, samples=65,
                         params=["a"]).blocks[0]["rows"] == 65
    assert shaderfit.fit("a*x", reference="erf(x)", domain={"x": (0, 1, 16)},
                         params=["a"]).blocks[0]["rows"] == 16


def test_fit_to_a_reference_over_the_columns_of_X(tmp_path):
    u = np.linspace(0, 2, 101)
    r = shaderfit.fit("a*u", u[:, None], inputs=["u"], reference="u * atan2(1, 2) + erf(0)",
                      params=["a"])
    assert r.parameters["a"] == pytest.approx(np.arctan2(1, 2), rel=1e-12)
    path = tmp_path / "f.glsl"
    path.write_text("float f(float u) { return u > 1.0 ? 2.0 * u - 1.0 : u * u; }\n")
    g = shaderfit.fit("a*u^2", u[:, None], inputs=["u"], reference_file=path, function="f",
                      params=["a"])
    assert g.json["reference"].endswith("f.glsl: f")
    with pytest.raises(TypeError):
        shaderfit.fit("a*u", u[:, None], u, inputs=["u"], reference="u", params=["a"])


def test_fit_reference_errors_name_the_keyword():
    with pytest.raises(shaderfit.Error) as e:
        shaderfit.fit("a*x", reference="acoss(x)", domain={"x": (0, 1)}, params=["a"])
    assert e.value.source == "reference"
    assert e.value.column == 1
    assert "unknown function 'acoss'" in str(e.value)
    with pytest.raises(shaderfit.Error) as e:
        shaderfit.fit("a*x", reference="x", domain={"x": (0, 1)}, define=["c = cos(x)", "d = q"],
                      params=["a"])
    assert e.value.source == "define"
    assert e.value.line == 2


def test_rational_on_reference_language_targets(tmp_path):
    doc = shaderfit.rational(target="acos(x)", domain="x=0:0.9", forms=["2/2"], fit="minimax")
    result = doc["runs"][0]["results"][0]
    assert result["minimax"]["converged"]
    assert doc["target"] == "acos(x)"
    # Taylor conditions use the exact derivatives: erf's cubic is 2/sqrt(pi) (x - x^3/3).
    doc = shaderfit.rational(target="erf(x)", domain={"x": (-1, 1)}, forms=["3/0"],
                             conditions=["f(0)=ref", "f'(0)=ref", "f''(0)=ref", "f'''(0)=ref"])
    p = doc["runs"][0]["results"][0]["numerator"]
    c = 2 / np.sqrt(np.pi)
    assert p == pytest.approx([0, c, 0, -c / 3], abs=1e-15)
    path = tmp_path / "g.hlsl"
    path.write_text("float g(float k, float v) { return v / (v * (1 - k) + k); }\n")
    doc = shaderfit.rational(reference_file=path, function="g", parameters=["k=0.25"],
                             forms=["1/1"], conditions=["f(0)=ref", "f(1)=ref", "f'(0)=ref"])
    assert doc["variable"] == "v"
    assert doc["runs"][0]["results"][0]["max_abs"] < 1e-12
    with pytest.raises(shaderfit.Error) as e:
        shaderfit.rational(target="acoss(x)", forms=["1/0"])
    assert e.value.source == "target"
    assert e.value.column == 1


BLINN_PHONG = "1/(3.14159*alpha^2) * pow(NoH, 2/alpha^2 - 2)"


def test_uniform_inputs_split_the_cost_and_the_code(cli):
    doc = shaderfit.cost(BLINN_PHONG, uniform=["alpha"])
    assert doc["targets"]["sass"]["instructions"] == 3
    assert doc["targets"]["sass"]["per_material"]["instructions"] == 6
    out = subprocess.run([cli, "cost", "--uniform", "alpha", "--json", "-", BLINN_PHONG],
                         capture_output=True, text=True, check=True)
    assert json.loads(out.stdout) == doc
    code = shaderfit.codegen(BLINN_PHONG, "glsl", name="d", uniform=["alpha"])
    assert "d_material d_material_values(float alpha)" in code
    assert "float d(float NoH, d_material m)" in code
    with pytest.raises(ValueError, match="uniform input 'beta' is not an input"):
        shaderfit.cost(BLINN_PHONG, uniform=["beta"])


def test_search_with_uniform_inputs_ranks_the_per_pixel_cost():
    nh, alpha = np.meshgrid(np.linspace(0.1, 1, 24), np.linspace(0.1, 0.5, 8))
    nh, alpha = nh.ravel(), alpha.ravel()
    d = np.exp((nh**2 - 1) / (alpha**2 * nh**2)) / (np.pi * alpha**2 * nh**4)
    keep = d >= 0.01
    X = np.column_stack([nh[keep], alpha[keep]])
    front = shaderfit.search(X, d[keep], inputs=["NoH", "alpha"], uniform=["alpha"],
                             loss="max_rel", max_candidates=200000, threads=1, time=60,
                             progress=False)
    cheap = [m for m in front if m.cost <= 3]
    assert cheap and all(m.uniform == ["alpha"] for m in front)
    assert min(m.max_rel for m in cheap) < 1.5  # Blinn-Phong's on these rows is above
    assert "_material_values(float alpha)" in cheap[-1].code("glsl")
