"""Shared fixtures: the seed's Fresnel data, its formula's error, and the CLI of this build."""

import os
import shutil

import numpy as np
import pytest

import shaderfit

SEED_FORMULA = "r0 + (x - r0)*x^4"


@pytest.fixture(scope="session")
def seed_data():
    return shaderfit.datasets.fresnel_seed(seed=1)


@pytest.fixture(scope="session")
def seed_mse(seed_data):
    prediction = shaderfit.evaluate(SEED_FORMULA, seed_data.X, inputs=seed_data.inputs)
    return float(np.mean((prediction - seed_data.y) ** 2))


@pytest.fixture(scope="session")
def cli():
    """The shaderfit command line of this build (ctest sets SHADERFIT_CLI), else on PATH."""
    path = os.environ.get("SHADERFIT_CLI") or shutil.which("shaderfit")
    if not path:
        pytest.skip("skipped: the shaderfit command line was not found (SHADERFIT_CLI)")
    return path
