#!/usr/bin/env python3
"""The yardstick: shaderfit's search against published real-time approximations.

    nice python3 bench/approximations/run.py --time 5 --threads 1

Runs build/release/bench/approximations to write every case's samples (CASE.csv: inputs, ref)
and the published formulas' costs and errors (cases.json) into --out, then runs

    shaderfit search --data CASE.csv --inputs ... --target ref --loss max_abs
                     --time T --threads N --seed 1 --ops OPS --evolve-ops EVOLVE_OPS
                     --quiet --json CASE.search.json

on each case with the same operator choice and budget for all (OPS and EVOLVE_OPS below: `auto`,
one rule applied to each case's data, not tuned per case), and prints a Markdown table: the published cost and max |err|, the best max |err| of
the search's front at cost <= the published cost, and whether it wins (cost <= and max |err| <=).
The table is also written to OUT/table.md and the numbers to OUT/results.json.
Python 3 standard library only; nothing is downloaded. docs/approximations.md has the sources.
"""

import argparse
import json
import os
import subprocess
import sys

# One documented operator choice for every case (docs/approximations.md, docs/search.md): the
# search's `auto` sets, chosen from each case's data by one rule (the shading set; pow in the
# enumeration for a high dynamic range), not tuned per case. The search prints what it chose.
OPS = "auto"
EVOLVE_OPS = "auto"
SEED = 1


def main() -> int:
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--time", type=float, default=5.0, help="search seconds per case (default 5)")
    ap.add_argument("--threads", type=int, default=1, help="search threads (default 1)")
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
    subprocess.run([gen, args.out], check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(args.out, "cases.json"), encoding="utf-8") as f:
        cases = json.load(f)
    if args.cases:
        wanted = set(args.cases.split(","))
        unknown = wanted - {c["name"] for c in cases}
        if unknown:
            print(f"run.py: unknown cases: {', '.join(sorted(unknown))}", file=sys.stderr)
            return 2
        cases = [c for c in cases if c["name"] in wanted]

    results = []
    for c in cases:
        out_json = os.path.join(args.out, c["name"] + ".search.json")
        cmd = [shaderfit, "search", "--data", os.path.join(args.out, c["name"] + ".csv"),
               "--inputs", ",".join(c["inputs"]), "--target", "ref", "--loss", "max_abs",
               "--time", str(args.time), "--threads", str(args.threads), "--seed", str(SEED),
               "--ops", OPS, "--evolve-ops", EVOLVE_OPS, "--quiet", "--json", out_json]
        # Inputs per material (the published form hoists what reads only them): costs per pixel.
        if c.get("uniform"):
            cmd += ["--uniform", ",".join(c["uniform"])]
        run = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        best = None
        used_ops = None
        symmetry = None
        if run.returncode == 0:
            with open(out_json, encoding="utf-8") as f:
                doc = json.load(f)
            front = doc["front"]
            # The operators the search used (auto resolved), enumeration | evolution.
            used_ops = doc["options"]["operators"] + " | " + doc["options"]["evolution_operators"]
            # The symmetry the search folded the data by, and how it was found (older JSON: no
            # method).
            sy = doc["summary"].get("symmetry")
            if sy:
                symmetry = sy["kind"] + " (" + sy.get("method", "mirrored_pairs") + ")"
            # The front member with the least max |err| among those no costlier than published.
            for m in front:
                if m["cost"] <= c["cost"] and (best is None or m["max_abs"] < best["max_abs"]):
                    best = m
        else:
            print(f"run.py: search failed on {c['name']}: {run.stderr.strip()}", file=sys.stderr)
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
        print(f"{c['name']}: published {c['max_abs']:.3g} at {c['cost']:g}, ours "
              f"{best['max_abs']:.3g} at {best['cost']:g}" if best else f"{c['name']}: none",
              file=sys.stderr)

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
                 f"--time {args.time:g} --threads {args.threads} --seed {SEED} "
                 f"--ops {OPS} --evolve-ops {EVOLVE_OPS}.")
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
