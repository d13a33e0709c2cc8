#!/usr/bin/env python3
"""A batch stopped by Ctrl-C and run again against one run uninterrupted (docs/batch.md,
"Resuming"): on bench/mpi/batch.py's count-budgeted manifest of eight functions, runs
`shaderfit batch` to the end, then again from scratch with SIGINT (what Ctrl-C sends) after
--stop-after seconds, then the same command once more. Prints the three wall times, the entries
read back, and whether the resumed result (every front, every chosen formula) equals the
uninterrupted one.

    python3 bench/batch_resume.py --build build/release --evals 1500000 --stop-after 3
"""

import argparse
import importlib.util
import json
import os
import shutil
import signal
import subprocess
import tempfile
import time


def mpi_batch_bench():
    """bench/mpi/batch.py, whose manifest this reuses."""
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "mpi", "batch.py")
    spec = importlib.util.spec_from_file_location("mpi_batch_bench", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def batch(build, manifest, out, parallel, stop_after=None):
    """Runs the batch; returns (seconds, its stdout)."""
    cmd = [f"{build}/shaderfit", "batch", manifest, "--out", out, "--parallel", str(parallel)]
    t0 = time.monotonic()
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if stop_after is not None:
        try:
            p.wait(timeout=stop_after)
        except subprocess.TimeoutExpired:
            p.send_signal(signal.SIGINT)
    output, _ = p.communicate()
    return time.monotonic() - t0, output


def result(out):
    """Every entry's front (formulas and losses) and chosen formula, by name."""
    with open(os.path.join(out, "batch.json"), encoding="utf-8") as f:
        doc = json.load(f)
    return {e["name"]: ([(m["formula"], m["loss"]) for m in e["run"]["front"]],
                        e["run"]["front"][e["chosen"]]["formula"]) for e in doc["entries"]}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default="build/release")
    ap.add_argument("--evals", type=int, default=1500000, help="candidates per function")
    ap.add_argument("--stop-after", type=float, default=3.0, help="seconds before the Ctrl-C")
    ap.add_argument("--parallel", type=int, default=2)
    args = ap.parse_args()
    work = tempfile.mkdtemp(prefix="shaderfit_batch_resume_")
    manifest = os.path.join(work, "m.toml")
    with open(manifest, "w", encoding="utf-8") as f:
        f.write(mpi_batch_bench().manifest(args.evals))
    whole, resumed = os.path.join(work, "whole"), os.path.join(work, "resumed")

    t_whole, _ = batch(args.build, manifest, whole, args.parallel)
    t_stopped, out_stopped = batch(args.build, manifest, resumed, args.parallel, args.stop_after)
    entries = os.path.join(resumed, "entries")
    done = len(os.listdir(entries)) if os.path.isdir(entries) else 0
    t_again, out_again = batch(args.build, manifest, resumed, args.parallel)

    print(f"uninterrupted: {t_whole:.2f} s")
    print(f"Ctrl-C after {args.stop_after:g} s: stopped at {t_stopped:.2f} s, "
          f"{done} of 8 entries finished")
    print(f"run again: {t_again:.2f} s")
    for line in out_again.splitlines():
        print("  " + line)
    print("resumed result equals the uninterrupted one:", result(resumed) == result(whole))
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
