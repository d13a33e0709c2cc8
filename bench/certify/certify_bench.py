#!/usr/bin/env python3
"""Certified bounds (`search --certify`) against a dense check and against Sollya.

For each case (ten functions of one variable, three of two) this runs

    shaderfit search --reference F --domain ... --loss max_abs --ops auto --time T --threads 2
                     --certify --json out.json

and then, for every front member, compares its certified bound (JSON `certified_max_abs`) with
  - the largest |error| over 10^7 uniform points, computed here in numpy float64 from the
    member's `formula` text (its constants as stored) and the reference written in numpy;
  - in one variable, Sollya's bound: `supnorm(0, ref - approx, I, absolute, 2^-20)` on each piece
    where the formula's selects, copysigns, signs, min/max, saturate and abs are decided (the
    pieces meet where their arguments change sign); where supnorm fails on a piece (a singular
    end, such as acos at 1), the piece is cut geometrically towards both ends, supnorm on each
    part, and `infnorm` on the last 2^-40 of it; the method column says which were used.
and prints a table. Run by hand (not a test): docs/reference.md "Certification" quotes it;
bench/certify/README.md says how.

    bench/certify/certify_bench.py [--shaderfit build/release/shaderfit] [--time 20]
                                   [--cases acos,erf] [--points 10000000] [--keep DIR]
"""

import argparse
import ast
import itertools
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from decimal import Decimal

import numpy as np

TOLERANCE = 0.01  # CertifyOptions::tolerance: the bound's target is (1 + this) x the maximum


def erf(x):
    try:
        from scipy.special import erf as scipy_erf
        return scipy_erf(x)
    except ImportError:
        return np.vectorize(math.erf)(x)


def fresnel(c, f0):
    """Exact dielectric Fresnel reflectance (unpolarised) for the normal-incidence reflectance f0."""
    s = np.sqrt(f0)
    eta = (1 + s) / (1 - s)
    g = np.sqrt(eta * eta - 1 + c * c)
    return 0.5 * ((g - c) / (g + c)) ** 2 * (1 + ((c * (g + c) - 1) / (c * (g - c) + 1)) ** 2)


FRESNEL_TEXT = "0.5 * ((g - c) / (g + c))^2 * (1 + ((c * (g + c) - 1) / (c * (g - c) + 1))^2)"
FRESNEL_004_SOLLYA = ("0.5 * ((sqrt(1.25 + x^2) - x) / (sqrt(1.25 + x^2) + x))^2 * (1 + ((x * "
                      "(sqrt(1.25 + x^2) + x) - 1) / (x * (sqrt(1.25 + x^2) - x) + 1))^2)")
SRGB_BREAK = 0.0031308

# name, reference (reference language), defines, domain {var: (lo, hi)}, numpy reference,
# Sollya pieces of the reference [(lo, hi, text)] (one variable only), and the operators where
# `--ops auto` would offer the function itself (exp2 for exp2, a division for a rational, sqrt
# for hypot): an exact member says nothing about the bounds.
CASES = [
    ("acos", "acos(x)", [], {"x": (-1.0, 1.0)}, lambda x: np.arccos(x), [(-1, 1, "acos(x)")]),
    ("asin", "asin(x)", [], {"x": (-1.0, 1.0)}, lambda x: np.arcsin(x), [(-1, 1, "asin(x)")]),
    ("atan", "atan(x)", [], {"x": (-1.0, 1.0)}, lambda x: np.arctan(x), [(-1, 1, "atan(x)")]),
    ("erf", "erf(x)", [], {"x": (-2.0, 2.0)}, erf, [(-2, 2, "erf(x)")]),
    ("exp2", "exp2(x)", [], {"x": (0.0, 1.0)}, lambda x: np.exp2(x), [(0, 1, "2^x")],
     "+,-,*,/"),
    ("log2", "log2(x)", [], {"x": (1.0, 2.0)}, lambda x: np.log2(x), [(1, 2, "log2(x)")],
     "+,-,*,/,sqrt"),
    ("tanh", "tanh(x)", [], {"x": (-3.0, 3.0)}, lambda x: np.tanh(x), [(-3, 3, "tanh(x)")]),
    ("srgb", f"x <= {SRGB_BREAK} ? 12.92 * x : 1.055 * pow(x, 1 / 2.4) - 0.055", [],
     {"x": (0.0, 1.0)},
     lambda x: np.where(x <= SRGB_BREAK, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055),
     [(0, SRGB_BREAK, "12.92 * x"), (SRGB_BREAK, 1, "1.055 * x^(1 / 2.4) - 0.055")]),
    ("schlick", FRESNEL_TEXT.replace("g", "sqrt(1.25 + c^2)"), [], {"c": (0.0, 1.0)},
     lambda c: fresnel(c, 0.04), [(0, 1, FRESNEL_004_SOLLYA)]),
    ("rational", "1 / (1 + 25 * x^2)", [], {"x": (-1.0, 1.0)},
     lambda x: 1 / (1 + 25 * x * x), [(-1, 1, "1 / (1 + 25 * x^2)")], "+,-,*,abs,sqrt"),
    ("fresnel-2d", FRESNEL_TEXT,
     ["eta = (1 + sqrt(f0)) / (1 - sqrt(f0))", "g = sqrt(eta^2 - 1 + c^2)"],
     {"c": (0.0, 1.0), "f0": (0.02, 0.1)}, fresnel, None),
    ("smith-2d", "2 * v / (v + sqrt(a^2 + (1 - a^2) * v^2))", [],
     {"v": (0.0, 1.0), "a": (0.1, 1.0)},
     lambda v, a: 2 * v / (v + np.sqrt(a * a + (1 - a * a) * v * v)), None),
    ("hypot-2d", "hypot(x, y)", [], {"x": (0.0, 1.0), "y": (0.0, 1.0)},
     lambda x, y: np.hypot(x, y), None, "+,-,*,/,min,max,abs"),
]


# --- the member's formula (shaderfit's syntax, expr/parse.hpp), through Python's ast ---------

def parse(text):
    return ast.parse(text.replace("^", "**"), mode="eval").body


def condition_operand(node):
    """select's first argument is `X >= 0` as shaderfit prints it: X."""
    if isinstance(node, ast.Compare) and isinstance(node.ops[0], ast.GtE):
        right = node.comparators[0]
        if isinstance(right, ast.Constant) and right.value == 0:
            return node.left
        return ast.BinOp(node.left, ast.Sub(), right)
    raise ValueError("select's condition is not 'X >= 0': " + ast.unparse(node))


def evaluate(node, env):
    """The formula in numpy float64, with shaderfit's operator meaning (expr/op.hpp)."""
    ev = lambda n: evaluate(n, env)
    if isinstance(node, ast.Constant):
        return float(node.value)
    if isinstance(node, ast.Name):
        return np.pi if node.id == "pi" else env[node.id]
    if isinstance(node, ast.UnaryOp):
        return -ev(node.operand) if isinstance(node.op, ast.USub) else ev(node.operand)
    if isinstance(node, ast.BinOp):
        a, b = ev(node.left), ev(node.right)
        if isinstance(node.op, ast.Pow):  # an integer exponent (x^k), by the power itself
            k = b
            return a ** int(k) if k > 0 else 1.0 / a ** int(-k)
        return {ast.Add: np.add, ast.Sub: np.subtract, ast.Mult: np.multiply,
                ast.Div: np.divide}[type(node.op)](a, b)
    if isinstance(node, ast.Call):
        name, args = node.func.id, node.args
        if name == "select":
            return np.where(ev(condition_operand(args[0])) >= 0, ev(args[1]), ev(args[2]))
        v = [ev(a) for a in args]
        unary = {"sqrt": np.sqrt, "exp2": np.exp2, "log2": np.log2, "exp": np.exp, "log": np.log,
                 "abs": np.abs, "sin": np.sin, "cos": np.cos, "sign": np.sign,
                 "rsqrt": lambda a: 1.0 / np.sqrt(a), "rcp": lambda a: 1.0 / a,
                 "saturate": lambda a: np.clip(a, 0.0, 1.0)}
        if name in unary:
            return unary[name](v[0])
        if name == "min":
            return np.fmin(v[0], v[1])
        if name == "max":
            return np.fmax(v[0], v[1])
        if name == "copysign":
            return np.copysign(v[0], v[1])
        if name == "pow":  # exp2(b log2 a): NaN for a < 0, as on GPUs
            return np.exp2(v[1] * np.log2(v[0]))
        if name == "fma":
            return v[0] * v[1] + v[2]
    raise ValueError("unknown construct: " + ast.unparse(node))


def decision_points(node):
    """The arguments whose sign decides a branch or a kink: pieces end where they change sign."""
    out = []
    for n in ast.walk(node):
        if not isinstance(n, ast.Call):
            continue
        name, args = n.func.id, n.args
        if name == "select":
            out.append(condition_operand(args[0]))
        elif name in ("abs", "sign"):
            out.append(args[0])
        elif name == "copysign":
            out += [args[0], args[1]]
        elif name in ("min", "max"):
            out.append(ast.BinOp(args[0], ast.Sub(), args[1]))
        elif name == "saturate":
            out += [args[0], ast.BinOp(args[0], ast.Sub(), ast.Constant(1.0))]
    return out


def exact(v):
    """A double as the exact decimal Sollya reads without rounding (prec = 165)."""
    return "(" + str(Decimal(float(v))) + ")"


def to_sollya(node, var, mid):
    """Sollya text of the formula on a piece whose middle is `mid`: every choice decided there."""
    s = lambda n: to_sollya(n, var, mid)
    at = lambda n: float(np.atleast_1d(evaluate(n, {var: np.array([mid])}))[0])
    sign_at = lambda n: float(np.sign(at(n)))
    if isinstance(node, ast.Constant):
        return exact(node.value)
    if isinstance(node, ast.Name):
        return "pi" if node.id == "pi" else "x"
    if isinstance(node, ast.UnaryOp):
        return "(-" + s(node.operand) + ")"
    if isinstance(node, ast.BinOp):
        if isinstance(node.op, ast.Pow):
            return "(" + s(node.left) + ")^(" + str(int(node.right.value if isinstance(
                node.right, ast.Constant) else -node.right.operand.value)) + ")"
        op = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/"}[type(node.op)]
        return "(" + s(node.left) + " " + op + " " + s(node.right) + ")"
    name, args = node.func.id, node.args
    if name == "select":
        return s(args[1]) if sign_at(condition_operand(args[0])) >= 0 else s(args[2])
    if name == "abs":
        return s(args[0]) if sign_at(args[0]) >= 0 else "(-" + s(args[0]) + ")"
    if name == "copysign":  # |a| with b's sign, both decided on the piece
        a = s(args[0]) if sign_at(args[0]) >= 0 else "(-" + s(args[0]) + ")"
        return a if sign_at(args[1]) >= 0 else "(-" + a + ")"
    if name == "sign":
        return "(" + str(int(sign_at(args[0]))) + ")"
    if name in ("min", "max"):
        d = sign_at(ast.BinOp(args[0], ast.Sub(), args[1]))
        first = (d <= 0) if name == "min" else (d >= 0)
        return s(args[0]) if first else s(args[1])
    if name == "saturate":
        v = at(args[0])
        return "0" if v <= 0 else ("1" if v >= 1 else s(args[0]))
    simple = {"sqrt": "sqrt({})", "exp": "exp({})", "log": "log({})", "log2": "log2({})",
              "sin": "sin({})", "cos": "cos({})", "exp2": "2^({})", "rsqrt": "(1 / sqrt({}))",
              "rcp": "(1 / ({}))"}
    if name in simple:
        return simple[name].format(s(args[0]))
    if name == "pow":
        return "((" + s(args[0]) + ")^(" + s(args[1]) + "))"
    if name == "fma":
        return "(" + s(args[0]) + " * " + s(args[1]) + " + " + s(args[2]) + ")"
    raise ValueError("no Sollya form for " + name)


def breakpoints(node, var, lo, hi):
    """Where the decision arguments change sign on [lo, hi], to double precision."""
    xs = np.linspace(lo, hi, 100001)
    out = set()
    for d in decision_points(node):
        with np.errstate(all="ignore"):
            g = evaluate(d, {var: xs})
        g = np.broadcast_to(g, xs.shape)
        s = np.sign(g)
        for i in np.nonzero(s[:-1] * s[1:] < 0)[0]:
            a, b = xs[i], xs[i + 1]
            ga = s[i]
            for _ in range(80):  # bisection in double
                m = 0.5 * (a + b)
                if m <= a or m >= b:
                    break
                with np.errstate(all="ignore"):
                    gm = np.sign(np.atleast_1d(evaluate(d, {var: np.array([m])}))[0])
                if gm == 0:
                    a = b = m
                    break
                if gm == ga:
                    a = m
                else:
                    b = m
            out.add(float(b))
        for i in np.nonzero(s == 0)[0]:
            out.add(float(xs[i]))
    return sorted(p for p in out if lo < p < hi)


SOLLYA_PRELUDE = r"""
prec = 165!;
verbosity = 0!;
procedure ok(r) {
  var res;
  res = match r with [lo;up] : (true) default : (false);
  return res;
};
procedure piece(f, a, b) {
  var r, res;
  r = supnorm(0, f, [a;b], absolute, 2^(-20));
  if (ok(r)) then {
    res = [| 0, inf(r), sup(r) |];
  } else {
    r = infnorm(f, [a;b]);
    res = [| 2, inf(r), sup(r) |];
  };
  return res;
};
procedure join(p, q) {
  return [| max(p[0], q[0]), max(p[1], q[1]), max(p[2], q[2]) |];
};
procedure bound(f, a, b) {
  var r, res, k, w, q;
  r = supnorm(0, f, [a;b], absolute, 2^(-20));
  if (ok(r)) then {
    res = [| 0, inf(r), sup(r) |];
  } else {
    w = b - a;
    res = piece(f, a + w / 4, b - w / 4);
    for k from 2 to 40 do {
      res = join(res, piece(f, a + w / 2^(k + 1), a + w / 2^k));
      res = join(res, piece(f, b - w / 2^k, b - w / 2^(k + 1)));
    };
    q = infnorm(f, [a; a + w / 2^41]);
    res = join(res, [| 1, inf(q), sup(q) |]);
    q = infnorm(f, [b - w / 2^41; b]);
    res = join(res, [| 1, inf(q), sup(q) |]);
  };
  return res;
};
"""

METHODS = {0: "supnorm", 1: "supnorm+infnorm(ends)", 2: "supnorm+infnorm"}


def sollya_bound(formula, var, lo, hi, ref_pieces, timeout):
    """Sollya's enclosure [l, u] of max |ref - formula| on [lo, hi], and the method used."""
    node = parse(formula)
    cuts = set(breakpoints(node, var, lo, hi))
    for a, b, _ in ref_pieces:
        cuts.update(p for p in (a, b) if lo < p < hi)
    ends = [lo] + sorted(cuts) + [hi]
    lines = [SOLLYA_PRELUDE, "res = [| 0, 0, 0 |];"]
    for a, b in zip(ends[:-1], ends[1:]):
        mid = 0.5 * (a + b)
        ref = next(t for pa, pb, t in ref_pieces if pa <= mid <= pb)
        approx = to_sollya(node, var, mid)
        lines.append(f"f = ({ref}) - ({approx});")
        lines.append(f"res = join(res, bound(f, {exact(a)}, {exact(b)}));")
    lines.append('write(res[0], " ", res[1], " ", res[2], "\\n");')
    try:
        out = subprocess.run(["sollya", "--nocolor"], input="\n".join(lines), text=True,
                             capture_output=True, timeout=timeout).stdout
    except subprocess.TimeoutExpired:
        return None, None, "timeout"
    m = re.findall(r"^(\d) (\S+) (\S+)$", out, re.M)
    if not m:
        return None, None, "failed"
    method, l, u = m[-1]
    return float(l), float(u), METHODS[int(method)]


def real_value(node, env):
    """The formula in real arithmetic (mpmath, 200 bits; constants as stored): None where it is
    undefined (a complex or NaN intermediate, a division by 0)."""
    import mpmath
    mpmath.mp.prec = 200

    def ev(n):  # raises ValueError at the first undefined intermediate
        value = ev_node(n)
        if isinstance(value, mpmath.mpc) or mpmath.isnan(value):
            raise ValueError("undefined")
        return value

    def ev_node(n):
        if isinstance(n, ast.Constant):
            return mpmath.mpf(float(n.value))
        if isinstance(n, ast.Name):
            return mpmath.pi if n.id == "pi" else env[n.id]
        if isinstance(n, ast.UnaryOp):
            return -ev(n.operand)
        if isinstance(n, ast.BinOp):
            a, b = ev(n.left), ev(n.right)
            if isinstance(n.op, ast.Pow):
                return a ** int(b)
            return {ast.Add: lambda: a + b, ast.Sub: lambda: a - b, ast.Mult: lambda: a * b,
                    ast.Div: lambda: a / b}[type(n.op)]()
        name, args = n.func.id, n.args
        if name == "select":
            return ev(args[1]) if ev(condition_operand(args[0])) >= 0 else ev(args[2])
        v = [ev(x) for x in args]
        table = {"sqrt": lambda: mpmath.sqrt(v[0]), "exp2": lambda: 2 ** v[0],
                 "log2": lambda: mpmath.log(v[0], 2), "exp": lambda: mpmath.exp(v[0]),
                 "log": lambda: mpmath.log(v[0]), "abs": lambda: abs(v[0]),
                 "sin": lambda: mpmath.sin(v[0]), "cos": lambda: mpmath.cos(v[0]),
                 "sign": lambda: mpmath.sign(v[0]), "rsqrt": lambda: 1 / mpmath.sqrt(v[0]),
                 "rcp": lambda: 1 / v[0], "saturate": lambda: min(max(v[0], 0), 1),
                 "min": lambda: min(v[0], v[1]), "max": lambda: max(v[0], v[1]),
                 "copysign": lambda: abs(v[0]) if v[1] >= 0 else -abs(v[0]),
                 "pow": lambda: 2 ** (v[1] * mpmath.log(v[0], 2)),
                 "fma": lambda: v[0] * v[1] + v[2]}
        return table[name]()

    try:
        return ev(node)
    except (ZeroDivisionError, TypeError, ValueError):
        return None


def undefined_at(formula, domain):
    """A point of the domain where the formula is undefined in the reals (a corner, or 0 inside),
    or next to which it is unbounded or undefined (a denominator changing sign, a square root or
    logarithm of a negative number, found on a grid): None when neither is found."""
    node = parse(formula)
    names = list(domain)
    axes = [[lo, hi] + ([0.0] if lo < 0 < hi else []) for lo, hi in domain.values()]
    for point in itertools.product(*axes):
        if real_value(node, dict(zip(names, point))) is None:
            return point
    singular = []  # (argument, whether only its sign change matters)
    for n in ast.walk(node):
        if isinstance(n, ast.BinOp) and isinstance(n.op, ast.Div):
            singular.append((n.right, True))
        elif isinstance(n, ast.Call) and n.func.id in ("rcp",):
            singular.append((n.args[0], True))
        elif isinstance(n, ast.Call) and n.func.id in ("sqrt", "rsqrt", "log", "log2", "pow"):
            singular.append((n.args[0], False))
    if not singular:
        return None
    k = 100001 if len(names) == 1 else 1001
    grids = np.meshgrid(*[np.linspace(lo, hi, k) for lo, hi in domain.values()], indexing="ij")
    env = dict(zip(names, grids))
    for arg, sign_change in singular:
        with np.errstate(all="ignore"):
            g = np.broadcast_to(evaluate(arg, env), grids[0].shape)
        if not sign_change:
            bad = np.argwhere(g < 0)
            if len(bad):
                return tuple(float(grid[tuple(bad[0])]) for grid in grids)
            continue
        for axis in range(len(names)):  # neighbours along each axis with opposite signs
            lo_side = np.take(g, range(k - 1), axis=axis)
            hi_side = np.take(g, range(1, k), axis=axis)
            change = np.argwhere(np.sign(lo_side) * np.sign(hi_side) <= 0)
            if len(change):
                i = tuple(change[0])
                j = list(i)
                j[axis] += 1
                a = np.array([grid[i] for grid in grids])
                b = np.array([grid[tuple(j)] for grid in grids])
                sa = np.sign(g[i])
                for _ in range(80):  # bisection along the segment
                    m = 0.5 * (a + b)
                    with np.errstate(all="ignore"):
                        gm = np.sign(np.atleast_1d(evaluate(arg, dict(zip(names, m))))[0])
                    if gm == 0:
                        a = b = m
                        break
                    a, b = (m, b) if gm == sa else (a, m)
                return tuple(float(v) for v in b)
    return None


def dense_max(formula, variables, domain, ref, points):
    """max |formula - reference| over `points` uniform points (a grid in two variables)."""
    node = parse(formula)
    worst = 0.0
    if len(variables) == 1:
        (v,) = variables
        lo, hi = domain[v]
        xs = np.linspace(lo, hi, points)
        for k in range(0, points, 1_000_000):
            x = xs[k:k + 1_000_000]
            with np.errstate(all="ignore"):
                e = np.abs(np.broadcast_to(evaluate(node, {v: x}), x.shape) - ref(x))
            if np.isnan(e).any():
                return math.inf
            worst = max(worst, float(e.max()))
        return worst
    n = int(math.isqrt(points))
    (u, w) = variables
    us = np.linspace(*domain[u], n)
    ws = np.linspace(*domain[w], n)
    for k in range(0, n, 256):
        a, b = np.meshgrid(us[k:k + 256], ws, indexing="ij")
        with np.errstate(all="ignore"):
            e = np.abs(np.broadcast_to(evaluate(node, {u: a, w: b}), a.shape) - ref(a, b))
        if np.isnan(e).any():
            return math.inf
        worst = max(worst, float(e.max()))
    return worst


def run_case(case, args, workdir):
    name, reference, defines, domain, ref, ref_pieces = case[:6]
    ops = case[6] if len(case) > 6 else "auto"
    out = os.path.join(workdir, name + ".json")
    cmd = [args.shaderfit, "search", "--reference", reference, "--loss", "max_abs", "--ops", ops,
           "--time", str(args.time), "--threads", "2", "--certify", "--json", out]
    if ops != "auto":
        cmd += ["--evolve-ops", "none"]
    for v, (lo, hi) in domain.items():
        cmd += ["--domain", f"{v}={lo!r}:{hi!r}"]
    for d in defines:
        cmd += ["--define", d]
    t0 = time.time()
    log = subprocess.run(cmd, text=True, capture_output=True)
    if log.returncode != 0:
        print(f"{name}: shaderfit failed ({log.returncode}): {log.stderr.strip()[-400:]}")
        return []
    search_s = time.time() - t0
    front = json.load(open(out))["front"]
    variables = list(domain)
    # The reference's largest magnitude, for exact members (at the corners and a grid).
    grids = np.meshgrid(*[np.linspace(lo, hi, 101) for lo, hi in domain.values()], indexing="ij")
    scale = float(np.nanmax(np.abs(ref(*grids))))
    rows = []
    for m in front:
        formula = m["formula"]
        cert = m.get("certified_max_abs")
        cert = math.inf if cert is None else float(cert)
        dense = dense_max(formula, variables, domain, ref, args.points)
        lo_s = hi_s = None
        method = "-"
        if ref_pieces is not None and len(variables) == 1 and shutil.which("sollya"):
            try:
                lo_s, hi_s, method = sollya_bound(formula, variables[0], *domain[variables[0]],
                                                  ref_pieces, args.sollya_timeout)
            except (ValueError, KeyError, AttributeError) as e:  # a construct without a form
                method = "n/a: " + str(e)[:40]
        nan_at = undefined_at(formula, domain) if math.isinf(cert) else None
        rows.append(dict(case=name, cost=m["cost"], dense=dense, certified=cert, scale=scale,
                         nan_at=nan_at,
                         converged=m.get("certified_converged"), sollya_lo=lo_s,
                         sollya_hi=hi_s, method=method, time=m.get("certify_time_s"),
                         formula=formula, search_s=search_s))
    return rows


def verdict(r, limit):
    """The acceptance: dense <= certified <= limit x dense, and Sollya's enclosure agrees. An exact
    member (dense max 0) is certified down to CertifyOptions::resolution, 2^-30 of the reference;
    one undefined somewhere in the reals (sqrt of a constant-folded -5e-17 at x = 1, which float64
    happens to round to 0) has no finite bound, rightly."""
    if r.get("nan_at") is not None:  # undefined in the reals: no finite bound is right
        return True
    if r["dense"] <= 1e-12 * r["scale"]:  # exact, up to float64 rounding
        return r["certified"] <= 2.0**-30 * r["scale"] * (1 + 1e-9)
    # The dense maximum carries float64 rounding (a few ulps of the reference).
    ok = r["dense"] <= r["certified"] + 4e-16 * r["scale"] and r["certified"] <= limit * r["dense"]
    if r["sollya_hi"] is not None:
        ok = ok and r["sollya_lo"] <= r["certified"] <= (1 + TOLERANCE) * r["sollya_hi"] * (
            1 + 1e-9)
    return ok


def fmt_point(p):
    return "(" + ", ".join(f"{v:.6g}" for v in p) + ")"


def row_text(r):
    two = r["case"].endswith("-2d")
    limit = 1.2 if two else 1.05
    ratio = r["certified"] / r["dense"] if r["dense"] > 0 else math.inf
    sollya = "-" if r["sollya_hi"] is None else f"{r['sollya_hi']:.4e}"
    return (f"{r['case']:<11}{r['cost']:>5g}{r['dense']:>12.4e}{r['certified']:>12.4e}"
            f"{ratio:>8.4f}{sollya:>12}  {r['method']:<22}"
            f"{'yes' if verdict(r, limit) else 'NO':>6}{(r['time'] or 0):>8.3f}"
            + (f"  undefined or unbounded at {fmt_point(r['nan_at'])}"
               if r.get("nan_at") is not None else ""))


HEADER = (f"{'case':<11}{'cost':>5}{'dense max':>12}{'certified':>12}{'ratio':>8}"
          f"{'sollya':>12}  {'method':<22}{'agree':>6}{'time s':>8}")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--shaderfit", default="build/release/shaderfit")
    p.add_argument("--time", type=float, default=20, help="search seconds per case")
    p.add_argument("--cases", default="", help="comma-separated case names (default: all)")
    p.add_argument("--points", type=int, default=10_000_000, help="dense check points")
    p.add_argument("--sollya-timeout", type=float, default=300, help="seconds per member")
    p.add_argument("--keep", default="", help="keep the search JSON in this folder")
    p.add_argument("--json", default="", help="write the rows here")
    p.add_argument("--table", default="", help="print the table of rows written by --json")
    args = p.parse_args()
    if args.table:
        rows = json.load(open(args.table))
        domains = {c[0]: c[3] for c in CASES}
        for r in rows:
            if "nan_at" not in r:
                r["nan_at"] = (undefined_at(r["formula"], domains[r["case"]])
                               if math.isinf(r["certified"]) else None)
        summary(rows)
        return 0
    if not shutil.which("sollya"):
        print("sollya not found: the Sollya column stays empty (Debian package sollya)")
    wanted = set(filter(None, args.cases.split(",")))
    workdir = args.keep or tempfile.mkdtemp(prefix="certify_bench_")
    os.makedirs(workdir, exist_ok=True)
    print(HEADER)
    print("-" * len(HEADER), flush=True)
    rows = []
    for case in CASES:
        if wanted and case[0] not in wanted:
            continue
        for r in run_case(case, args, workdir):
            rows.append(r)
            print(row_text(r), flush=True)
        if args.json:
            json.dump(rows, open(args.json, "w"), indent=1)
    summary(rows, table=False)


def summary(rows, table=True):
    if table:
        print(HEADER)
        print("-" * len(HEADER))
        for r in rows:
            print(row_text(r))
    one = sorted(r["time"] for r in rows if r["time"] is not None and "-2d" not in r["case"])
    two = sorted(r["time"] for r in rows if r["time"] is not None and "-2d" in r["case"])
    bad = sum(not verdict(r, 1.2 if "-2d" in r["case"] else 1.05) for r in rows)
    print(f"\n{len(rows)} members, {bad} not agreeing")
    for name, t in (("one variable", one), ("two variables", two)):
        if t:
            print(f"certification time per member, {name}: median {t[len(t) // 2]:.3f} s, "
                  f"max {t[-1]:.3f} s ({len(t)} members)")


if __name__ == "__main__":
    sys.exit(main())
