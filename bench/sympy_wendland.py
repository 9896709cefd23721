#!/usr/bin/env python3
"""SymPy reference timing for the normalised extended Wendland functions.

Definitions (Franz thesis, section 4.3):

    I f(r)        = int_r^1 s f(s) ds                  (I^k: k-fold application)
    f_n(r)        = (1 - r)^n
    psi_{d,k,l}   = I^k f_{mu+l},  mu = floor(d/2) + k + 1,   0 <= r <= 1
    W_{d,k,l}     = psi / (omega_d * int_0^1 r^(d-1) psi(r) dr)
    omega_1 = 2, omega_2 = 2 pi, omega_3 = 4 pi

so that W has unit integral over R^d.  W factors as
    W(r) = pi^pi_power * (1 - r)^edge_power * p(r),
    edge_power = floor(d/2) + 2k + l + 1,  deg p = k.

The script computes W exactly for d = 1..3, k = 0..4, l = 0..4 (75 kernels),
prints the elapsed wall time of the computation (time.perf_counter, after the
imports) and with --json OUT writes

    {"d=3,k=2,l=1": {
        "normalisation": "p/q*pi^-1",   # C with W = C * psi ("p/q" for d = 1)
        "pi_power": -1,                 # 0 for d = 1, -1 for d = 2, 3
        "monomial": ["p/q", ...],       # W(r) = pi^pi_power * sum_i monomial[i] r^i
        "edge_power": n,
        "factor": ["p/q", ...],         # W(r) = pi^pi_power * (1-r)^n * sum_i factor[i] r^i
        "psi_monomial": ["p/q", ...]}}  # psi(r) = sum_i psi_monomial[i] r^i (unnormalised)

All coefficient lists are in ascending powers of r; every rational is written
as "p/q" (q = 1 for integers).

Two implementations, which must give identical output:
  --method integrate  (default) the literal transcription: sympy.integrate on
                      expressions, with pi as the symbol sympy.pi;
  --method poly       sympy.Poly over QQ: I p = P(1) - P(r) with P' = s p(s).
"""

import argparse
import json
import sys
import time

import sympy as sp

R = sp.Symbol("r", nonnegative=True)
S = sp.Symbol("s", nonnegative=True)

DIMS = (1, 2, 3)
KS = range(0, 5)
LS = range(0, 5)

# omega_d = (rational part, power of pi)
OMEGA = {1: (sp.Integer(2), 0), 2: (sp.Integer(2), 1), 3: (sp.Integer(4), 1)}

# W(0) for d = 3, l = 0 (Dehnen & Aly 2012, Wendland C2 / C4 / C6, r = support radius)
DEHNEN_ALY_3D = {1: sp.Rational(21, 2) / sp.pi, 2: sp.Rational(495, 32) / sp.pi, 3: sp.Rational(1365, 64) / sp.pi}


def edge_power(d, k, l):
    return d // 2 + 2 * k + l + 1


def mu(d, k):
    return d // 2 + k + 1


# ---------------------------------------------------------------------------
# Method "integrate": symbolic expressions, sympy.integrate, symbolic pi.

def wendland_integrate(d, k, l):
    """Return (psi, W) as sympy expressions in R."""
    psi = (1 - R) ** (mu(d, k) + l)
    for _ in range(k):
        psi = sp.integrate(S * psi.subs(R, S), (S, R, 1))
    omega = OMEGA[d][0] * sp.pi ** OMEGA[d][1]
    mass = omega * sp.integrate(R ** (d - 1) * psi, (R, 0, 1))
    return sp.expand(psi), sp.expand(psi / mass)


def rational_coeffs(expr, pi_power):
    """Ascending rational coefficients of expr * pi^(-pi_power), a polynomial in R."""
    poly = sp.Poly(sp.expand(expr * sp.pi ** (-pi_power)), R)
    coeffs = list(reversed(poly.all_coeffs()))
    assert all(c.is_Rational for c in coeffs), coeffs
    return coeffs


def kernel_integrate(d, k, l):
    pi_power = -OMEGA[d][1]
    psi, w = wendland_integrate(d, k, l)
    return rational_coeffs(psi, 0), rational_coeffs(w, pi_power)


# ---------------------------------------------------------------------------
# Method "poly": sympy.Poly over QQ; pi tracked as an exponent.

def op_I(p):
    """I p (r) = int_r^1 s p(s) ds = P(1) - P(r), P an antiderivative of s p(s)."""
    big_p = (sp.Poly(R, R, domain=sp.QQ) * p).integrate()
    return sp.Poly(big_p.eval(1), R, domain=sp.QQ) - big_p


def kernel_poly(d, k, l):
    psi = sp.Poly((1 - R) ** (mu(d, k) + l), R, domain=sp.QQ)
    for _ in range(k):
        psi = op_I(psi)
    moment = (sp.Poly(R ** (d - 1), R, domain=sp.QQ) * psi).integrate().eval(1)
    c = 1 / (OMEGA[d][0] * moment)
    w = psi * c
    return [sp.Rational(x) for x in reversed(psi.all_coeffs())], [sp.Rational(x) for x in reversed(w.all_coeffs())]


# ---------------------------------------------------------------------------

METHODS = {"integrate": kernel_integrate, "poly": kernel_poly}


def factor_out_edge(monomial, n):
    """p with sum_i monomial[i] r^i = (1-r)^n p(r); asserts exact divisibility."""
    num = sp.Poly(list(reversed(monomial)), R, domain=sp.QQ)
    quo, rem = sp.div(num, sp.Poly((1 - R) ** n, R, domain=sp.QQ))
    assert rem.is_zero, "not divisible by (1-r)^%d" % n
    return [sp.Rational(x) for x in reversed(quo.all_coeffs())]


def compute_all(method):
    kernel = METHODS[method]
    out = {}
    for d in DIMS:
        for k in KS:
            for l in LS:
                psi_coeffs, w_coeffs = kernel(d, k, l)
                n = edge_power(d, k, l)
                out[(d, k, l)] = {
                    "psi": psi_coeffs,
                    "w": w_coeffs,
                    "pi_power": -OMEGA[d][1],
                    "normalisation": w_coeffs[0] / psi_coeffs[0],  # rational part; psi(0) != 0
                    "edge_power": n,
                    "factor": factor_out_edge(w_coeffs, n),
                }
    return out


def sanity_checks(kernels):
    for (d, k, l), kern in kernels.items():
        pi_fac = sp.pi ** kern["pi_power"]
        factor = kern["factor"]
        assert len(factor) == k + 1, (d, k, l, factor)  # deg p = k
        assert len(kern["w"]) == kern["edge_power"] + k + 1
        # unit mass over R^d: omega_d * int_0^1 r^(d-1) W(r) dr == 1
        mass = sum(c / (i + d) for i, c in enumerate(kern["w"]))
        assert sp.simplify(OMEGA[d][0] * sp.pi ** OMEGA[d][1] * mass * pi_fac) == 1, (d, k, l)
        # W = C * psi
        assert all(wc == kern["normalisation"] * pc for wc, pc in zip(kern["w"], kern["psi"]))
    for k, expected in DEHNEN_ALY_3D.items():
        kern = kernels[(3, k, 0)]
        got = kern["w"][0] * sp.pi ** kern["pi_power"]
        assert sp.simplify(got - expected) == 0, (k, got, expected)
    # classical shapes: C2 ~ (1-r)^4 (1 + 4r), C4 ~ (1-r)^6 (3 + 18r + 35r^2) in 3D
    for k, shape in ((1, [1, 4]), (2, [3, 18, 35])):
        p = kernels[(3, k, 0)]["factor"]
        assert all(pc * shape[0] == p[0] * sc for pc, sc in zip(p, shape)), (k, p)


def pq(x):
    x = sp.Rational(x)
    return "%d/%d" % (x.p, x.q)


def to_json(kernels):
    doc = {}
    for (d, k, l), kern in kernels.items():
        norm = pq(kern["normalisation"])
        if kern["pi_power"] != 0:
            norm += "*pi^%d" % kern["pi_power"]
        doc["d=%d,k=%d,l=%d" % (d, k, l)] = {
            "normalisation": norm,
            "pi_power": kern["pi_power"],
            "monomial": [pq(c) for c in kern["w"]],
            "edge_power": kern["edge_power"],
            "factor": [pq(c) for c in kern["factor"]],
            "psi_monomial": [pq(c) for c in kern["psi"]],
        }
    return doc


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", metavar="OUT", help="write the coefficients as JSON to OUT")
    ap.add_argument("--method", choices=sorted(METHODS), default="integrate",
                    help="sympy implementation to time (default: integrate)")
    args = ap.parse_args(argv)

    t0 = time.perf_counter()
    kernels = compute_all(args.method)
    elapsed = time.perf_counter() - t0

    sanity_checks(kernels)  # not timed
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(to_json(kernels), fh, indent=1)
            fh.write("\n")
    print("elapsed: %.6f s (%d kernels, method %s, sympy %s)" % (elapsed, len(kernels), args.method, sp.__version__))
    return 0


if __name__ == "__main__":
    sys.exit(main())
