#!/usr/bin/env python3
"""The evolution on large data: generations per second and fronts, two builds side by side.

    bench/evolution_speed.py --before OLD/build/release [--after build/release] [--time 20]

Each build's `shaderfit search --strategy evolve --threads 1 --device cpu --time T --seed S` runs
(--strategy both: the enumeration first, as `shaderfit search` runs by default)
on shader references sampled on their domains (../shared/data/shaders):
  - burley: Fd_Burley of burley.hlsl over NoV, NoL, LoH, roughness in [0, 1] (15,096 rows);
  - hg: phaseHG of hg.glsl over cosTheta in [-1, 1], g in [0, 0.9];
  - hg_uniform: the same with g per material (--uniform g);
seeds 1..--seeds, the builds interleaved (both see the same load). Printed: per case and build,
the median generations per second (summary.generations / summary.evolution_time_s) and their
ratio after/before; then the front's best RMS error at cost <= 8, 11, 13, 15, the median over
the seeds, before and after. Standard library only.
"""

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SHADERS = ROOT.parent / "shared" / "data" / "shaders"
COSTS = [8, 11, 13, 15]


def cases(shaders: Path) -> dict:
    burley = ["--reference-file", str(shaders / "burley.hlsl"), "--function", "Fd_Burley",
              "--domain", "NoV=0:1", "--domain", "NoL=0:1", "--domain", "LoH=0:1",
              "--domain", "roughness=0:1"]
    hg = ["--reference-file", str(shaders / "hg.glsl"), "--function", "phaseHG",
          "--domain", "cosTheta=-1:1", "--domain", "g=0:0.9"]
    return {"burley": burley, "hg": hg, "hg_uniform": hg + ["--uniform", "g"]}


def search(cli: Path, args: list, seed: int, seconds: float, strategy: str, out: Path) -> dict:
    r = subprocess.run([str(cli), "search", *args, "--strategy", strategy, "--threads", "1",
                        "--device", "cpu", "--time", str(seconds), "--seed", str(seed), "--quiet",
                        "--json", str(out)], capture_output=True, text=True)
    if r.returncode != 0:
        raise SystemExit(f"{cli} search {' '.join(args)} failed:\n{r.stderr.strip()}")
    return json.loads(out.read_text())


def best_rms(front: list, cost: float) -> float:
    return min((m["rmse"] for m in front if m["cost"] <= cost), default=float("inf"))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--before", required=True, type=Path, help="the previous build's folder")
    ap.add_argument("--after", default=ROOT / "build" / "release", type=Path,
                    help="this build's folder (default build/release)")
    ap.add_argument("--time", type=float, default=20, help="seconds per search (default 20)")
    ap.add_argument("--seeds", type=int, default=3, help="seeds 1..N per case (default 3)")
    ap.add_argument("--shaders", type=Path, default=SHADERS, help="the shader files' folder")
    ap.add_argument("--cases", default="burley,hg,hg_uniform", help="comma-separated")
    ap.add_argument("--strategy", default="evolve",
                    help="evolve (default), or both: the fronts as `shaderfit search` finds them")
    args = ap.parse_args()
    builds = {"before": args.before / "shaderfit", "after": args.after / "shaderfit"}
    all_cases = cases(args.shaders)
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.cases.split(","):
            speed = {b: [] for b in builds}
            rms = {b: {c: [] for c in COSTS} for b in builds}
            rows = None
            for seed in range(1, args.seeds + 1):
                for b, cli in builds.items():
                    j = search(cli, all_cases[name], seed, args.time, args.strategy,
                               Path(tmp) / f"{b}.json")
                    s = j["summary"]
                    speed[b].append(s["generations"] / s["evolution_time_s"])
                    for c in COSTS:
                        rms[b][c].append(best_rms(j["front"], c))
                    rows = j["data"]["rows"]
            mb, ma = statistics.median(speed["before"]), statistics.median(speed["after"])
            print(f"{name} ({rows} rows), --strategy {args.strategy}, {args.time:g} s, one thread, "
                  f"seeds 1..{args.seeds}: generations per second, median: before {mb:.2f}, "
                  f"after {ma:.2f}, ratio after/before {ma / mb:.2f}", flush=True)
            for b in builds:
                print(f"  {b:6s} per seed: " + ", ".join(f"{v:.2f}" for v in speed[b]))
            print("  best RMS error at cost <=  " + "".join(f"{c:>12d}" for c in COSTS))
            median = {b: [statistics.median(rms[b][c]) for c in COSTS] for b in builds}
            for b in builds:
                print(f"  {b:6s} median             " + "".join(f"{v:12.3e}" for v in median[b]))
            verdict = ["yes" if a <= b else "NO" for a, b in zip(median["after"], median["before"])]
            print("  after <= before            " + "".join(f"{v:>12s}" for v in verdict))
            for b in builds:
                for i, seed in enumerate(range(1, args.seeds + 1)):
                    print(f"  {b:6s} seed {seed:<3d}           " +
                          "".join(f"{rms[b][c][i]:12.3e}" for c in COSTS))
            sys.stdout.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main())
