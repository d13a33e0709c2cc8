"""docs/python.md's worked example runs as written."""

import pathlib
import re

DOC = pathlib.Path(__file__).resolve().parents[2] / "docs" / "python.md"


def test_worked_example_runs():
    text = DOC.read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    example = [b for b in blocks if "import shaderfit" in b]
    assert example, "docs/python.md has no example that imports shaderfit"
    for code in example:
        exec(compile(code, str(DOC), "exec"), {"__name__": "docs_example"})
