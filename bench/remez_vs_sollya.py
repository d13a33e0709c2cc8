#!/usr/bin/env python3
"""Polynomial minimax: shaderfit's Remez exchange against Sollya's remez, in one run.

For exp2 on [0, 1], log2 on [1, 2] and atan on [-1, 1], degrees 3 to 7, it asks
`shaderfit rational --minimax` for the best polynomial, then runs one Sollya script that computes
Sollya's own `remez` polynomial and measures both errors the same way (dirtyinfnorm at 200 bits),
and prints a table. Needs the Debian package sollya (scripts/install-deps installs it); the tests
never do.

  bench/remez_vs_sollya.py [path/to/shaderfit]     (default: build/release/shaderfit)
"""
import json
import os
import re
import shutil
import subprocess
import sys
import time

CASES = [  # shaderfit target, Sollya expression, domain
    ("exp2", "2^x", (0, 1)),
    ("log2", "log2(x)", (1, 2)),
    ("atan", "atan(x)", (-1, 1)),
]
DEGREES = range(3, 8)


def shaderfit_minimax(binary, target, domain, degree):
    out = subprocess.run(
        [binary, "rational", "--target", target, "--domain", f"{domain[0]},{domain[1]}",
         "--form", f"{degree}/0", "--minimax", "--json", "-"],
        check=True, capture_output=True, text=True).stdout
    result = json.loads(out)["runs"][0]["results"][0]
    return result["numerator"], result["minimax"]


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    binary = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "build", "release", "shaderfit")
    if not os.path.exists(binary):
        sys.exit(f"no shaderfit binary at {binary}: build first (scripts/build)")
    if shutil.which("sollya") is None:
        sys.exit("sollya is not installed (apt-get install sollya, or scripts/install-deps)")

    rows, script = [], ["prec = 200!;", "display = decimal!;"]
    started = time.perf_counter()
    for target, expr, (lo, hi) in CASES:
        for d in DEGREES:
            coefficients, minimax = shaderfit_minimax(binary, target, (lo, hi), d)
            ours = " + ".join(f"({c!r}) * x^{i}" for i, c in enumerate(coefficients))
            dom = f"[{lo};{hi}]"
            script += [f"p = remez({expr}, {d}, {dom});",
                       f'write("ROW {target} {d} ", dirtyinfnorm({expr} - p, {dom}), " ",'
                       f' dirtyinfnorm({expr} - ({ours}), {dom}), "\\n");']
            rows.append((target, (lo, hi), d, minimax))
    shaderfit_s = time.perf_counter() - started
    started = time.perf_counter()
    text = subprocess.run(["sollya"], input="\n".join(script) + "\nquit;\n", check=True,
                          capture_output=True, text=True).stdout
    sollya_s = time.perf_counter() - started
    measured = {(m[0], int(m[1])): (float(m[2]), float(m[3]))
                for m in re.findall(r"ROW (\w+) (\d+) (\S+) (\S+)", text)}

    print(f"{'function':<8} {'domain':<8} {'deg':>3} {'Sollya remez':>13} {'shaderfit':>13} "
          f"{'ratio':>8} {'spread':>9}  within 1%")
    worst = 0.0
    for target, (lo, hi), d, minimax in rows:
        sollya_err, ours_err = measured[(target, d)]
        ratio = ours_err / sollya_err
        worst = max(worst, ratio)
        print(f"{target:<8} [{lo},{hi}]{'':<{max(0, 4 - len(str(lo)) - len(str(hi)))}} {d:>3} "
              f"{sollya_err:>13.6e} {ours_err:>13.6e} {ratio:>8.5f} {minimax['spread']:>9.1e}  "
              f"{'yes' if ratio <= 1.01 else 'NO'}")
    print(f"errors: max |f - p| on the domain, both measured by Sollya's dirtyinfnorm at 200 bits; "
          f"ratio = shaderfit / Sollya (worst {worst:.5f}); spread = relative spread of |error| at "
          f"shaderfit's alternation points")
    print(f"time: shaderfit {shaderfit_s:.2f} s for {len(rows)} fits (process start included), "
          f"Sollya {sollya_s:.2f} s")
    return 0 if worst <= 1.01 else 1


if __name__ == "__main__":
    sys.exit(main())
