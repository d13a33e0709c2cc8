#!/usr/bin/env python3
"""A batch across MPI ranks against one rank, measured side by side in one run (docs/batch.md):
`mpirun -np 1` and `mpirun -np N` of `shaderfit-mpi batch` on one count-budgeted manifest of
eight functions, interleaved (1 N 1 N ...), each rank searching one function at a time. Prints
the median wall times, their ratio, and whether every run chose the same formulas.

    python3 bench/mpi/batch.py --build build/release --ranks 2 --reps 3
"""

import argparse
import json
import os
import shutil
import statistics
import subprocess
import tempfile
import time

FUNCTIONS = [("f_tanh", "tanh(x)", "0.0, 4.0"), ("f_exp", "exp(x)", "0.0, 1.0"),
             ("f_sin", "sin(x)", "0.0, 1.5"), ("f_sqrt", "sqrt(x)", "0.1, 1.0"),
             ("f_log", "log(x + 1)", "0.0, 1.0"), ("f_inv", "1 / (1 + x)", "0.0, 1.0"),
             ("f_cos", "cos(x)", "0.0, 1.5"), ("f_atan", "atan(x)", "0.0, 1.0")]


def manifest(evals):
    text = (f"[defaults]\ntime = 600\nevals = {evals}\nseed = 2\nloss = \"max_abs\"\n"
            "samples = 2000\n")
    for name, reference, domain in FUNCTIONS:
        text += (f"\n[[function]]\nname = \"{name}\"\nreference = \"{reference}\"\n"
                 f"domain = {{ x = [{domain}] }}\n")
    return text


def run(build, ranks, path, out):
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_btl_vader_single_copy_mechanism="none",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    shutil.rmtree(out, ignore_errors=True)
    t0 = time.monotonic()
    subprocess.run(["mpirun", "-np", str(ranks), f"{build}/shaderfit-mpi", "batch", path,
                    "--out", out, "--quiet"], check=True, env=env, stdout=subprocess.DEVNULL)
    seconds = time.monotonic() - t0
    with open(os.path.join(out, "batch.json"), encoding="utf-8") as f:
        doc = json.load(f)
    chosen = {e["name"]: e["run"]["front"][e["chosen"]]["formula"] for e in doc["entries"]}
    return seconds, chosen


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default="build/release")
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--evals", type=int, default=2500000, help="candidates per function")
    args = ap.parse_args()
    work = tempfile.mkdtemp(prefix="shaderfit_mpi_batch_")
    path = os.path.join(work, "m.toml")
    with open(path, "w", encoding="utf-8") as f:
        f.write(manifest(args.evals))
    times = {1: [], args.ranks: []}
    results = []
    for _ in range(args.reps):
        for ranks in (1, args.ranks):
            seconds, chosen = run(args.build, ranks, path, os.path.join(work, f"out{ranks}"))
            times[ranks].append(seconds)
            results.append(chosen)
    one, many = statistics.median(times[1]), statistics.median(times[args.ranks])
    print(f"1 rank: median {one:.2f} s of {times[1]}")
    print(f"{args.ranks} ranks: median {many:.2f} s of {times[args.ranks]}")
    print(f"ratio {args.ranks} ranks / 1 rank: {many / one:.2f}")
    print("same chosen formulas in every run:", all(r == results[0] for r in results))
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
