#!/usr/bin/env python3
"""Real shading code: shaderfit's search on the functions of bench/shaders/, checked in numpy.

    python3 bench/shaders/run.py --shaderfit build/release/shaderfit --time 20 --jobs 2 \\
        --out build/shaders --markdown build/shaders/table.md

For each function of functions.toml (a GLSL or HLSL function, its domain, its per-material
inputs and its numpy implementation in numpy_refs.py) and each mode (`default`; `uniform`:
`--uniform` with the manifest's per-material inputs, skipped where there are none):

1. Own cost: `shaderfit cost --reference-file F --function N --json -` (`--uniform ...` in
   uniform mode), the `sass` target's instructions (per pixel with --uniform). Where the function
   cannot be written in the search's operators (floor, tan, ...) it "does not lower": the reason
   is kept and the cost columns are "-".
2. Checks that the numpy implementation is the shader: the formula `cost` prints (the shader
   lowered) is evaluated in numpy on --points random points and must agree with the numpy
   reference to a relative RMS of 1e-6 (of the reference's standard deviation); and, for every
   function, lowering or not, `shaderfit eval` gives the shader's own values on a regular grid
   (grouped by a point index, formulas 0 and -B: |f| and its sign), which must agree with numpy
   to 1e-6 of the standard deviation at every grid point. A failure prints FAIL.
3. Search: `shaderfit search --reference-file F --function N --domain ... --time T --threads 1
   --seed S --quiet --json OUT/NAME.MODE.json` (+ `--uniform ...`), default settings otherwise.
4. Every front member's `formula` is evaluated in numpy (float64) on the points: rel_rms =
   RMS(member - reference) / std(reference). Reported: `itself`, some member with cost <= the own
   cost C and rel_rms <= 1e-6; the least rel_rms among members with cost <= floor(0.75 C) and
   <= floor(0.5 C); the least overall; the search's generations and sample rows. Then the medians
   over functions of the two rel_rms columns and the count of `itself`.

numpy only (scipy's erf where installed, else math.erf); nothing is downloaded. The tables go
to stdout and to --markdown; every search's JSON and results.json to --out.
"""

import argparse
import concurrent.futures
import json
import math
import os
import re
import statistics
import subprocess
import sys
import time
import tomllib

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
import numpy_refs  # noqa: E402

CHECK_TOL = 1e-6      # lowered formula and grid values against numpy, relative to std
ITSELF_TOL = 1e-6     # "the front holds the function"

try:
    from scipy.special import erf as _erf  # type: ignore
except ImportError:  # pragma: no cover
    _erf = np.vectorize(math.erf, otypes=[float])


# --- formulas in numpy -------------------------------------------------------------------------
# The grammar of shaderfit's formulas (include/shaderfit/expr/parse.hpp, grammar.hpp): + - * /
# left-associative, unary signs, `^` binding tighter than a sign and grouping from the left
# (-x^2 = -(x^2), x^2^3 = (x^2)^3), a '-' right before a number literal that is not the base of
# '^' a negative literal, calls, `pi`, and select(X cmp Y, b, c) with cmp one of >= > <= <.
# Meanings as include/shaderfit/expr/op.hpp: pow(a, b) = exp2(b log2 a) (NaN for a < 0) unless b
# is an integer literal (then the exact power), min/max are fmin/fmax, saturate keeps a NaN,
# sign(+-0) = 0, select(a, b, c) = a >= 0 ? b : c (NaN takes c), rsqrt = 1/sqrt, rcp = 1/x.

_TOKEN = re.compile(r"\s*(?:(?P<num>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)|(?P<name>[A-Za-z_]\w*)"
                    r"|(?P<sym>>=|<=|[-+*/^(),<>]))")


def _tokenize(text):
    pos, out = 0, []
    text = text.strip()
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if not m or m.end() == pos:
            raise ValueError(f"cannot read formula at {pos}: {text[pos:pos + 20]!r}")
        pos = m.end()
        if m.group("num") is not None:
            out.append(("num", m.group("num")))
        elif m.group("name") is not None:
            out.append(("name", m.group("name")))
        else:
            out.append(("sym", m.group("sym")))
    out.append(("end", ""))
    return out


def _sat(a):
    return np.where(a < 0, 0.0, np.where(a > 1, 1.0, a))


def _pow(a, b):
    return np.exp2(b * np.log2(a))


def _sign(a):
    return np.where(a > 0, 1.0, np.where(a < 0, -1.0, a * 0.0))


_FUNCS = {
    "sqrt": (1, np.sqrt), "rsqrt": (1, lambda a: 1.0 / np.sqrt(a)),
    "inversesqrt": (1, lambda a: 1.0 / np.sqrt(a)), "rcp": (1, lambda a: 1.0 / a),
    "exp2": (1, np.exp2), "log2": (1, np.log2), "exp": (1, np.exp), "log": (1, np.log),
    "abs": (1, np.abs), "saturate": (1, _sat), "sin": (1, np.sin), "cos": (1, np.cos),
    "sign": (1, _sign), "asin": (1, np.arcsin), "acos": (1, np.arccos), "atan": (1, np.arctan),
    "tanh": (1, np.tanh), "erf": (1, lambda a: _erf(a)),
    "min": (2, np.fmin), "max": (2, np.fmax), "pow": (2, _pow), "copysign": (2, np.copysign),
    "atan2": (2, np.arctan2), "fma": (3, lambda a, b, c: a * b + c),
}


class _Parser:
    def __init__(self, text):
        self.text = text
        self.toks = _tokenize(text)
        self.i = 0

    def peek(self, k=0):
        return self.toks[min(self.i + k, len(self.toks) - 1)]

    def next(self):
        t = self.toks[self.i]
        self.i += 1
        return t

    def accept(self, sym):
        if self.peek() == ("sym", sym):
            self.i += 1
            return True
        return False

    def expect(self, sym):
        if not self.accept(sym):
            raise ValueError(f"expected {sym!r} in {self.text!r}, found {self.peek()[1]!r}")

    def parse(self):
        f = self.binary()
        if self.peek()[0] != "end":
            raise ValueError(f"unexpected {self.peek()[1]!r} in {self.text!r}")
        return f

    PREC = {"+": 1, "-": 1, "*": 2, "/": 2}

    def binary(self, min_prec=1):
        lhs = self.unary()
        while True:
            kind, text = self.peek()
            p = self.PREC.get(text, 0) if kind == "sym" else 0
            if p == 0 or p < min_prec:
                return lhs
            self.next()
            rhs = self.binary(p + 1)
            lhs = self._bin(text, lhs, rhs)

    @staticmethod
    def _bin(op, a, b):
        if op == "+":
            return lambda env: a(env) + b(env)
        if op == "-":
            return lambda env: a(env) - b(env)
        if op == "*":
            return lambda env: a(env) * b(env)
        return lambda env: a(env) / b(env)

    def unary(self):
        if self.accept("-"):
            if self.peek()[0] == "num" and self.peek(1) != ("sym", "^"):
                v = -float(self.next()[1])
                return lambda env: v
            f = self.unary()
            return lambda env: -f(env)
        if self.accept("+"):
            return self.unary()
        return self.power()

    def power(self):
        base = self.primary()
        while self.accept("^"):
            sign = 1.0
            if self.peek() in (("sym", "-"), ("sym", "+")):
                sign = -1.0 if self.next()[1] == "-" else 1.0
            if self.peek()[0] == "num":
                k = sign * float(self.next()[1])
                base = self._ipow(base, k) if k == int(k) else (lambda b, k: lambda env: _pow(b(env), k))(base, k)
            else:  # the reference language's real exponent: C's pow
                e = self.primary()
                base = (lambda b, e, s: lambda env: np.power(b(env), s * e(env)))(base, e, sign)
        return base

    @staticmethod
    def _ipow(f, k):
        return lambda env: np.power(f(env), float(k))

    def primary(self):
        kind, text = self.next()
        if kind == "num":
            v = float(text)
            return lambda env: v
        if kind == "sym" and text == "(":
            f = self.binary()
            self.expect(")")
            return f
        if kind != "name":
            raise ValueError(f"unexpected {text!r} in {self.text!r}")
        if self.peek() != ("sym", "("):
            if text == "pi":
                return lambda env: math.pi
            return lambda env, n=text: env[n]
        self.next()  # '('
        if text == "select":
            return self.select()
        if text not in _FUNCS:
            raise ValueError(f"unknown function {text!r} in {self.text!r}")
        arity, fn = _FUNCS[text]
        args, arg_texts = [], []
        while True:
            start = self.i
            args.append(self.binary())
            arg_texts.append(self.toks[start:self.i])
            if self.accept(","):
                continue
            self.expect(")")
            break
        if text == "atan" and len(args) == 2:
            arity, fn = _FUNCS["atan2"]
        if len(args) != arity:
            raise ValueError(f"{text} takes {arity} arguments in {self.text!r}")
        if text == "pow":
            toks = arg_texts[1]
            lit = "".join(t[1] for t in toks)
            if re.fullmatch(r"-?\d+", lit) and -16 <= int(lit) <= 16 and int(lit) not in (0, 1):
                return self._ipow(args[0], int(lit))
        return (lambda fn, args: lambda env: fn(*[a(env) for a in args]))(fn, args)

    def select(self):
        x = self.binary()
        kind, cmp = self.next()
        if kind != "sym" or cmp not in (">=", "<=", ">", "<"):
            raise ValueError(f"select's first argument must be a comparison in {self.text!r}")
        y = self.binary()
        self.expect(",")
        b = self.binary()
        self.expect(",")
        c = self.binary()
        self.expect(")")
        # As shaderfit's parser: the condition becomes a difference tested >= 0.
        if cmp == ">=":
            return lambda env: np.where(x(env) - y(env) >= 0, b(env), c(env))
        if cmp == "<=":
            return lambda env: np.where(y(env) - x(env) >= 0, b(env), c(env))
        if cmp == ">":
            return lambda env: np.where(y(env) - x(env) >= 0, c(env), b(env))
        return lambda env: np.where(x(env) - y(env) >= 0, c(env), b(env))


def compile_formula(text):
    """A numpy function of a dict of arrays (by input name) for a shaderfit formula."""
    f = _Parser(text).parse()

    def run(env):
        with np.errstate(all="ignore"):
            n = len(next(iter(env.values())))
            return np.broadcast_to(np.asarray(f(env), dtype=float), (n,)).astype(float)
    return run


# --- helpers ------------------------------------------------------------------------------------

def parse_domain(spec):
    name, rng = spec.split("=", 1)
    lo, hi = rng.split(":")[:2]
    const = lambda s: float(compile_formula(s)({"_": np.zeros(1)})[0])  # noqa: E731
    return name.strip(), const(lo), const(hi)


def rel_rms(a, ref, std):
    d = a - ref
    if not np.all(np.isfinite(d)):
        return math.inf
    return float(np.sqrt(np.mean(d * d)) / std)


def fmt(x, digits=2):
    if x is None:
        return "-"
    if isinstance(x, float) and math.isinf(x):
        return "inf"
    if x == 0:
        return "0"
    return f"{x:.{digits}e}"


def fmt_cost(c):
    if c is None:
        return "-"
    return str(int(c)) if float(c).is_integer() else f"{c:g}"


def run_cmd(cmd, timeout):
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    return p.returncode, p.stdout, p.stderr


def own_cost(sf, path, fn, uniform):
    cmd = [sf, "cost", "--reference-file", path, "--function", fn, "--json", "-"]
    if uniform:
        cmd += ["--uniform", ",".join(uniform)]
    rc, out, err = run_cmd(cmd, 120)
    if rc != 0:
        why = (err.strip().splitlines() or ["exit status %d" % rc])[-1]
        return {"lowers": False, "why": why.replace("shaderfit: error: --reference-file: ", "")}
    d = json.loads(out)
    return {"lowers": True, "cost": float(d["targets"]["sass"]["instructions"]),
            "material_cost": (d["targets"]["sass"].get("per_material") or {}).get("instructions"),
            "formula": d["formula"]}


GRID_COUNTS = {1: 190, 2: 23, 3: 11, 4: 7}  # counts that miss the round values of the domains


def grid_check(sf, path, fn, domain, ref, std, workdir, name):
    """The shader's own values (shaderfit eval on a regular grid, one group per point) against
    numpy; returns (max |diff| / std, points)."""
    dims = [parse_domain(s) for s in domain]
    n = GRID_COUNTS.get(len(dims), 5)
    axes = [np.linspace(lo, hi, n) for _, lo, hi in dims]
    mesh = np.meshgrid(*axes, indexing="ij")
    env = {d[0]: m.ravel() for d, m in zip(dims, mesh)}
    idx = np.zeros(n ** len(dims), dtype=int)
    for k, (_, lo, hi) in enumerate(dims):
        i = np.rint((env[dims[k][0]] - lo) / (hi - lo) * (n - 1)).astype(int)
        idx += i * n ** k
    with np.errstate(all="ignore"):
        want = np.asarray(ref(**env), dtype=float)
    big = float(10.0 * np.nanmax(np.abs(want)) + 1.0)
    terms = [f"{n ** k} * round(({d[0]} - ({d[1]!r})) / ({d[2] - d[1]!r}) * {n - 1})"
             for k, d in enumerate(dims)]
    cmd = [sf, "eval", "--reference-file", path, "--function", fn]
    for (nm, lo, hi), spec in zip(dims, domain):
        cmd += ["--domain", f"{spec}:{n}:endpoints"]
    jpath = os.path.join(workdir, f"{name}.grid.json")
    cmd += ["--define", "shaderfit_point = " + " + ".join(terms), "--group", "shaderfit_point",
            "--json", jpath, "--", "0", f"-{big!r}"]
    rc, out, err = run_cmd(cmd, 600)
    if rc != 0:
        return None, f"eval failed: {(err.strip().splitlines() or [''])[-1]}"
    d = json.loads(open(jpath).read())
    mag = {int(float(k)): v["max_abs"] for k, v in d["results"][0]["groups"]["shaderfit_point"].items()}
    shifted = {int(float(k)): v["max_abs"] for k, v in d["results"][1]["groups"]["shaderfit_point"].items()}
    got = np.array([math.copysign(mag[i], shifted[i] - big) if i in mag else math.nan for i in idx])
    diff = np.abs(got - want)
    if not np.all(np.isfinite(diff)):
        return math.inf, f"{len(idx)} grid points ({n}^{len(dims)}), some not finite"
    return float(np.max(diff) / std), f"{len(idx)} grid points ({n}^{len(dims)})"


def search(sf, path, fn, domain, uniform, args, json_path, log_path):
    cmd = [sf, "search", "--reference-file", path, "--function", fn]
    for spec in domain:
        cmd += ["--domain", spec]
    cmd += ["--time", str(args.time), "--threads", str(args.threads), "--seed", str(args.seed),
            "--quiet", "--json", json_path]
    if uniform:
        cmd += ["--uniform", ",".join(uniform)]
    t0 = time.time()
    rc, out, err = run_cmd(cmd, args.time * 5 + 300)
    with open(log_path, "w") as f:
        f.write(" ".join(cmd) + "\n\n" + out + err)
    return rc, time.time() - t0, " ".join(cmd)


# --- main ---------------------------------------------------------------------------------------

def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--shaderfit", default=os.path.join(ROOT, "build", "release", "shaderfit"))
    ap.add_argument("--manifest", default=os.path.join(HERE, "functions.toml"))
    ap.add_argument("--time", type=float, default=20.0, help="search seconds (default 20)")
    ap.add_argument("--threads", type=int, default=1, help="threads per search (default 1)")
    ap.add_argument("--seed", type=int, default=1, help="search seed (default 1)")
    ap.add_argument("--jobs", type=int, default=2, help="searches at once (default 2)")
    ap.add_argument("--only", default="", help="comma-separated function names")
    ap.add_argument("--modes", default="default,uniform", help="default, uniform or both")
    ap.add_argument("--out", default=os.path.join(ROOT, "build", "shaders"))
    ap.add_argument("--markdown", default="", help="write the tables to this file")
    ap.add_argument("--points", type=int, default=200000, help="random points of the numpy checks")
    ap.add_argument("--numpy-seed", type=int, default=12345)
    ap.add_argument("--checks-only", action="store_true",
                    help="only the own costs and the numpy checks, no search")
    ap.add_argument("--reuse", action="store_true",
                    help="keep a search whose JSON is already in --out (no new search)")
    args = ap.parse_args()

    sf = os.path.abspath(args.shaderfit)
    if not os.access(sf, os.X_OK):
        print(f"run.py: {sf} not found", file=sys.stderr)
        return 2
    modes = [m for m in args.modes.split(",") if m]
    if any(m not in ("default", "uniform") for m in modes):
        print("run.py: --modes takes default and uniform", file=sys.stderr)
        return 2
    with open(args.manifest, "rb") as f:
        funcs = tomllib.load(f)["function"]
    if args.only:
        wanted = args.only.split(",")
        unknown = set(wanted) - {f["name"] for f in funcs}
        if unknown:
            print(f"run.py: unknown functions: {', '.join(sorted(unknown))}", file=sys.stderr)
            return 2
        funcs = [f for f in funcs if f["name"] in wanted]
    os.makedirs(args.out, exist_ok=True)
    version = run_cmd([sf, "--version"], 30)[1].strip()
    t_start = time.time()

    # Points, references, own costs and the checks.
    results = {}
    failures = 0
    for fdef in funcs:
        name = fdef["name"]
        path = os.path.join(os.path.dirname(os.path.abspath(args.manifest)), fdef["file"])
        ref = numpy_refs.REFS[fdef["numpy"]]
        dims = [parse_domain(s) for s in fdef["domain"]]
        rng = np.random.default_rng(args.numpy_seed)
        env = {nm: rng.uniform(lo, hi, args.points) for nm, lo, hi in dims}
        with np.errstate(all="ignore"):
            yref = np.asarray(ref(**env), dtype=float)
        if not np.all(np.isfinite(yref)):
            print(f"FAIL {name}: the numpy reference is not finite at "
                  f"{int(np.sum(~np.isfinite(yref)))} points")
            failures += 1
        std = float(np.std(yref))
        r = {"name": name, "file": fdef["file"], "function": fdef["function"],
             "domain": fdef["domain"], "uniform": fdef["uniform"], "std": std, "modes": {}}
        own = own_cost(sf, path, fdef["function"], [])
        r["lowers"] = own["lowers"]
        r["why"] = own.get("why")
        r["lowered_formula"] = own.get("formula")
        if own["lowers"]:
            low = compile_formula(own["formula"])(env)
            r["lowered_vs_numpy"] = rel_rms(low, yref, std)
        else:
            r["lowered_vs_numpy"] = None
        r["grid_vs_numpy"], r["grid_note"] = grid_check(
            sf, path, fdef["function"], fdef["domain"], ref, std, args.out, name)
        ok_low = r["lowered_vs_numpy"] is None or r["lowered_vs_numpy"] <= CHECK_TOL
        ok_grid = r["grid_vs_numpy"] is not None and r["grid_vs_numpy"] <= CHECK_TOL
        r["check"] = "PASS" if ok_low and ok_grid else "FAIL"
        failures += r["check"] == "FAIL"
        print(f"{r['check']} {name}: lowered formula vs numpy "
              f"{fmt(r['lowered_vs_numpy']) if own['lowers'] else '(does not lower: ' + own['why'] + ')'}"
              f"; shader on the grid vs numpy {fmt(r['grid_vs_numpy'])} ({r['grid_note']})", flush=True)
        for mode in modes:
            uni = fdef["uniform"] if mode == "uniform" else []
            if mode == "uniform" and not uni:
                continue
            c = own if mode == "default" else own_cost(sf, path, fdef["function"], uni)
            r["modes"][mode] = {"own_cost": c.get("cost"),
                                "own_material_cost": c.get("material_cost")}
        results[name] = (r, path, env, yref)

    if args.checks_only:
        print(f"\n{len(results)} functions, {failures} check failures")
        return 1 if failures else 0

    # Searches, --jobs at once.
    tasks = [(name, mode) for name, (r, *_rest) in results.items() for mode in r["modes"]]

    def do(task):
        name, mode = task
        r, path, _, _ = results[name]
        fdef = next(f for f in funcs if f["name"] == name)
        jp = os.path.join(args.out, f"{name}.{mode}.json")
        lp = os.path.join(args.out, f"{name}.{mode}.log")
        if args.reuse and os.path.exists(jp):
            return task, 0, 0.0, "(reused)"
        uni = fdef["uniform"] if mode == "uniform" else []
        return (task,) + search(sf, path, fdef["function"], fdef["domain"], uni, args, jp, lp)

    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as ex:
        for (name, mode), rc, wall, cmd in ex.map(do, tasks):
            m = results[name][0]["modes"][mode]
            m["search_rc"], m["search_wall_s"], m["command"] = rc, wall, cmd
            print(f"searched {name} ({mode}): exit {rc}, {wall:.1f} s", flush=True)

    # Every member in numpy.
    warnings = 0
    for name, (r, path, env, yref) in results.items():
        std = r["std"]
        for mode, m in r["modes"].items():
            jp = os.path.join(args.out, f"{name}.{mode}.json")
            if not os.path.exists(jp):
                m["error"] = "no JSON (search failed)"
                continue
            d = json.load(open(jp))
            s = d.get("summary", {})
            m["generations"] = s.get("generations")
            m["rows"] = d.get("data", {}).get("rows")
            m["termination"] = s.get("termination")
            members = []
            for mem in d["front"]:
                try:
                    y = compile_formula(mem["formula"])(env)
                    rr = rel_rms(y, yref, std)
                except (ValueError, KeyError) as e:
                    print(f"WARN {name} ({mode}): cannot evaluate {mem['formula']!r}: {e}")
                    rr = math.inf
                jr = mem.get("rmse")
                entry = {"cost": mem["cost"], "material_cost": mem.get("material_cost"),
                         "formula": mem["formula"], "json_rmse": jr, "numpy_rel_rms": rr}
                # The JSON's rmse is on shaderfit's samples (corners, faces, Sobol points): for an
                # accurate member it should be near the numpy figure on random points.
                if jr is not None and math.isfinite(rr) and 1e-9 < jr / std <= 0.1:
                    ratio = (rr * std) / jr
                    if not 0.5 <= ratio <= 2.0:
                        warnings += 1
                        entry["warning"] = f"numpy rmse / JSON rmse = {ratio:.3g}"
                        print(f"WARN {name} ({mode}) cost {mem['cost']:g}: numpy rmse "
                              f"{rr * std:.3g} vs JSON rmse {jr:.3g} ({mem['formula']})")
                members.append(entry)
            m["members"] = members
            C = m["own_cost"]

            def best(limit):
                cands = [e["numpy_rel_rms"] for e in members if limit is None or e["cost"] <= limit + 1e-9]
                return min(cands) if cands else None

            m["best"] = best(None)
            if C is None:
                m["itself"] = None
                m["at_75"] = m["at_50"] = None
                m["limit_75"] = m["limit_50"] = None
            else:
                m["limit_75"] = math.floor(0.75 * C + 1e-9)
                m["limit_50"] = math.floor(0.5 * C + 1e-9)
                m["itself"] = any(e["cost"] <= C + 1e-9 and e["numpy_rel_rms"] <= ITSELF_TOL
                                  for e in members)
                m["at_75"] = best(m["limit_75"])
                m["at_50"] = best(m["limit_50"])

    wall = time.time() - t_start
    text = tables(results, modes, args, version, wall)
    print()
    print(text)
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write(text)
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump({"shaderfit": sf, "version": version, "args": vars(args), "wall_s": wall,
                   "check_failures": failures, "warnings": warnings,
                   "functions": [r for r, *_ in results.values()]}, f, indent=1)
    print(f"\n{len(results)} functions, {failures} check failures, {warnings} rmse warnings, "
          f"{wall:.0f} s")
    return 1 if failures else 0


def tables(results, modes, args, version, wall):
    out = []
    med_rows = []
    for mode in modes:
        rows = [(r, r["modes"][mode]) for r, *_ in results.values() if mode in r["modes"]]
        if not rows:
            continue
        per = "per-pixel " if mode == "uniform" else ""
        out.append(f"### Mode `{mode}`" + (" (`--uniform` with the per-material inputs)" if mode == "uniform" else ""))
        out.append("")
        out.append(f"| function | inputs | {per}own cost | itself | rel RMS at <= 75% | rel RMS at <= 50% "
                   "| best rel RMS (cost) | generations | rows |")
        out.append("| --- | --- | ---: | :---: | ---: | ---: | ---: | ---: | ---: |")
        for r, m in rows:
            names = [s.split("=")[0] for s in r["domain"]]
            inputs = ", ".join(n for n in names if n not in r["uniform"])
            if r["uniform"] and mode == "uniform":
                inputs += "; u: " + ", ".join(r["uniform"])
            elif r["uniform"]:
                inputs = ", ".join(names)
            members = m.get("members", [])
            bm = min(members, key=lambda e: (e["numpy_rel_rms"], e["cost"])) if members else None
            best = f"{fmt(bm['numpy_rel_rms'])} ({fmt_cost(bm['cost'])})" if bm else "-"
            own = fmt_cost(m["own_cost"]) if r["lowers"] else "-"
            itself = "-" if m.get("itself") is None else ("yes" if m["itself"] else "no")
            a75 = "-" if m.get("limit_75") is None else f"{fmt(m['at_75'])} (<= {m['limit_75']})"
            a50 = "-" if m.get("limit_50") is None else f"{fmt(m['at_50'])} (<= {m['limit_50']})"
            out.append(f"| {r['name']} | {inputs} | {own} | {itself} | {a75} | {a50} | {best} "
                       f"| {m.get('generations', '-')} | {m.get('rows', '-')} |")
        out.append("")
        low = [m for r, m in rows if m.get("limit_75") is not None]
        v75 = [m["at_75"] if m["at_75"] is not None else 1.0 for m in low]
        v50 = [m["at_50"] if m["at_50"] is not None else 1.0 for m in low]
        med_rows.append(
            f"| {mode} | {len(rows)} ({len(low)} lower) | {sum(1 for m in low if m['itself'])} / {len(low)} "
            f"| {fmt(statistics.median(v75)) if v75 else '-'} | {fmt(statistics.median(v50)) if v50 else '-'} "
            f"| {fmt(statistics.median([m['best'] for r, m in rows if m.get('best') is not None]))} |")
    head = ["### Medians", "",
            "| mode | functions | itself | median rel RMS at <= 75% | median rel RMS at <= 50% | median best rel RMS |",
            "| --- | ---: | ---: | ---: | ---: | ---: |"] + med_rows + [""]
    checks = ["### Checks (numpy against the shader)", "",
              "| function | file | lowered formula vs numpy | shader on a grid vs numpy | check |",
              "| --- | --- | ---: | ---: | :---: |"]
    for r, *_ in results.values():
        low = fmt(r["lowered_vs_numpy"]) if r["lowers"] else f"does not lower: {r['why']}"
        checks.append(f"| {r['name']} | {r['file']} | {low} | {fmt(r['grid_vs_numpy'])} "
                      f"({r['grid_note'].split(' (')[0]}) | {r['check']} |")
    checks.append("")
    note = [f"{version}; search {args.time:g} s, {args.threads} thread(s), seed {args.seed}, "
            f"{args.jobs} at once; numpy on {args.points:,} random points (seed {args.numpy_seed}); "
            f"whole run {wall:.0f} s.", "",
            "rel RMS: RMS(member - numpy reference) / std(reference) over the random points; "
            "itself: a member at cost <= the own cost with rel RMS <= 1e-6; "
            "'<= 75%': the least rel RMS among members costing at most floor(0.75 x own cost) "
            "(the limit in parentheses); 'u:': the per-material inputs; '-': the function does not "
            "lower (no own cost).", ""]
    return "\n".join(note + head + out + checks)


if __name__ == "__main__":
    sys.exit(main())
