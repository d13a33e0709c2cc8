#!/usr/bin/env python3
"""The Python layer's overhead, measured side by side in one run (docs/python.md).

1. Time to target on the seed task: shaderfit.search(...) with stop_at=(seed formula's MSE, 4)
   against `shaderfit search ... --stop-loss MSE --stop-cost 4` on the same data seed, the two
   interleaved (A B A B ...) so that both see the same machine. Reported: the median wall time of
   the Python call (data already in numpy) and of the CLI process (start, data generation,
   search, JSON), and the median of the search's own total_time_s in each; ratios Python / CLI.
2. Memory: the peak resident set during a search on an N x k X (float64 in C and Fortran order,
   float32) minus the resident set before the call, each in a fresh process, against the same
   search run by the library on data already in its columns (bench/search_memory): the
   difference is what the Python layer costs, in units of X's float64 copy.

    PYTHONPATH=build/release/python python3 bench/python/overhead.py --cli build/release/shaderfit
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import time

SEED_FORMULA = "r0 + (x - r0)*x^4"


def seed_mse(shaderfit, data):
    import numpy as np

    p = shaderfit.evaluate(SEED_FORMULA, data.X, inputs=data.inputs)
    return float(np.mean((p - data.y) ** 2))


def time_to_target(args):
    import shaderfit

    py_wall, py_search, cli_wall, cli_search = [], [], [], []
    for rep in range(args.reps):
        seed = 1 + rep % 10
        data = shaderfit.datasets.fresnel_seed(seed=seed)
        mse = seed_mse(shaderfit, data)
        # Python: the call, data already in numpy.
        t0 = time.perf_counter()
        front = shaderfit.search(data.X, data.y, inputs=data.inputs, time=20, seed=1,
                                 threads=args.threads, stop_at=(mse, 4), progress=False)
        py_wall.append(time.perf_counter() - t0)
        py_search.append(front.summary["total_time_s"])
        assert front.termination == "target reached", front
        # CLI: the whole process.
        cmd = [args.cli, "search", "--dataset", "fresnel-seed", "--data-seed", str(seed),
               "--inputs", "r0,x", "--target", "R", "--time", "20", "--seed", "1",
               "--threads", str(args.threads), "--stop-loss", repr(mse), "--stop-cost", "4",
               "--quiet", "--json", "-"]
        t0 = time.perf_counter()
        out = subprocess.run(cmd, capture_output=True, text=True, check=True)
        cli_wall.append(time.perf_counter() - t0)
        doc = json.loads(out.stdout)
        cli_search.append(doc["summary"]["total_time_s"])
        assert doc["summary"]["termination"] == "target reached"
    med = statistics.median
    print(f"time to target, seed task (data seeds 1-10), {args.reps} runs each, "
          f"{args.threads} threads, interleaved:")
    print(f"  wall:   python call {med(py_wall) * 1e3:8.2f} ms   cli process "
          f"{med(cli_wall) * 1e3:8.2f} ms   ratio {med(py_wall) / med(cli_wall):.3f}")
    print(f"  search: python      {med(py_search) * 1e3:8.2f} ms   cli         "
          f"{med(cli_search) * 1e3:8.2f} ms   ratio {med(py_search) / med(cli_search):.3f}")
    pairs = [a / b for a, b in zip(py_search, cli_search)]
    print(f"  median of the paired search-time ratios: {med(pairs):.3f}")


def status_mib(field):
    """A field of /proc/self/status in MiB ("VmRSS", "VmHWM")."""
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(field + ":"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


def memory_case(layout, rows, inputs):
    """Runs in a child process: prints one JSON line."""
    import numpy as np

    import shaderfit

    rng = np.random.default_rng(1)
    dtype = np.float32 if layout == "f32" else np.float64
    X = np.empty((rows, inputs), dtype=dtype, order="F" if layout == "F" else "C")
    for j in range(inputs):
        X[:, j] = rng.uniform(0.0, 1.0, size=rows)
    y = X[:, 0] * X[:, 1] + X[:, 2]
    x_mb = rows * inputs * 8 / 2**20  # the float64 copy the search holds
    with open("/proc/self/clear_refs", "w") as f:
        f.write("5")  # VmHWM := VmRSS, so that the peak is the search's
    before = status_mib("VmRSS")
    # The smallest search: the enumeration's first levels on a small evaluation budget, so that
    # the peak is the data the search holds, not its work.
    shaderfit.search(X, y, time=60, threads=1, max_candidates=200, evolve=False,
                     max_enumeration_cost=1, progress=False)
    print(json.dumps({"layout": layout, "x_mb": x_mb, "before_mb": before,
                      "peak_mb": status_mib("VmHWM")}))


def memory(args):
    x_mb = args.rows * args.inputs * 8 / 2**20
    y_mb = args.rows * 8 / 2**20
    ref = subprocess.run([args.memory_reference, str(args.rows), str(args.inputs)],
                         capture_output=True, text=True, check=True)
    r = json.loads(ref.stdout)
    library = r["peak_mib"] - r["before_mib"]
    print(f"peak memory of a search on {args.rows:,} x {args.inputs} X "
          f"(its float64 copy: {x_mb:.1f} MiB; y's: {y_mb:.1f} MiB), peak - before:")
    print(f"  library alone (bench/search_memory, data already its columns): {library:7.1f} MiB")
    for layout in ("C", "F", "f32"):
        out = subprocess.run([sys.executable, __file__, "--memory-case", layout, "--rows",
                              str(args.rows), "--inputs", str(args.inputs)],
                             capture_output=True, text=True, check=True, env=os.environ)
        r = json.loads(out.stdout.strip().splitlines()[-1])
        extra = r["peak_mb"] - r["before_mb"]
        over = extra - library
        print(f"  python, X {layout:>3} order{'' if layout != 'f32' else ' (float32)'}: "
              f"{extra:7.1f} MiB; more than the library alone: {over:6.1f} MiB = "
              f"{over / x_mb:.2f} x X's copy ({(over - y_mb) / x_mb:.2f} x without y's)")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cli", default="build/release/shaderfit")
    ap.add_argument("--reps", type=int, default=30)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--rows", type=int, default=1_000_000)
    ap.add_argument("--inputs", type=int, default=4)
    ap.add_argument("--memory-case", choices=["C", "F", "f32"])
    ap.add_argument("--memory-reference", default="build/release/bench/search_memory")
    ap.add_argument("--only", choices=["time", "memory"])
    args = ap.parse_args()
    if args.memory_case:
        memory_case(args.memory_case, args.rows, args.inputs)
        return
    if args.only != "memory":
        time_to_target(args)
    if args.only != "time":
        memory(args)


if __name__ == "__main__":
    main()
