"""shaderfit: cheap formulas for expensive functions, from Python (docs/python.md).

    import shaderfit
    data = shaderfit.datasets.fresnel_seed(seed=1)
    front = shaderfit.search(data.X, data.y, inputs=data.inputs, time=2)
    best = front.best(max_cost=4)
    print(best, best.mse, best.cost("sass"))
    print(best.code("glsl"))
"""

from . import _errors
from . import _shaderfit  # noqa: F401  (the library; raises shaderfit.Error)
from . import datasets
from ._commands import FitResult, codegen, cost, evaluate, fit, latex, rational
from ._errors import Error
from ._estimator import ShaderFitRegressor
from ._front import Front, Member
from ._search import search, search_options

__all__ = [
    "Error", "Front", "Member", "FitResult", "ShaderFitRegressor", "search", "search_options",
    "evaluate", "cost", "codegen", "latex", "fit", "rational", "datasets",
]
__version__ = "0.1.0"
