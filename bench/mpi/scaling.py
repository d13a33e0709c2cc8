#!/usr/bin/env python3
"""Searches across MPI ranks against one process, measured side by side in one run
(docs/distributed.md): 1 rank x 1 thread, 1 rank x 2 threads and 2 ranks x 1 thread, interleaved
(A B C A B C ...) on the seed task.

For each configuration, medians over --reps runs of:
  candidates/s      a --time T search (enumeration, then evolution): summary candidates / total
  evolution cand/s  a --time T search with --strategy evolve: the part the ranks share out
  time to target    --stop-loss <seed formula's MSE> --stop-cost 4: the search's total_time_s
and for 2 ranks the bytes every rank sent per generation (summary bytes_sent / ranks /
generations), with the ratios to 1 rank x 1 thread.

    python3 bench/mpi/scaling.py --build build/release --time 10 --reps 3
"""

import argparse
import json
import os
import statistics
import subprocess

SEED_MSE = 3.5226917573287524e-4  # r0 + (x - r0) x^4 on fresnel-seed, data seed 1
SEARCH = ["search", "--dataset", "fresnel-seed", "--inputs", "r0,x", "--target", "R", "--quiet",
          "--json", "-"]


def command(build, ranks, threads, extra):
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_btl_vader_single_copy_mechanism="none")
    if ranks == 1:
        return [f"{build}/shaderfit"] + SEARCH + ["--threads", str(threads)] + extra, env
    return (["mpirun", "-np", str(ranks), f"{build}/shaderfit-mpi"] + SEARCH +
            ["--threads", str(threads)] + extra, env)


def summary(build, ranks, threads, extra):
    cmd, env = command(build, ranks, threads, extra)
    out = subprocess.run(cmd, capture_output=True, text=True, check=True, env=env)
    return json.loads(out.stdout)["summary"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default="build/release")
    ap.add_argument("--time", type=float, default=10.0)
    ap.add_argument("--reps", type=int, default=3)
    args = ap.parse_args()
    configs = [("1 rank x 1 thread", 1, 1), ("1 rank x 2 threads", 1, 2),
               ("2 ranks x 1 thread", 2, 1)]
    t = ["--time", repr(args.time)]
    rows = {name: {"cps": [], "evo": [], "ttt": [], "bytes": []} for name, _, _ in configs}
    for rep in range(args.reps):
        for name, ranks, threads in configs:
            s = summary(args.build, ranks, threads, t + ["--seed", str(rep + 1)])
            rows[name]["cps"].append(s["candidates"] / s["total_time_s"])
            if s["generations"] > 0:
                rows[name]["bytes"].append(s["bytes_sent"] / s["ranks"] / s["generations"])
            s = summary(args.build, ranks, threads,
                        t + ["--seed", str(rep + 1), "--strategy", "evolve"])
            rows[name]["evo"].append(s["candidates"] / s["evolution_time_s"])
            s = summary(args.build, ranks, threads,
                        ["--time", "30", "--seed", str(rep + 1), "--stop-loss", repr(SEED_MSE),
                         "--stop-cost", "4"])
            assert s["termination"] == "target reached", s
            rows[name]["ttt"].append(s["total_time_s"])
    med = statistics.median
    base = rows[configs[0][0]]
    print(f"seed task, {args.reps} runs per configuration (seeds 1-{args.reps}), --time "
          f"{args.time:g}, interleaved; medians, and ratios to 1 rank x 1 thread:")
    print(f"  {'':<20} {'candidates/s':>14} {'ratio':>6} {'evolution cand/s':>17} {'ratio':>6} "
          f"{'time to target':>15} {'ratio':>6}")
    for name, _, _ in configs:
        r = rows[name]
        print(f"  {name:<20} {med(r['cps']):14.4g} {med(r['cps']) / med(base['cps']):6.2f} "
              f"{med(r['evo']):17.4g} {med(r['evo']) / med(base['evo']):6.2f} "
              f"{med(r['ttt']) * 1e3:12.2f} ms {med(r['ttt']) / med(base['ttt']):6.2f}")
    b = rows["2 ranks x 1 thread"]["bytes"]
    if b:
        print(f"  2 ranks: {med(b):.0f} bytes sent per rank per generation (median of runs)")


if __name__ == "__main__":
    main()
