#!/usr/bin/env python3
"""The AI-Feynman benchmark: how many of the 100 equations a search recovers exactly.

For each equation of the AI-Feynman table (Udrescu & Tegmark 2020; a CSV with the columns
Number, Output, Formula, "# variables", v1_name, v1_low, v1_high, ...):
  - 2,000 training rows drawn uniformly from the listed ranges (numpy, seeded per equation);
  - `shaderfit search --data train.csv --target OUTPUT --time T --threads 1 --json ...`;
  - the front's most accurate member on the training rows is taken (ties: the cheaper);
  - it is exact when 1 - R^2 <= 1e-9 on 2,000 fresh rows of the same ranges AND 1 - R^2 <= 1e-8
    on 2,000 rows whose ranges are widened by 50% above (hi' = hi + (hi - lo) / 2), so a formula
    that only fits the training range fails. Rows where the equation is not finite are dropped.

The formula is evaluated here with numpy, independently of shaderfit, from the member's
full-precision text. Writes OUT/results.json and prints a table per equation and by number of
variables. Example (the figures in the closing note):

  bench/feynman/run.py --time 40 --jobs 2 --out /tmp/feynman
"""

from __future__ import annotations

import argparse
import concurrent.futures
import csv
import json
import math
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
DEFAULT_EQUATIONS = ROOT.parent / "shared" / "data" / "feynman_equations.csv"
TRAIN_TOLERANCE = 1e-9
WIDE_TOLERANCE = 1e-8


def load_equations(path: Path) -> list[dict]:
    out = []
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            variables = []
            for k in range(1, 11):
                name = (row.get(f"v{k}_name") or "").strip()
                if name:
                    variables.append(
                        (name, float(row[f"v{k}_low"]), float(row[f"v{k}_high"])))
            out.append({
                "number": int(row["Number"]),
                "name": row["Filename"].strip(),
                "output": row["Output"].strip(),
                "formula": row["Formula"].strip(),
                "variables": variables,
            })
    out.sort(key=lambda e: e["number"])
    return out


# The equations' own syntax (Python with numpy's functions).
EQUATION_NAMES = {
    "exp": np.exp, "sqrt": np.sqrt, "sin": np.sin, "cos": np.cos, "tan": np.tan,
    "arcsin": np.arcsin, "arccos": np.arccos, "arctan": np.arctan, "tanh": np.tanh,
    "ln": np.log, "log": np.log, "pi": np.pi,
}


def evaluate_equation(eq: dict, columns: dict) -> np.ndarray:
    with np.errstate(all="ignore"):
        return np.asarray(eval(eq["formula"], {"__builtins__": {}}, {**EQUATION_NAMES, **columns}),
                          dtype=np.float64) * np.ones(len(next(iter(columns.values()))))


def _erf(x):
    return np.vectorize(math.erf, otypes=[np.float64])(x)


# shaderfit's formula syntax (expr/print): the operators of expr/op.hpp by name, ^ for powers.
FORMULA_NAMES = {
    "sqrt": np.sqrt, "rsqrt": lambda a: 1.0 / np.sqrt(a), "rcp": lambda a: 1.0 / a,
    "exp2": np.exp2, "log2": np.log2, "exp": np.exp, "log": np.log, "abs": np.abs,
    "saturate": lambda a: np.clip(a, 0.0, 1.0), "sin": np.sin, "cos": np.cos,
    "pow": lambda a, b: np.exp2(b * np.log2(a)), "min": np.fmin, "max": np.fmax,
    "fma": lambda a, b, c: a * b + c, "sign": np.sign, "copysign": np.copysign,
    "select": lambda a, b, c: np.where(a >= 0, b, c), "asin": np.arcsin, "acos": np.arccos,
    "atan": np.arctan, "atan2": np.arctan2, "tanh": np.tanh, "erf": _erf,
}


def evaluate_formula(text: str, columns: dict, rows: int) -> np.ndarray:
    expr = re.sub(r"\^", "**", text)
    with np.errstate(all="ignore"):
        value = eval(expr, {"__builtins__": {}}, {**FORMULA_NAMES, **columns})
    return np.asarray(value, dtype=np.float64) * np.ones(rows)


def draw(eq: dict, rng: np.random.Generator, rows: int, widen: float) -> tuple[dict, np.ndarray]:
    columns = {}
    for name, lo, hi in eq["variables"]:
        columns[name] = rng.uniform(lo, hi + widen * (hi - lo), rows)
    y = evaluate_equation(eq, columns)
    keep = np.isfinite(y)
    return {k: v[keep] for k, v in columns.items()}, y[keep]


def one_minus_r2(y: np.ndarray, f: np.ndarray) -> float:
    if not np.all(np.isfinite(f)):
        return math.inf
    var = float(np.var(y))
    mse = float(np.mean((y - f) ** 2))
    return mse / var if var > 0 else (0.0 if mse == 0 else math.inf)


NEUTRAL = re.compile(r"(\* 1(?![0-9.e])|/ 1(?![0-9.e])|\+ 0(?![0-9.e])|- 0(?![0-9.e])|\^1(?![0-9])|"
                     r"(?<![A-Za-z_0-9.])1 \*|(?<![A-Za-z_0-9.])0 \+)")
NUMBER = re.compile(r"(?<![A-Za-z_0-9.])([0-9]+\.?[0-9]*(?:e[-+]?[0-9]+)?)")
NOISE_LEVEL = 1e-9  # rmse <= 1e-9 rms(y): shaderfit's kNoiseLevel (search/tidy.hpp)


def front_noise_check(front: list, y: np.ndarray) -> dict:
    """The issue's front rules, checked from outside: members at noise level print no neutral
    part (`* 1`, `+ 0`, `^1`) and no constant below 1e-6 in magnitude (a noise term), and nothing
    follows the first member at noise level."""
    bound = NOISE_LEVEL * math.sqrt(float(np.mean(y * y)))
    at_noise = [i for i, m in enumerate(front) if math.sqrt(m["mse"]) <= bound]
    noisy = []
    for i in at_noise:
        text = front[i].get("formula_display", front[i]["formula"])
        tiny = [v for v in NUMBER.findall(text) if 0 < abs(float(v)) < 1e-6]
        if NEUTRAL.search(text) or tiny:
            noisy.append(text)
    after = len(front) - 1 - at_noise[0] if at_noise else 0
    return {"members_at_noise_level": len(at_noise), "printing_noise": noisy,
            "members_after_first": after}


def run_one(eq: dict, args) -> dict:
    work = Path(args.out) / f"eq{eq['number']:03d}"
    work.mkdir(parents=True, exist_ok=True)
    seed = args.seed * 1000 + eq["number"]
    train_cols, train_y = draw(eq, np.random.default_rng([seed, 0]), args.rows, 0.0)
    test_cols, test_y = draw(eq, np.random.default_rng([seed, 1]), args.rows, 0.0)
    wide_cols, wide_y = draw(eq, np.random.default_rng([seed, 2]), args.rows, 0.5)
    names = [v[0] for v in eq["variables"]]
    with open(work / "train.csv", "w") as f:
        f.write(",".join(names + [eq["output"]]) + "\n")
        data = np.column_stack([train_cols[n] for n in names] + [train_y])
        for row in data:
            f.write(",".join(repr(float(v)) for v in row) + "\n")
    command = [args.shaderfit, "search", "--data", str(work / "train.csv"), "--target",
               eq["output"], "--time", str(args.time), "--threads", str(args.threads), "--seed",
               str(args.seed), "--quiet", "--json", str(work / "run.json")] + args.extra
    start = time.monotonic()
    if args.reuse and (work / "run.json").exists():
        proc = subprocess.CompletedProcess(command, 0, "", "")
    else:
        proc = subprocess.run(command, capture_output=True, text=True)
    wall = time.monotonic() - start
    result = {"number": eq["number"], "name": eq["name"], "variables": len(names),
              "equation": eq["formula"], "wall_s": wall, "exact": False}
    if proc.returncode != 0:
        result["error"] = (proc.stderr or proc.stdout).strip().splitlines()[-1:]
        return result
    run = json.load(open(work / "run.json"))
    front = run["front"]
    best = min(front, key=lambda m: (m["mse"], m["cost"]))
    result["operators"] = run["options"].get("operators")
    result["noise"] = front_noise_check(front, train_y)
    result.update(formula=best["formula"], display=best.get("formula_display", best["formula"]),
                  cost=best["cost"], train_mse=best["mse"], front_size=len(front))
    try:
        result["test"] = one_minus_r2(test_y, evaluate_formula(best["formula"], test_cols, len(test_y)))
        result["wide"] = one_minus_r2(wide_y, evaluate_formula(best["formula"], wide_cols, len(wide_y)))
    except Exception as e:  # a formula numpy cannot read is a miss, and said so
        result["error"] = f"numpy evaluation: {e}"
        return result
    result["exact"] = bool(result["test"] <= TRAIN_TOLERANCE and result["wide"] <= WIDE_TOLERANCE)
    return result


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--equations", default=str(DEFAULT_EQUATIONS))
    p.add_argument("--shaderfit", default=str(ROOT / "build" / "release" / "shaderfit"))
    p.add_argument("--time", type=float, default=40.0, help="seconds per equation (default 40)")
    p.add_argument("--threads", type=int, default=1, help="threads per search (default 1)")
    p.add_argument("--jobs", type=int, default=1, help="equations searched at once (default 1)")
    p.add_argument("--rows", type=int, default=2000)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--only", default="", help="equation numbers, e.g. 2,5,18-20")
    p.add_argument("--out", default="/tmp/shaderfit-feynman")
    p.add_argument("--reuse", action="store_true",
                   help="score the fronts an earlier run left in --out instead of searching")
    p.add_argument("extra", nargs="*", help="more search options, after --")
    args = p.parse_args()
    equations = load_equations(Path(args.equations))
    if args.only:
        wanted = set()
        for part in args.only.split(","):
            lo, _, hi = part.partition("-")
            wanted.update(range(int(lo), int(hi or lo) + 1))
        equations = [e for e in equations if e["number"] in wanted]
    Path(args.out).mkdir(parents=True, exist_ok=True)
    results = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        futures = [pool.submit(run_one, e, args) for e in equations]
        for fut in concurrent.futures.as_completed(futures):
            r = fut.result()
            results.append(r)
            mark = "exact" if r["exact"] else "miss "
            print(f"{r['number']:3d} {r['name']:10s} {mark} test {r.get('test', math.nan):9.2e} "
                  f"wide {r.get('wide', math.nan):9.2e}  {r.get('display', r.get('error', ''))}",
                  flush=True)
    results.sort(key=lambda r: r["number"])
    json.dump({"command": sys.argv, "results": results}, open(Path(args.out) / "results.json", "w"),
              indent=1)
    exact = sum(r["exact"] for r in results)
    print(f"\nexact: {exact} of {len(results)}")
    print("variables  equations  exact")
    for n in sorted({r["variables"] for r in results}):
        group = [r for r in results if r["variables"] == n]
        print(f"{n:9d}  {len(group):9d}  {sum(r['exact'] for r in group):5d}")
    print("misses:", " ".join(str(r["number"]) for r in results if not r["exact"]))
    checked = [r for r in results if "noise" in r]
    noisy = sum(len(r["noise"]["printing_noise"]) for r in checked)
    level = sum(r["noise"]["members_at_noise_level"] for r in checked)
    after = sum(1 for r in checked if r["noise"]["members_after_first"] > 0)
    print(f"fronts: {level} members at noise level in {len(checked)} fronts, {noisy} printing "
          f"noise; {after} fronts with a member after their first noise-level one")
    return 0


if __name__ == "__main__":
    sys.exit(main())
