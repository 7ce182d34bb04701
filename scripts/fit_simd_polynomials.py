#!/usr/bin/env python3
"""Derives the polynomial coefficients of the SIMD `ln` and `atan2`
(crates/core/src/coords/lanes/math.rs). Needs mpmath (pip install mpmath); not used by the
build or the tests.

Each polynomial is a relative least-squares fit on Chebyshev nodes (near-minimax) in 50-digit
arithmetic, checked on a dense grid with the coefficients rounded to f64:

* ln:   atanh(s)/s as a polynomial in z = s^2, |s| <= (sqrt2 - 1)/(sqrt2 + 1), degree 7;
* atan: atan(r)/r as a polynomial in z = r^2, |r| <= tan(pi/8), degree 11.
"""
from mpmath import mp, mpf, cos, pi, atanh, atan, sqrt, tan, matrix, lu_solve

mp.dps = 50


def fit(f, a, b, deg):
    n = 4 * (deg + 1)
    nodes = [(a + b) / 2 + (b - a) / 2 * cos(pi * (2 * k + 1) / (2 * n)) for k in range(n)]
    A = matrix(n, deg + 1)
    y = matrix(n, 1)
    for i, z in enumerate(nodes):
        fz = f(z)
        for j in range(deg + 1):
            A[i, j] = z**j / fz
        y[i] = 1
    c = lu_solve(A.T * A, A.T * y)
    return [float(c[j]) for j in range(deg + 1)]


def max_relative_error(f, cs, a, b, m=4000):
    worst = mpf(0)
    for i in range(m + 1):
        z = a + (b - a) * i / m
        acc = mpf(cs[-1])
        for c in reversed(cs[:-1]):
            acc = acc * z + c
        worst = max(worst, abs(acc / f(z) - 1))
    return float(worst)


def report(name, f, zmax, deg):
    cs = fit(f, mpf(0), zmax, deg)
    cs[0] = 1.0  # both functions are 1 at z = 0
    print(f"// {name}: degree {deg}, max relative error {max_relative_error(f, cs, mpf(0), zmax):.1e}")
    print(f"const {name}: [f64; {deg + 1}] = [")
    for c in cs:
        print(f"    {c!r},")
    print("];")


s_max = (sqrt(2) - 1) / (sqrt(2) + 1)
report("LN_POLY", lambda z: atanh(sqrt(z)) / sqrt(z) if z > 0 else mpf(1), s_max**2, 7)
report("ATAN_POLY", lambda z: atan(sqrt(z)) / sqrt(z) if z > 0 else mpf(1), tan(pi / 8) ** 2, 11)
