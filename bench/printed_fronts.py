#!/usr/bin/env python3
"""Fronts of real searches, kept for the printer's test (src/search/front/printed_formulas_test.cpp).

    bench/printed_fronts.py [--cli build/release/shaderfit] [--time 4] [--check-only]

Runs `shaderfit search` (default settings, --seed 1, two threads, --time seconds each) on
  - acos(x) on [-1, 1] and erf(x) on [-3, 3], as formulas;
  - Burley diffuse and Henyey-Greenstein as their shader files (bench/shaders), plain and with
    their per-material inputs (--uniform);
  - the ten yardstick cases and ten AI-Feynman equations of bench/compare_builds.py;
and writes every front member (its exact formula, its cost, its inputs' ranges) to
src/search/front/testdata/printed_fronts.json. Each member's display text is checked here as
the test checks it (no `* -`, `- -`, `+ -`, `-(` after an operator or opening a factor, no
`v * v`): the lines that break a rule are printed, and the exit status is 1 if any does.
--check-only checks without writing the file. Standard library and numpy.
"""

import argparse
import csv
import json
import re
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "bench"))
import compare_builds  # noqa: E402  (the yardstick and AI-Feynman cases)

OUT = ROOT / "src" / "search" / "front" / "testdata" / "printed_fronts.json"

# What a printed formula never shows (the test's rules, src/search/front/printed_formulas_test.cpp).
RULES = [
    (re.compile(r"\* -"), "'* -'"),
    (re.compile(r"/ -"), "'/ -'"),
    (re.compile(r"- -"), "'- -'"),
    (re.compile(r"\+ -"), "'+ -'"),
    (re.compile(r"(^|[-+*/(,^] ?)-\("), "'-(' after an operator or opening a factor"),
    (re.compile(r"(?<![\w.])([A-Za-z_]\w*) \* \1(?![\w(])"), "a variable times itself"),
    (re.compile(r"(?<![\w.])([A-Za-z_]\w*) \* \(\1 \* [\w.^ *]+\)"), "a variable times itself"),
]


def broken_rules(text: str) -> list:
    return [why for rx, why in RULES if rx.search(text)]


def shader_cases() -> list:
    functions = {f["name"]: f for f in
                 tomllib.loads((ROOT / "bench/shaders/functions.toml").read_text())["function"]}
    cases = []
    for name in ["burley", "hg"]:
        f = functions[name]
        args = ["--reference-file", str(ROOT / "bench/shaders" / f["file"]),
                "--function", f["function"]]
        for d in f["domain"]:
            args += ["--domain", d]
        cases.append((f"shader {name}", args))
        cases.append((f"shader {name} --uniform", args + ["--uniform", ",".join(f["uniform"])]))
    return cases


def ranges(front_json: dict, args: list) -> dict:
    """Each input's range: the domain given, or the CSV column's."""
    inputs = front_json["inputs"]
    out = {}
    for i, a in enumerate(args):
        if a == "--domain":
            name, span = args[i + 1].split("=")
            lo, hi = span.split(":")[:2]
            out[name] = [float(lo), float(hi)]
    if "--data" in args:
        path = args[args.index("--data") + 1]
        with open(path) as f:
            rows = list(csv.DictReader(f))
        for name in inputs:
            values = [float(r[name]) for r in rows]
            out[name] = [min(values), max(values)]
    return {name: out[name] for name in inputs}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cli", type=Path, default=ROOT / "build" / "release" / "shaderfit")
    ap.add_argument("--time", type=float, default=4.0, help="seconds per search")
    ap.add_argument("--check-only", action="store_true", help="check, do not write the corpus")
    args = ap.parse_args()
    corpus, broken = [], 0
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        cases = [("acos", ["--reference", "acos(x)", "--domain", "x=-1:1"]),
                 ("erf", ["--reference", "erf(x)", "--domain", "x=-3:3"])]
        cases += shader_cases()
        cases += compare_builds.yardstick_cases(args.cli.parent, work)
        cases += compare_builds.feynman_cases(work)
        for name, case in cases:
            out = work / "front.json"
            r = subprocess.run([str(args.cli), "search", *case, "--time", str(args.time),
                                "--threads", "2", "--seed", "1", "--quiet", "--min-step", "0",
                                "--json", str(out)], capture_output=True, text=True)
            if r.returncode != 0:
                raise SystemExit(f"{name}: {r.stderr.strip()}")
            d = json.loads(out.read_text())
            members = []
            for m in d["front"]:
                members.append({"formula": m["formula"], "cost": m["cost"]})
                why = broken_rules(m["formula_display"])
                if why:
                    broken += 1
                    print(f"{name}: {m['formula_display']}   ({', '.join(why)})")
            corpus.append({"case": name, "cost": d["options"]["cost"],
                           "uniform": d.get("uniform") or [],
                           "ranges": ranges(d, case), "members": members})
            print(f"{name}: {len(members)} members", file=sys.stderr)
    if not args.check_only:
        OUT.write_text(json.dumps({"generated_by": "bench/printed_fronts.py", "cases": corpus},
                                  indent=1) + "\n")
        print(f"{sum(len(c['members']) for c in corpus)} members of {len(corpus)} fronts "
              f"written to {OUT.relative_to(ROOT)}")
    print(f"{broken} printed formulas break a rule")
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
