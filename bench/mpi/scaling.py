#!/usr/bin/env python3
"""One search across MPI ranks against one process, side by side in one run (docs/distributed.md,
"Measured"): 2 ranks x 1 thread against 1 rank x 1 thread, interleaved (A B A B ...), medians of
--reps seeds.

  candidates/s      a --time T search (enumeration, then evolution): summary candidates / total
                    time, on the seed task and on the four-input problem below. The count is
                    almost all the enumeration's, in its share of the time (a tenth), and the
                    enumeration stores each new class (about 370 bytes). Where the machine gives
                    a process fresh memory slowly (a virtual machine that hands freed pages back
                    to its host: 2 to 4 ms per MB on the 2-core machine), much of that share is
                    spent in the kernel: the row "kernel s" is the searches' system time (all
                    ranks), from getrusage. Each run starts after --settle seconds idle, so that
                    both sides find the memory alike (pages a run frees stay the guest's for a
                    few seconds).
  evolution cand/s  the same with --strategy evolve (the islands' part)
  time to target    the four-input problem, I.34.8 of AI-Feynman (omega = q v B / p, 2,000 rows
                    drawn as bench/feynman/run.py draws them), --time 60 with --stop-loss 20.5
                    --stop-cost 3 (an MSE a fifth of the target's variance, at 3 instructions):
                    the search's total_time_s
  equal work        count-budgeted searches (--evals N) of both on the four-input problem: their
                    candidates/s, and at each cost of the one-rank front the 2-rank front's best
                    loss at that cost or below, as a ratio
  bytes             summary bytes_per_rank (sent, received) per synchronisation of the evolution
                    (--strategy evolve, 2 islands per rank, every 10 generations) on 2 and 4 ranks
                    (4 oversubscribed on a 2-core machine, for twice the time)

    python3 bench/mpi/scaling.py --build build/release --time 10 --reps 3
"""

import argparse
import csv
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "bench" / "feynman"))

SEED_TASK = ["--dataset", "fresnel-seed", "--inputs", "r0,x", "--target", "R"]
TARGET = ["--stop-loss", "20.5", "--stop-cost", "3"]
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_btl_vader_single_copy_mechanism="none")


def four_input_problem(work: Path) -> list:
    import run as feynman  # bench/feynman/run.py
    eq = {e["number"]: e for e in feynman.load_equations(feynman.DEFAULT_EQUATIONS)}[34]
    columns, y = feynman.draw(eq, np.random.default_rng(1000 + 34), 2000, 0.0)
    path = work / "feynman_34.csv"
    names = list(columns.keys())
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(names + [eq["output"]])
        for i in range(len(y)):
            w.writerow([repr(float(columns[k][i])) for k in names] + [repr(float(y[i]))])
    return ["--data", str(path), "--target", eq["output"]]


def summary(build, ranks, problem, extra, kernel=None):
    common = ["search"] + problem + ["--threads", "1", "--quiet", "--json", "-"] + extra
    if ranks == 1:
        cmd = [f"{build}/shaderfit"] + common
    else:
        cmd = (["mpirun", "--oversubscribe", "-np", str(ranks), f"{build}/shaderfit-mpi"] +
               common)
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_stime
    out = subprocess.run(cmd, capture_output=True, text=True, check=True, env=ENV)
    if kernel is not None:
        kernel.append(resource.getrusage(resource.RUSAGE_CHILDREN).ru_stime - before)
    return json.loads(out.stdout)


def best_at(front, cost):
    losses = [m["loss"] for m in front if m["cost"] <= cost]
    return min(losses) if losses else float("inf")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default="build/release")
    ap.add_argument("--time", type=float, default=10.0)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--evals", type=int, default=3_000_000, help="the equal-work budget")
    ap.add_argument("--settle", type=float, default=10.0,
                    help="seconds idle before each time-limited run")
    ap.add_argument("--only-rate", action="store_true",
                    help="only the candidates/s rows of time-limited searches")
    args = ap.parse_args()
    med = statistics.median
    t = ["--time", repr(args.time)]
    with tempfile.TemporaryDirectory() as tmp:
        four = four_input_problem(Path(tmp))
        keys = ("cps_seed", "sys_seed", "cps_four", "sys_four", "evo", "ttt", "cps_work")
        rows = {r: {k: [] for k in keys} for r in (1, 2)}
        ratios = []
        for rep in range(args.reps):
            seed = ["--seed", str(rep + 1)]
            runs = {}
            for ranks in (1, 2):  # interleaved
                for problem, rate, kernel in ((SEED_TASK, "cps_seed", "sys_seed"),
                                              (four, "cps_four", "sys_four")):
                    time.sleep(args.settle)
                    s = summary(args.build, ranks, problem, t + seed, rows[ranks][kernel])
                    rows[ranks][rate].append(s["summary"]["candidates"] /
                                             s["summary"]["total_time_s"])
                if args.only_rate:
                    continue
                s = summary(args.build, ranks, SEED_TASK, t + seed + ["--strategy", "evolve"])
                s = s["summary"]
                rows[ranks]["evo"].append(s["candidates"] / s["evolution_time_s"])
                s = summary(args.build, ranks, four, ["--time", "60"] + seed + TARGET)["summary"]
                assert s["termination"] == "target reached", s
                rows[ranks]["ttt"].append(s["total_time_s"])
                runs[ranks] = summary(args.build, ranks, four,
                                      ["--time", "600", "--evals", str(args.evals)] + seed)
                s = runs[ranks]["summary"]
                rows[ranks]["cps_work"].append(s["candidates"] / s["total_time_s"])
            for m in runs[1]["front"] if runs else []:
                ratios.append(best_at(runs[2]["front"], m["cost"]) / max(m["loss"], 1e-300))
        print(f"{args.reps} seeds, interleaved; medians, 2 ranks x 1 thread against 1 rank x 1 "
              f"thread (ratio 2 / 1):")
        kernel = "  kernel s (system time of the search, all ranks)"
        for key, name, unit in (("cps_seed", f"candidates/s, seed task, --time {args.time:g}", ""),
                                ("sys_seed", kernel, " s"),
                                ("cps_four", f"candidates/s, I.34.8, --time {args.time:g}", ""),
                                ("sys_four", kernel, " s"),
                                ("evo", "evolution cand/s, seed task (--strategy evolve)", ""),
                                ("ttt", "time to target, I.34.8 (mse <= 20.5 at cost <= 3)", " s"),
                                ("cps_work", f"candidates/s, I.34.8, --evals {args.evals}", "")):
            if not rows[1][key]:
                continue
            a, b = med(rows[1][key]), med(rows[2][key])
            print(f"  {name:<52} {a:12.4g}{unit} {b:12.4g}{unit}  ratio {b / a:5.2f}")
        if args.only_rate:
            return
        worse = [r for r in ratios if r > 1 + 1e-9]
        print(f"  equal work (--evals {args.evals}, I.34.8): at {len(ratios) - len(worse)} of "
              f"{len(ratios)} costs of the one-rank fronts the 2-rank front is as good or better; "
              f"worst ratio {max(ratios):.3g}, median {med(ratios):.3g}")
        print("  bytes per synchronisation of the evolution (--strategy evolve, 2 islands per "
              "rank), sent / received:")
        for ranks in (2, 4):
            islands = ["--islands", str(2 * ranks)]
            # As many generations per rank whatever the number of ranks on the machine's cores.
            longer = ["--time", repr(args.time * max(1, ranks / (os.cpu_count() or 1)))]
            s = summary(args.build, ranks, SEED_TASK,
                        longer + ["--seed", "1", "--strategy", "evolve"] + islands)["summary"]
            syncs = max(1, s["generations"] // 10)
            per = s["bytes_per_rank"]
            others = per[1:]
            print(f"    {ranks} ranks ({syncs} synchronisations): each other rank "
                  f"{med(p[0] for p in others) / syncs:.0f} / {med(p[1] for p in others) / syncs:.0f}"
                  f" (median), rank 0 {per[0][0] / syncs:.0f} / {per[0][1] / syncs:.0f}")


if __name__ == "__main__":
    main()
