#!/usr/bin/env python3
"""Two builds of shaderfit side by side: do their searches give the same fronts, and as fast?

    bench/compare_builds.py --before OLD/build/release --after build/release [--evals 200000]

For refactors that must not change results. Each build's `shaderfit search` runs count-budgeted
(--evals, --seed 1, --threads 1, --device cpu, a time limit far above what the budget needs) on
  - the seed task (fresnel-seed data, inputs r0 and x, target R, mse);
  - ten cases of the yardstick (bench/approximations: written by the AFTER build's
    bench/approximations, searched as its manifest states them: loss max_abs, operators auto,
    the per-material inputs of the _material cases);
  - ten AI-Feynman equations (../shared/data/feynman_equations.csv, 2,000 rows drawn as
    bench/feynman/run.py draws them);
and the two JSON fronts are compared by scripts/compare-fronts (formulas, constants, costs and
losses; timings aside). Then the cost model and code generation: --formulas random formulas of
x, y and z (every operator, drawn from a seeded generator) through `shaderfit cost --json -` on
every instruction target and `shaderfit codegen` in every language (float; half GLSL and CUDA;
HLSL with y per material), each output (listing, code or error message) compared byte for byte.
Then the time to target on the seed task (the search's own clock until a
member of cost <= 4 has the MSE of r0 + (x - r0) x^4), the builds interleaved, seeds 1..--seeds:
each seed --repeats times: medians and their ratio. Exit status 0 when every front and every
output is the same. Standard library and numpy.
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "bench" / "feynman"))

YARDSTICK = ["fresnel_schlick", "g1_ggx_schlick", "v_ggx_hammon", "d_blinn_phong_beckmann",
             "aces_narkowicz", "linear_to_srgb_pow", "acos_eberly2", "atan_rajan", "erf_as_7126",
             "v_ggx_schlick_material"]
FEYNMAN = [1, 5, 10, 14, 22, 30, 41, 53, 67, 88]  # equation numbers: 1 to 5 inputs
COMMON = ["--threads", "1", "--seed", "1", "--device", "cpu", "--time", "100000", "--quiet"]


def search(cli: Path, args: list, out: Path) -> None:
    r = subprocess.run([str(cli), "search", *args, *COMMON, "--json", str(out)],
                       capture_output=True, text=True)
    if r.returncode != 0:
        raise SystemExit(f"{cli} search {' '.join(args)} failed:\n{r.stderr.strip()}")


def same_front(a: Path, b: Path) -> tuple[bool, str]:
    r = subprocess.run([sys.executable, str(ROOT / "scripts" / "compare-fronts"), str(a), str(b)],
                       capture_output=True, text=True)
    lines = r.stdout.strip().splitlines()
    return r.returncode == 0, (lines[-1] if r.returncode == 0 else "\n      ".join(lines))


def yardstick_cases(build: Path, work: Path) -> list:
    out = work / "yardstick"
    subprocess.run([str(build / "bench" / "approximations"), str(out)], check=True,
                   capture_output=True)
    manifest = tomllib.loads((out / "manifest.toml").read_text())
    defaults = manifest["defaults"]
    cases = []
    for f in manifest["function"]:
        if f["name"] not in YARDSTICK:
            continue
        args = ["--data", str(out / f["data"]), "--inputs", ",".join(f["inputs"]),
                "--target", f["target"], "--loss", f.get("loss", defaults["loss"]),
                "--ops", f.get("operators", defaults["operators"]),
                "--evolve-ops", f.get("evolution_operators", defaults["evolution_operators"])]
        if f.get("uniform"):
            args += ["--uniform", ",".join(f["uniform"])]
        cases.append((f"yardstick {f['name']}", args))
    return cases


def feynman_cases(work: Path) -> list:
    import numpy as np
    import run as feynman  # bench/feynman/run.py
    equations = {e["number"]: e for e in feynman.load_equations(feynman.DEFAULT_EQUATIONS)}
    cases = []
    for n in FEYNMAN:
        eq = equations[n]
        columns, y = feynman.draw(eq, np.random.default_rng(1000 + n), 2000, 0.0)
        path = work / f"feynman_{n}.csv"
        names = list(columns)
        with open(path, "w") as f:
            f.write(",".join(names + [eq["output"]]) + "\n")
            for i in range(len(y)):
                f.write(",".join(repr(float(columns[k][i])) for k in names) + f",{float(y[i])!r}\n")
        cases.append((f"feynman {n} {eq['name']}", ["--data", str(path), "--target", eq["output"]]))
    return cases


def seed_target(cli: Path, work: Path) -> float:
    out = work / "seed_eval.json"
    subprocess.run([str(cli), "eval", "--dataset", "fresnel-seed", "--target", "R",
                    "r0 + (x - r0)*x^4", "--json", str(out)], check=True, capture_output=True)
    return json.loads(out.read_text())["results"][0]["all"]["mse"] * (1 + 1e-9)


def time_to_target(cli: Path, seed: int, target: float, work: Path) -> float:
    out = work / "ttt.json"
    r = subprocess.run([str(cli), "search", "--dataset", "fresnel-seed", "--inputs", "r0,x",
                        "--target", "R", "--threads", "1", "--seed", str(seed), "--device", "cpu",
                        "--time", "60", "--quiet", "--stop-loss", repr(target), "--stop-cost", "4",
                        "--json", str(out)], capture_output=True, text=True)
    if r.returncode != 0:
        raise SystemExit(f"{cli}: time to target failed:\n{r.stderr.strip()}")
    s = json.loads(out.read_text())["summary"]
    if s["termination"] != "target reached":
        raise SystemExit(f"{cli}: seed {seed} did not reach the target in 60 s")
    return s["total_time_s"]


TARGETS = ["sass", "ptx", "generic", "sass-half2", "rdna2", "rdna3"]
CODEGEN = [[("--lang", lang)] for lang in ("glsl", "hlsl", "cuda", "cpp", "metal")] + [
    [("--lang", "glsl"), ("--precision", "half")], [("--lang", "cuda"), ("--precision", "half")],
    [("--lang", "hlsl"), ("--uniform", "y")]]


def random_formulas(count: int, seed: int = 1) -> list:
    """Formulas of x, y, z up to five levels deep, over every operator of the formula language."""
    import random
    rng = random.Random(seed)
    unary = ["sqrt", "rsqrt", "exp2", "log2", "exp", "log", "sin", "cos", "abs", "saturate",
             "sign", "asin", "acos", "atan", "tanh", "erf", "rcp"]
    binary = ["min", "max", "pow", "copysign", "atan2"]

    def leaf() -> str:
        if rng.random() < 0.75:
            return rng.choice(["x", "y", "z"])
        return rng.choice(["1", "2", "0.5", "3.14159", "-1", "0.25", "1.4427"])

    def expr(depth: int) -> str:
        if depth == 0 or rng.random() < 0.2:
            return leaf()
        r = rng.random()
        if r < 0.3:
            return f"{rng.choice(unary)}({expr(depth - 1)})"
        if r < 0.35:
            return f"-({expr(depth - 1)})"
        if r < 0.45:
            a, b, c, d = (expr(depth - 1) for _ in range(4))
            return f"select({a} >= {b}, {c}, {d})"
        if r < 0.5:
            return f"fma({expr(depth - 1)}, {expr(depth - 1)}, {expr(depth - 1)})"
        if r < 0.55:
            return f"({expr(depth - 1)})^{rng.choice([2, 3, 4, 5, -1, -2])}"
        if r < 0.8:
            return f"({expr(depth - 1)} {rng.choice('+-*/')} {expr(depth - 1)})"
        return f"{rng.choice(binary)}({expr(depth - 1)}, {expr(depth - 1)})"

    return [expr(rng.randint(1, 5)) for _ in range(count)]


def outputs(cli: Path, formula: str) -> list:
    """What the build prints for the formula: its cost on every target, its code in every form."""
    runs = [["cost", "--inputs", "x,y,z", "--target", t, "--json", "-"] for t in TARGETS]
    runs += [["codegen", "--inputs", "x,y,z", *[a for pair in form for a in pair]]
             for form in CODEGEN]
    out = []
    for args in runs:
        r = subprocess.run([str(cli), *args, "--", formula], capture_output=True, text=True)
        out.append((args, r.returncode, r.stdout, r.stderr))
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--before", required=True, type=Path, help="the previous build's folder")
    ap.add_argument("--after", default=ROOT / "build" / "release", type=Path,
                    help="this build's folder (default build/release)")
    ap.add_argument("--evals", type=int, default=200000, help="candidates per search")
    ap.add_argument("--seeds", type=int, default=10, help="seeds of the time to target")
    ap.add_argument("--repeats", type=int, default=5,
                    help="runs of each seed and build (the median is over all)")
    ap.add_argument("--formulas", type=int, default=200,
                    help="random formulas whose costs and code are compared (0: none)")
    ap.add_argument("--skip-timing", action="store_true", help="fronts only")
    ap.add_argument("--skip-fronts", action="store_true", help="the time to target only")
    args = ap.parse_args()
    before, after = args.before / "shaderfit", args.after / "shaderfit"
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        cases = [("seed task", ["--dataset", "fresnel-seed", "--inputs", "r0,x", "--target", "R"])]
        if args.skip_fronts:
            cases = []
        else:
            cases += yardstick_cases(args.after, work) + feynman_cases(work)
        different = 0
        budget = ["--evals", str(args.evals)]
        for i, (name, case) in enumerate(cases):
            a, b = work / f"{i}_before.json", work / f"{i}_after.json"
            search(before, case + budget, a)
            search(after, case + budget, b)
            same, text = same_front(a, b)
            different += not same
            print(f"{'same     ' if same else 'DIFFERENT'} {name:40s} {text}", flush=True)
        if cases:
            print(f"{len(cases) - different} of {len(cases)} fronts the same "
                  f"({args.evals} candidates each, seed 1, one thread)")
        if args.formulas > 0 and not args.skip_fronts:
            same_outputs, total, shown = 0, 0, 0
            for f in random_formulas(args.formulas):
                for x, y in zip(outputs(before, f), outputs(after, f)):
                    total += 1
                    if x == y:
                        same_outputs += 1
                    elif shown < 5:  # the first few
                        shown += 1
                        print(f"DIFFERENT shaderfit {' '.join(x[0])} -- '{f}'")
            print(f"{same_outputs} of {total} cost listings and generated functions the same "
                  f"({args.formulas} random formulas x {len(TARGETS)} targets and "
                  f"{len(CODEGEN)} code forms)", flush=True)
            different += total - same_outputs
        if not args.skip_timing:
            target = seed_target(after, work)
            tb, ta = [], []
            for _ in range(args.repeats):
                for seed in range(1, args.seeds + 1):  # interleaved: both see the same load
                    tb.append(time_to_target(before, seed, target, work))
                    ta.append(time_to_target(after, seed, target, work))
            mb, ma = statistics.median(tb), statistics.median(ta)
            print(f"time to target, seed task, one thread, seeds 1..{args.seeds} x {args.repeats}: "
                  f"before median "
                  f"{mb * 1e3:.1f} ms, after {ma * 1e3:.1f} ms, ratio after/before {ma / mb:.3f}")
    return 0 if different == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
