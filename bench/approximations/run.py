#!/usr/bin/env python3
"""The yardstick: shaderfit's search against published real-time approximations.

    nice python3 bench/approximations/run.py --time 5

Runs build/release/bench/approximations to write every case's samples (CASE.csv: inputs, ref),
the published formulas' costs and errors (cases.json) and the batch manifest (manifest.toml)
into --out, then the whole yardstick as one batch,

    shaderfit batch OUT/manifest.toml --out OUT/batch

every case with loss max_abs, seed 1, --threads per case (default 1; cases run cores / threads at
once), operators `auto` (one rule applied to each
case's data, not tuned per case), the published formula as its baseline and the goal to beat it:
the front member with the least max |err| among those no costlier than the published formula,
and whether it wins (cost <= and max |err| <=). It prints a Markdown table, also written to
OUT/table.md, and the numbers to OUT/results.json. A batch interrupted and run again resumes:
finished cases are not searched again. Python 3 standard library only; nothing is downloaded.
docs/approximations.md has the sources.
"""

import argparse
import json
import os
import subprocess
import sys

OPS = "auto"
EVOLVE_OPS = "auto"
SEED = 1


def set_default(manifest: str, line: str) -> None:
    """Adds `line` to the [defaults] table of `manifest`."""
    with open(manifest, encoding="utf-8") as f:
        text = f.read()
    with open(manifest, "w", encoding="utf-8") as f:
        f.write(text.replace("[defaults]\n", "[defaults]\n" + line + "\n", 1))


def keep_only(manifest: str, names: set) -> None:
    """Drops the [[function]] tables of `manifest` whose name is not in `names`."""
    with open(manifest, encoding="utf-8") as f:
        head, *tables = f.read().split("\n[[function]]\n")
    kept = [t for t in tables if t.split("\n", 1)[0].split('"')[1] in names]
    with open(manifest, "w", encoding="utf-8") as f:
        f.write("\n[[function]]\n".join([head] + kept))


def main() -> int:
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--time", type=float, default=5.0, help="search seconds per case (default 5)")
    ap.add_argument("--threads", type=int, default=1, help="search threads per case (default 1)")
    ap.add_argument("--parallel", type=int, default=0,
                    help="cases searched at once (default: cores / threads)")
    ap.add_argument("--build", default=os.path.join(root, "build", "release"),
                    help="build folder with shaderfit and bench/approximations")
    ap.add_argument("--out", default=os.path.join(root, "build", "approximations"),
                    help="folder for the CSVs, the search JSONs and the table")
    ap.add_argument("--cases", default="", help="comma-separated case names (default: all)")
    args = ap.parse_args()

    gen = os.path.join(args.build, "bench", "approximations")
    shaderfit = os.path.join(args.build, "shaderfit")
    for exe in (gen, shaderfit):
        if not os.access(exe, os.X_OK):
            print(f"run.py: {exe} not found; build the release preset first", file=sys.stderr)
            return 2
    os.makedirs(args.out, exist_ok=True)
    subprocess.run([gen, args.out, "--time", str(args.time)], check=True,
                   stdout=subprocess.DEVNULL)
    with open(os.path.join(args.out, "cases.json"), encoding="utf-8") as f:
        cases = json.load(f)
    if args.cases:
        wanted = set(args.cases.split(","))
        unknown = wanted - {c["name"] for c in cases}
        if unknown:
            print(f"run.py: unknown cases: {', '.join(sorted(unknown))}", file=sys.stderr)
            return 2
        cases = [c for c in cases if c["name"] in wanted]
        keep_only(os.path.join(args.out, "manifest.toml"), wanted)
    if args.threads != 1:
        set_default(os.path.join(args.out, "manifest.toml"), f"threads = {args.threads}")
    parallel = args.parallel or max(1, (os.cpu_count() or 1) // args.threads)

    cmd = [shaderfit, "batch", os.path.join(args.out, "manifest.toml"), "--out",
           os.path.join(args.out, "batch"), "--quiet"]
    cmd += ["--parallel", str(parallel)]
    run = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    sys.stderr.write(run.stdout + run.stderr)
    with open(os.path.join(args.out, "batch", "batch.json"), encoding="utf-8") as f:
        batch = json.load(f)
    entries = {e["name"]: e for e in batch["entries"]}

    results = []
    for c in cases:
        e = entries.get(c["name"])
        best = None
        used_ops = None
        symmetry = None
        if e is not None:
            doc = e["run"]
            front = doc["front"]
            # The operators the search used (auto resolved), enumeration | evolution.
            used_ops = doc["options"]["operators"] + " | " + doc["options"]["evolution_operators"]
            sy = doc["summary"].get("symmetry")
            if sy:
                symmetry = sy["kind"] + " (" + sy.get("method", "mirrored_pairs") + ")"
            # The goal's member: the least max |err| among those no costlier than published.
            if front:
                best = front[e["chosen"]]
                if best["cost"] > c["cost"]:
                    best = None
        else:
            print(f"run.py: no result for {c['name']}", file=sys.stderr)
        win = best is not None and best["max_abs"] <= c["max_abs"]
        results.append({"case": c["name"], "published_cost": c["cost"], "operators": used_ops,
                        "uniform": c.get("uniform", []),
                        "published_material_cost": c.get("material_cost", 0),
                        "ours_material_cost": best.get("material_cost", 0) if best else None,
                        "symmetry": symmetry,
                        "published_max_abs": c["max_abs"],
                        "ours_cost": best["cost"] if best else None,
                        "ours_max_abs": best["max_abs"] if best else None,
                        "ours_float32_stable": best.get("float32_stable") if best else None,
                        "ours_formula": best["formula"] if best else None, "win": win})

    # Costs are per pixel; with per-material inputs (uniform) the per-material count follows
    # after a slash ("3 / 5"): SASS instructions once per material.
    lines = ["| case | published cost | published max abs err | ours max abs err (cost <= published) "
             "| our cost | ratio ours/published | f32 stable | symmetry | ours wins |",
             "| --- | ---: | ---: | ---: | ---: | ---: | --- | --- | --- |"]

    def cost_text(pixel, material, uniform):
        return f"{pixel:g}" if not uniform else f"{pixel:g} / {material:g}"

    for r in results:
        ours = "-" if r["ours_max_abs"] is None else f"{r['ours_max_abs']:.3g}"
        cost = ("-" if r["ours_cost"] is None
                else cost_text(r["ours_cost"], r["ours_material_cost"] or 0, r["uniform"]))
        published = cost_text(r["published_cost"], r["published_material_cost"], r["uniform"])
        ratio = ("-" if r["ours_max_abs"] is None or r["published_max_abs"] == 0
                 else f"{r['ours_max_abs'] / r['published_max_abs']:.3g}")
        stable = "-" if r["ours_float32_stable"] is None else ("yes" if r["ours_float32_stable"] else "no")
        lines.append(f"| {r['case']} | {published} | {r['published_max_abs']:.3g} | {ours} "
                     f"| {cost} | {ratio} | {stable} | {r['symmetry'] or '-'} "
                     f"| {'yes' if r['win'] else 'no'} |")
    wins = sum(r["win"] for r in results)
    lines.append("")
    lines.append(f"Won {wins} of {len(results)} ({100.0 * wins / max(len(results), 1):.0f}%) with "
                 f"--time {args.time:g} --threads {args.threads} (per case, {parallel} at once) "
                 f"--seed {SEED} "
                 f"--ops {OPS} --evolve-ops {EVOLVE_OPS}, in {batch['seconds']:.0f} s.")
    table = "\n".join(lines)
    print(table)
    with open(os.path.join(args.out, "table.md"), "w", encoding="utf-8") as f:
        f.write(table + "\n")
    with open(os.path.join(args.out, "results.json"), "w", encoding="utf-8") as f:
        json.dump({"time": args.time, "threads": args.threads, "seed": SEED, "ops": OPS,
                   "evolve_ops": EVOLVE_OPS, "results": results}, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
