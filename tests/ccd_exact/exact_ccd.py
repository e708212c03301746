#!/usr/bin/env python3
# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""Randomized differential test of the continuous narrow phase
(lib/narrow/narrow_sweep.c) against an exact rational reference.

Queries have small integer coordinates, so every quantity of a query is a
polynomial in t with rational coefficients, and the reference decides each
query exactly (Python's fractions, no floating point):

  A VF pair touches at time t when p(t) lies in the closed triangle
  (a(t), b(t), c(t)); an EE pair when the closed segments meet. Either
  predicate is a Boolean combination of sign conditions on a fixed family of
  polynomials in t (below: `vf_touch`, `ee_touch`, degenerate triangles and
  segments included). On each open interval between consecutive real roots
  of the family's polynomials every sign is constant, so the predicate is.
  The pair touches at some t in [0, 1] iff the predicate holds at 0, at 1,
  at a root in [0, 1], or at one rational point between consecutive roots;
  the first of these, in increasing order, where it holds is the earliest
  time of contact (the set of contact times is closed).

  Roots are isolated with Sturm sequences into rational intervals; the sign
  of a polynomial g at a root r of a square-free f isolated in (lo, hi) is 0
  when gcd(f, g) has a root in (lo, hi) (the only root of f there), else the
  interval is halved until g has no root in it and g's sign is read at an
  end. Two roots are compared the same way (equal when the gcd of their
  polynomials has a root in both intervals).

Generated motions favour degenerate cases: coplanar motions (everything at
z = 0), shared and repeated points, zero-length edges, collinear triangles,
parallel edges, points that do not move.

Usage: exact_ccd.py DRIVER [--queries N] [--seed S]. DRIVER is the
narrow_sweep_driver binary (reads queries, prints the narrow phase's answer
and toi). Exit 1 on a false negative, or on a toi later than the exact
earliest contact; prints the counts, false positives included.

exact_ccd.py --check-reference ../shared/data/ccd-sample-queries [--limit N]
checks the reference itself against that benchmark's exact truth (N queries
spread over its files; 0: all of them).
"""
import argparse
import random
import subprocess
import sys
from fractions import Fraction

ZERO = Fraction(0)


# ---------------------------------------------------------------------------
# Polynomials: tuples of Fractions, lowest degree first, no trailing zeros.

def trim(p):
    p = list(p)
    while p and p[-1] == 0:
        p.pop()
    return tuple(p)


def add(p, q):
    n = max(len(p), len(q))
    return trim((p[i] if i < len(p) else ZERO) + (q[i] if i < len(q) else ZERO) for i in range(n))


def neg(p):
    return tuple(-c for c in p)


def sub(p, q):
    return add(p, neg(q))


def mul(p, q):
    if not p or not q:
        return ()
    r = [ZERO] * (len(p) + len(q) - 1)
    for i, a in enumerate(p):
        if a:
            for j, b in enumerate(q):
                r[i + j] += a * b
    return trim(r)


def evaluate(p, t):
    r = ZERO
    for c in reversed(p):
        r = r * t + c
    return r


def derivative(p):
    return trim(i * p[i] for i in range(1, len(p)))


def remainder(p, q):
    p = list(p)
    while len(p) >= len(q):
        if p[-1] != 0:
            f = p[-1] / q[-1]
            s = len(p) - len(q)
            for i, c in enumerate(q):
                p[s + i] -= f * c
        p.pop()
    return trim(p)


def quotient(p, q):
    p = list(p)
    out = [ZERO] * max(len(p) - len(q) + 1, 1)
    while len(p) >= len(q):
        f = p[-1] / q[-1]
        s = len(p) - len(q)
        out[s] = f
        for i, c in enumerate(q):
            p[s + i] -= f * c
        p.pop()
    return trim(out)


def monic(p):
    return tuple(c / p[-1] for c in p)


def gcd(p, q):
    while q:
        p, q = q, remainder(p, q)
    return monic(p) if p else ()


def squarefree(p):
    g = gcd(p, derivative(p))
    return monic(quotient(p, g)) if len(g) > 1 else monic(p)


def sturm(p):
    seq = [p, derivative(p)]
    while len(seq[-1]) > 1:
        r = remainder(seq[-2], seq[-1])
        if not r:
            break
        seq.append(neg(r))
    return seq


def sign(x):
    return (x > 0) - (x < 0)


def variations(seq, t):
    signs = [s for s in (sign(evaluate(p, t)) for p in seq) if s != 0]
    return sum(1 for a, b in zip(signs, signs[1:]) if a != b)


def roots_between(seq, lo, hi):
    """Distinct roots in (lo, hi] of the square-free polynomial seq[0]."""
    return variations(seq, lo) - variations(seq, hi)


# ---------------------------------------------------------------------------
# Real roots in [0, 1]: exact Fractions, or (f, sturm(f), lo, hi) with
# exactly one root of the square-free f in the open interval, f(lo), f(hi)
# nonzero.

class Root:
    def __init__(self, f, seq, lo, hi):
        self.f, self.seq, self.lo, self.hi = f, seq, lo, hi

    def halve(self):
        mid = (self.lo + self.hi) / 2
        v = evaluate(self.f, mid)
        if v == 0:
            return mid  # an exact rational root
        if sign(v) == sign(evaluate(self.f, self.lo)):
            self.lo = mid
        else:
            self.hi = mid
        return None


def make_root(f, seq, lo, hi):
    """The one root of f in (lo, hi): a Root whose ends are no roots of f,
    or the Fraction it turns out to be."""
    while evaluate(f, lo) == 0 or evaluate(f, hi) == 0:
        mid = (lo + hi) / 2
        if evaluate(f, mid) == 0:
            return mid
        if roots_between(seq, lo, mid) > 0:  # in (lo, mid): f(mid) != 0
            hi = mid
        else:
            lo = mid
    return Root(f, seq, lo, hi)


def isolate(p):
    """Roots of p in [0, 1], each a Fraction or a Root."""
    if len(p) <= 1:
        return []
    f = squarefree(p)
    seq = sturm(f)
    out = []
    for t in (ZERO, Fraction(1)):
        if evaluate(f, t) == 0:
            out.append(t)
    stack = [(ZERO, Fraction(1))]
    while stack:
        lo, hi = stack.pop()
        n = roots_between(seq, lo, hi) - (evaluate(f, hi) == 0)
        if n == 0:
            continue
        if n == 1:
            out.append(make_root(f, seq, lo, hi))
            continue
        mid = (lo + hi) / 2
        if evaluate(f, mid) == 0:
            out.append(mid)
        stack.append((lo, mid))
        stack.append((mid, hi))
    # An isolated root whose interval halving lands on it exactly becomes a
    # Fraction (tidier; not needed for correctness).
    return out


def sign_at(g, r):
    """Sign of g at r (a Fraction or a Root); refines r's interval."""
    if isinstance(r, Fraction):
        return sign(evaluate(g, r))
    if not g:
        return 0
    common = gcd(r.f, g)
    if len(common) > 1 and roots_between(sturm(common), r.lo, r.hi) - (evaluate(common, r.hi) == 0) > 0:
        return 0
    gs = sturm(squarefree(g))
    while True:
        if evaluate(g, r.lo) != 0 and evaluate(g, r.hi) != 0 and roots_between(gs, r.lo, r.hi) == 0:
            return sign(evaluate(g, r.lo))
        exact = r.halve()
        if exact is not None:
            return sign(evaluate(g, exact))


def less(a, b):
    """-1, 0 or 1 as a < b, a == b, a > b, for Fractions and Roots."""
    if isinstance(a, Fraction) and isinstance(b, Fraction):
        return sign(a - b)
    if isinstance(a, Fraction):
        return -less(b, a)
    if isinstance(b, Fraction):
        if a.lo < b < a.hi and evaluate(a.f, b) == 0:
            return 0  # b is the one root of a.f in the interval
        while True:
            if a.hi <= b:
                return -1
            if a.lo >= b:
                return 1
            exact = a.halve()
            if exact is not None:
                return sign(exact - b)
    common = gcd(a.f, b.f)
    if len(common) > 1:
        cs = sturm(common)
        lo, hi = max(a.lo, b.lo), min(a.hi, b.hi)
        if lo < hi and roots_between(cs, lo, hi) - (evaluate(common, hi) == 0) > 0:
            return 0  # the one root of each in the shared interval
    while True:
        if a.hi <= b.lo:
            return -1
        if b.hi <= a.lo:
            return 1
        ea, eb = a.halve(), b.halve()
        if ea is not None:
            return less(ea, b)
        if eb is not None:
            return less(a, eb)


def sorted_roots(rs):
    out = []
    for r in rs:
        i = 0
        while i < len(out) and less(out[i], r) < 0:
            i += 1
        if i < len(out) and less(out[i], r) == 0:
            continue
        out.insert(i, r)
    return out


# ---------------------------------------------------------------------------
# Motions: a point is a triple of linear polynomials x0 + t (x1 - x0).

def point(x0, x1):
    return tuple(trim((Fraction(a), Fraction(b - a))) for a, b in zip(x0, x1))


def vsub(u, v):
    return tuple(sub(a, b) for a, b in zip(u, v))


def cross(u, v):
    return (sub(mul(u[1], v[2]), mul(u[2], v[1])), sub(mul(u[2], v[0]), mul(u[0], v[2])),
            sub(mul(u[0], v[1]), mul(u[1], v[0])))


def dot(u, v):
    return add(add(mul(u[0], v[0]), mul(u[1], v[1])), mul(u[2], v[2]))


class Predicate:
    """A Boolean combination of sign conditions, evaluated at any t by a
    sign oracle; `family` lists every polynomial it may ask about."""

    def __init__(self):
        self.family = []

    def poly(self, p):
        self.family.append(p)
        return p


def on_segment(P, p, x, y):
    """Conditions for point p on the closed segment [x, y] (y may equal x)."""
    d, w = vsub(y, x), vsub(p, x)
    c = cross(d, w)
    along, beyond = dot(w, d), dot(vsub(p, y), vsub(x, y))
    for q in (*d, *w, *c, along, beyond):
        P.poly(q)

    def holds(s):
        if all(s(q) == 0 for q in d):
            return all(s(q) == 0 for q in w)  # x == y: p must be that point
        return all(s(q) == 0 for q in c) and s(along) >= 0 and s(beyond) >= 0
    return holds


def vf_touch(p, a, b, c):
    P = Predicate()
    n = cross(vsub(b, a), vsub(c, a))
    for q in n:
        P.poly(q)
    plane = P.poly(dot(n, vsub(p, a)))
    sides = [P.poly(dot(cross(vsub(y, x), vsub(p, x)), n)) for x, y in ((a, b), (b, c), (c, a))]
    segments = [on_segment(P, p, x, y) for x, y in ((a, b), (b, c), (c, a))]

    def holds(s):
        if any(s(q) != 0 for q in n):
            return s(plane) == 0 and all(s(w) >= 0 for w in sides)
        # Collinear or coincident corners: the hull is one of the sides.
        return any(seg(s) for seg in segments)
    return P, holds


def ee_touch(a, b, c, d):
    P = Predicate()
    u, v = vsub(b, a), vsub(d, c)
    m = cross(u, v)
    for q in m:
        P.poly(q)
    plane = P.poly(dot(m, vsub(c, a)))
    s1 = P.poly(dot(cross(u, vsub(c, a)), m))
    s2 = P.poly(dot(cross(u, vsub(d, a)), m))
    s3 = P.poly(dot(cross(v, vsub(a, c)), m))
    s4 = P.poly(dot(cross(v, vsub(b, c)), m))
    ends = [on_segment(P, a, c, d), on_segment(P, b, c, d), on_segment(P, c, a, b),
            on_segment(P, d, a, b)]

    def holds(s):
        if any(s(q) != 0 for q in m):
            # Not parallel: coplanar, and each segment's ends on both sides
            # (or on) the other's line.
            return (s(plane) == 0 and s(s1) * s(s2) <= 0 and s(s3) * s(s4) <= 0)
        # Parallel (or a zero-length edge): meeting puts an end of one on the other.
        return any(e(s) for e in ends)
    return P, holds


def earliest_contact(P, holds):
    """The earliest t in [0, 1] at which the predicate holds, or None."""
    roots = []
    for q in set(P.family):
        if len(q) > 1:
            roots.extend(isolate(q))
    roots = sorted_roots(roots + [ZERO, Fraction(1)])
    samples = []
    for i in range(len(roots)):
        samples.append(roots[i])
        if i + 1 == len(roots):
            break
        # A rational point strictly between this root and the next.
        while True:
            r, nxt = roots[i], roots[i + 1]
            lower = r.hi if isinstance(r, Root) else r
            upper = nxt.lo if isinstance(nxt, Root) else nxt
            if lower < upper:
                samples.append((lower + upper) / 2)
                break
            if lower == upper and isinstance(r, Root) and isinstance(nxt, Root):
                samples.append(lower)  # r < r.hi = nxt.lo < nxt
                break
            for k in (i, i + 1):
                if isinstance(roots[k], Root):
                    exact = roots[k].halve()
                    if exact is not None:
                        roots[k] = exact
    for t in samples:
        if holds(lambda q, t=t: sign_at(q, t)):
            return t
    return None


# ---------------------------------------------------------------------------
# Random queries.

def random_query(rng):
    kind = rng.choice(("vf", "ee"))
    span = rng.choice((1, 2, 3))
    flat = rng.random() < 0.3  # a coplanar motion: every z = 0

    def coord():
        return rng.randint(-span, span)

    pts0, pts1 = [], []
    for k in range(4):
        x0 = [coord(), coord(), 0 if flat else coord()]
        r = rng.random()
        if k > 0 and r < 0.15:
            x0 = list(pts0[rng.randrange(k)])  # a repeated point at t = 0
        if r > 0.85:
            x1 = list(x0)  # a point that does not move
        else:
            x1 = [coord(), coord(), 0 if flat else coord()]
            if k > 0 and rng.random() < 0.1:
                x1 = list(pts1[rng.randrange(k)])
        pts0.append(x0)
        pts1.append(x1)
    return kind, pts0, pts1


def check_reference(directory, limit):
    """The reference itself against the exact truth of the continuous-
    collision benchmark's sample queries (rational coordinates, 8 rows a
    query: the 4 points at t = 0, then at t = 1, the truth in the last
    column): `limit` queries spread over every file."""
    import glob
    import os
    files = sorted(glob.glob(os.path.join(directory, "*", "*", "*.csv")))
    queries = []
    for path in files:
        rows = [line.strip().split(",") for line in open(path) if line.strip()]
        kind = "vf" if "vertex-face" in path else "ee"
        for q in range(len(rows) // 8):
            r = rows[8 * q:8 * q + 8]
            pts = [tuple(Fraction(int(x[2 * k]), int(x[2 * k + 1])) for k in range(3)) for x in r]
            queries.append((os.path.relpath(path, directory), kind, pts[:4], pts[4:], int(r[0][6])))
    step = max(1, len(queries) // limit) if limit else 1
    chosen = queries[::step]
    wrong = 0
    for name, kind, p0, p1, truth in chosen:
        pts = [tuple(trim((a, b - a)) for a, b in zip(x0, x1)) for x0, x1 in zip(p0, p1)]
        P, holds = vf_touch(*pts) if kind == "vf" else ee_touch(*pts)
        got = earliest_contact(P, holds) is not None
        if got != bool(truth):
            wrong += 1
            print("REFERENCE DISAGREES on %s (%s): truth %d" % (name, kind, truth))
    print("reference: %d of %d sample queries (%d files) agree with the benchmark's truth"
          % (len(chosen) - wrong, len(chosen), len(files)))
    return 1 if wrong else 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("driver", nargs="?")
    ap.add_argument("--queries", type=int, default=4000)
    ap.add_argument("--seed", type=int, default=2026)
    ap.add_argument("--check-reference", metavar="DIR",
                    help="check the reference on the sample queries in DIR instead")
    ap.add_argument("--limit", type=int, default=300)
    args = ap.parse_args()
    if args.check_reference:
        return check_reference(args.check_reference, args.limit)
    if not args.driver:
        ap.error("the driver is required")
    rng = random.Random(args.seed)
    queries = [random_query(rng) for _ in range(args.queries)]
    text = "".join(
        "%s %s\n" % (k, " ".join(str(x) for p in p0 + p1 for x in p)) for k, p0, p1 in queries)
    run = subprocess.run([args.driver], input=text, capture_output=True, text=True, check=True)
    answers = run.stdout.split("\n")
    counts = {"vf": [0, 0, 0], "ee": [0, 0, 0]}  # touching, false negatives, false positives
    failures = 0
    for (kind, p0, p1), line in zip(queries, answers):
        hit, toi = line.split()
        hit, toi = int(hit), Fraction(float(toi))
        pts = [point(a, b) for a, b in zip(p0, p1)]
        P, holds = vf_touch(*pts) if kind == "vf" else ee_touch(*pts)
        t = earliest_contact(P, holds)
        c = counts[kind]
        if t is not None:
            c[0] += 1
            if not hit:
                c[1] += 1
                failures += 1
                print("FALSE NEGATIVE %s %s -> %s, exact earliest t %s" % (kind, p0, p1, t))
            elif less(t, toi) < 0:
                failures += 1
                print("LATE TOI %s %s -> %s: toi %s after the exact %s" % (kind, p0, p1, float(toi), t))
        elif hit:
            c[2] += 1
    for kind in ("vf", "ee"):
        n = sum(1 for q in queries if q[0] == kind)
        print("%s: %d queries, %d touch (exact), %d false negatives, %d false positives"
              % (kind, n, counts[kind][0], counts[kind][1], counts[kind][2]))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
