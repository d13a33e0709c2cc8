"""A problem stated by keywords: a reference formula or shader function sampled by shaderfit,
the errors checked between the samples and certified; a CSV whose columns are inferred."""

import json

import numpy as np
import pytest

import shaderfit

# One thread and a budget of evaluations: reproducible, and quick.
BUDGET = dict(threads=1, time=60, max_candidates=100_000, progress=False)


def test_search_on_a_reference_formula_and_domain():
    front = shaderfit.search(reference="acos(x)", domain={"x": (-1, 1)}, loss="max_abs",
                             **BUDGET)
    assert len(front) >= 3
    x = np.linspace(-1, 1, 200_001)
    for m in front:
        assert m.checked_between_samples
        assert m.inputs == ["x"]
        dense = float(np.max(np.abs(m.predict(x[:, None]) - np.arccos(x))))
        # Never below what a finer grid finds, and close to it.
        assert m.max_abs >= dense * (1 - 1e-9), m
        assert m.max_abs <= dense * 1.01, m
        assert m.float32_max_abs > 0
    assert json.loads(front.to_json())["problem"]["domain"] == ["x=-1.0:1.0"]


def test_certify_keyword_gives_bounds_above_the_error():
    front = shaderfit.search(reference="exp2(x)", domain={"x": (0, 1)}, loss="max_abs",
                             certify=True, certify_time_limit_s=5, **BUDGET)
    bounded = [m for m in front if m.certified_max_abs is not None]
    assert bounded, front
    for m in bounded:
        assert m.certified_max_abs >= m.max_abs


def test_definitions_and_samples():
    front = shaderfit.search(reference="exp(-t)", domain={"x": (0, 1), "y": (0, 2)},
                             define=["t = x * y"], inputs=["t"], samples=512, **BUDGET)
    assert front[-1].inputs == ["t"]


def test_a_shader_function(tmp_path):
    path = tmp_path / "smith.hlsl"
    path.write_text("float G1(float NdotV, float roughness) {\n"
                    "  float a2 = roughness * roughness * roughness * roughness;\n"
                    "  float d = NdotV + sqrt(a2 + (1 - a2) * NdotV * NdotV);\n"
                    "  return NdotV > 0 ? 2 * NdotV / d : 0;\n"
                    "}\n")
    front = shaderfit.search(reference_file=path, function="G1",
                             domain={"NdotV": (0, 1), "roughness": (0.05, 1)}, **BUDGET)
    assert front[-1].inputs == ["NdotV", "roughness"]
    assert "float" in front[-1].code("hlsl")


def test_a_csv_file_needs_no_inputs_or_target(tmp_path):
    path = tmp_path / "xy.csv"
    x = np.linspace(0, 1, 65)
    np.savetxt(path, np.c_[x, 2.5 * np.sqrt(x + 0.5)], delimiter=",", header="x,y", comments="")
    front = shaderfit.search(data=path, **BUDGET)
    assert front[-1].inputs == ["x"]
    assert json.loads(front.to_json())["problem"]["target"] == "y"


def test_a_gap_in_a_csv_column_is_an_error_or_a_dropped_row(tmp_path):
    path = tmp_path / "gap.csv"
    rows = ["x,y"] + [f"{i / 64},{2.5 * (i / 64) + 1}" for i in range(65)]
    rows[10] = rows[10].split(",")[0] + ","
    path.write_text("\n".join(rows) + "\n")
    with pytest.raises(shaderfit.Error) as e:
        shaderfit.search(data=path, **BUDGET)
    assert "column 'y' is numbers but for 1 cell" in str(e.value)
    assert "drop_missing" in str(e.value)
    assert (e.value.line, e.value.column) == (11, len(rows[10]) + 1)
    front = shaderfit.search(data=path, drop_missing=True, **BUDGET)
    problem = json.loads(front.to_json())["problem"]
    assert problem["drop_missing"] is True


def test_bad_problems_are_errors_at_the_keyword(tmp_path):
    with pytest.raises(shaderfit.Error) as e:
        shaderfit.search(reference="acoss(x)", domain={"x": (-1, 1)}, **BUDGET)
    assert "unknown function 'acoss'" in str(e.value)
    assert e.value.source == "reference"
    with pytest.raises(shaderfit.Error) as e:
        shaderfit.search(reference="x + y", domain={"x": (0, 1)}, **BUDGET)
    assert e.value.source == "domain"
    assert "'y'" in str(e.value)
    with pytest.raises(shaderfit.Error) as e:
        shaderfit.search(reference="acos(x)", domain={"x": (1, -1)}, **BUDGET)
    assert e.value.source == "domain"
    with pytest.raises(shaderfit.Error) as e:
        shaderfit.search(reference="log(x)", domain={"x": (-1, 1)}, **BUDGET)
    assert "NaN or infinite" in str(e.value)
    front = shaderfit.search(reference="log(x)", domain={"x": (-1, 1)}, drop_nonfinite=True,
                             **BUDGET)
    assert len(front) >= 1
    with pytest.raises(TypeError):
        shaderfit.search(np.zeros((3, 1)), np.zeros(3), reference="x", domain={"x": (0, 1)})
    with pytest.raises(TypeError):
        shaderfit.search(reference="x", domain={"x": 1})


def test_the_display_loss_on_a_scene():
    # The same loss as `shaderfit search --loss display` and a manifest's loss = "display": the
    # MSE of the scene's samples, each weighed by its pixel's display.
    front = shaderfit.search(reference="fresnel-dielectric-f0", scene="sphere", loss="display",
                             threads=1, time=60, max_candidates=20_000, progress=False)
    assert len(front) >= 2
    for m in front:
        assert m.inputs == ["v_dot_h", "f0"]
        assert m.loss == m.mse
    plain = shaderfit.search(reference="fresnel-dielectric-f0", scene="sphere", loss="mse",
                             threads=1, time=60, max_candidates=20_000, progress=False)
    assert [m.mse for m in plain] != [m.mse for m in front]
    document = json.loads(front.to_json())
    assert document["options"]["loss"] == "display"
    assert document["problem"]["scene"]["kind"] == "sphere"
    assert document["problem"]["scene"]["term"] == "F"
    with pytest.raises(shaderfit.Error) as e:
        shaderfit.search(reference="x^2", domain={"x": (0, 1)}, loss="display", **BUDGET)
    assert e.value.source == "loss"
    assert "the display loss needs a scene" in str(e.value)
    with pytest.raises(shaderfit.Error) as e:
        shaderfit.search(reference="fresnel-dielectric-f0", scene="teapot", **BUDGET)
    assert e.value.source == "scene"
