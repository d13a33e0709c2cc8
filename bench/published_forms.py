#!/usr/bin/env python3
"""The yardstick's published formulas, kept for the RDNA cost check (src/codegen/rdna_check_test.cpp).

    bench/published_forms.py [--approximations build/release/bench/approximations]

Runs the yardstick's generator (bench/approximations) into a scratch folder and writes each
distinct published formula of its manifest (the baseline of every function: name, inputs,
formula) to src/codegen/testdata/published_forms.json, which the test compiles with clang for
gfx1030 and gfx1100. Standard library only.
"""

import argparse
import json
import subprocess
import tempfile
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--approximations", default=str(ROOT / "build/release/bench/approximations"))
    ap.add_argument("--out", default=str(ROOT / "src/codegen/testdata/published_forms.json"))
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        subprocess.run([a.approximations, tmp], check=True, capture_output=True)
        manifest = tomllib.loads((Path(tmp) / "manifest.toml").read_text())
    forms, seen = [], set()
    for f in manifest["function"]:
        key = (f["baseline"], tuple(f["inputs"]))
        if key in seen:
            continue
        seen.add(key)
        forms.append({"name": f["name"], "inputs": f["inputs"], "formula": f["baseline"]})
    Path(a.out).write_text(json.dumps({"forms": forms}, indent=1) + "\n")
    print(f"{len(forms)} published formulas -> {a.out}")


if __name__ == "__main__":
    main()
