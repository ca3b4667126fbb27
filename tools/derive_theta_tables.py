#!/usr/bin/env python3
"""Writes include/eulervop/special/detail/theta_tables.hpp, the generated constants of the theta-function
route (jacobi_theta.hpp), after checking each against mpmath at 60 digits:

1. Piecewise polynomials, in double, for the two modulus quantities on its critical path:

       g(d)    = q(m) / m        the nome q = exp(-pi K'/K) over the parameter m = k^2
       rate(d) = pi / (2 K(m))   the rate of the theta argument v = pi u / (2K)

   both as functions of d = kc^2 = 1 - m on [2^-6, 1] (k <= 0.99 is d >= 0.0199). They are
   analytic there, with a branch point at d = 0 (m = 1). Each binade [2^E, 2^(E+1)) of d,
   E = -6..-1, is cut into 4 equal intervals; on each the function is interpolated at 14
   Chebyshev points (degree 13) in t = (d - centre) / halfwidth, which is exact in double, and
   converted to monomial coefficients in t. The interval nearest the singularity has
   centre/halfwidth = 9: Chebyshev convergence rate 9 + sqrt(80) = 17.9 per degree, so degree 13
   leaves ~5e-17 relative.

2. The sin/cos kernel of sincos_double.hpp on |r| <= pi/4: S(z) = (sin(sqrt z)/sqrt z - 1)/z
   (degree 5) and C(z) = (cos(sqrt z) - 1)/z (degree 6), z = r^2, interpolated at Chebyshev
   points of [0, (pi/4)^2 (1 + 1e-4)] (near-minimax; the Taylor series would need degrees 7, 8).

The script evaluates the rounded coefficients in double in the same order as the C++ (Estrin's
scheme) at 400 points per interval (20,000 for the kernel) and prints the worst relative error
in units of 2^-52; it refuses to write the header if any exceeds 1.

Usage: tools/derive_theta_tables.py [output]   (default include/eulervop/special/detail/theta_tables.hpp)
Needs mpmath (Debian: python3-mpmath); the build does not run it, the header is committed.
"""
import sys

import mpmath as mp

mp.mp.dps = 60
DEGREE = 13
SUB = 4          # intervals per binade
ROWS = 6         # binades 2^-1 .. 2^-6
EPS = 2.0 ** -52


def g_of_d(d):
    m = 1 - d
    if m == 0:
        return mp.mpf(1) / 16
    return mp.qfrom(m=m) / m


def rate_of_d(d):
    return mp.pi / (2 * mp.ellipk(1 - d))


def interval(row, j):
    """d range of table entry (row, j): binade 2^-(row+1), quarter j."""
    base = mp.mpf(2) ** (-(row + 1))
    lo = base * (1 + mp.mpf(j) / SUB)
    hi = base * (1 + mp.mpf(j + 1) / SUB)
    return lo, hi


def chebyshev_coefficients(f, lo, hi, degree):
    """Chebyshev coefficients a_j of the degree-`degree` interpolant of f at the Chebyshev points
    of [lo, hi], in t = (x - centre) / halfwidth."""
    n = degree + 1
    c, h = (lo + hi) / 2, (hi - lo) / 2
    nodes = [mp.cos(mp.pi * (k + mp.mpf(1) / 2) / n) for k in range(n)]
    vals = [f(c + h * t) for t in nodes]
    a = [2 * mp.fsum(vals[k] * mp.cos(j * mp.pi * (k + mp.mpf(1) / 2) / n) for k in range(n)) / n
         for j in range(n)]
    a[0] /= 2
    return a


def monomial(a, c=0, h=1):
    """sum_j a_j T_j((x - c) / h) as monomial coefficients in x (c = 0, h = 1: in t itself)."""
    c, h = mp.mpf(c), mp.mpf(h)
    T = [[mp.mpf(1)], [-c / h, 1 / h]]
    for j in range(2, len(a)):
        nxt = [mp.mpf(0)] * (j + 1)
        for i, x in enumerate(T[j - 1]):
            nxt[i] += 2 * (-c / h) * x
            nxt[i + 1] += 2 * x / h
        for i, x in enumerate(T[j - 2]):
            nxt[i] -= x
        T.append(nxt)
    mono = [mp.mpf(0)] * len(a)
    for j, aj in enumerate(a):
        for i, x in enumerate(T[j]):
            mono[i] += aj * x
    return mono


def estrin(cs, t):
    """Double-precision evaluation in the order of jacobi_theta.hpp's nome_poly: c0 + t R(t),
    R by Estrin's scheme over c1..c13, so that the dominant c0 meets a single rounding."""
    t2 = t * t
    t4 = t2 * t2
    t8 = t4 * t4
    p = [cs[1 + 2 * i] + cs[2 + 2 * i] * t for i in range(6)]
    q0 = p[0] + t2 * p[1]
    q1 = p[2] + t2 * p[3]
    q2 = p[4] + t2 * p[5]
    lo = q0 + t4 * q1
    hi = q2 + t4 * cs[13]
    return cs[0] + t * (lo + t8 * hi)


KERNEL_Z = (mp.pi / 4) ** 2 * mp.mpf("1.0001")
S_DEGREE, C_DEGREE = 5, 6


def kernel_coefficients():
    fS = lambda z: (mp.sin(mp.sqrt(z)) / mp.sqrt(z) - 1) / z
    fC = lambda z: (mp.cos(mp.sqrt(z)) - 1) / z
    half = KERNEL_Z / 2
    S = [float(x) for x in monomial(chebyshev_coefficients(fS, 0, KERNEL_Z, S_DEGREE), half, half)]
    C = [float(x) for x in monomial(chebyshev_coefficients(fC, 0, KERNEL_Z, C_DEGREE), half, half)]
    C[0] = -0.5  # exact (the interpolant's constant rounds to it anyway)
    S = S + [0.0] * (len(C) - len(S))
    return S, C


def kernel_eval(S, C, r):
    """Double evaluation in the order of sincos_kernel."""
    z = r * r
    z2 = z * z
    z4 = z2 * z2
    def est(k):
        return ((k[0] + k[1] * z) + z2 * (k[2] + k[3] * z)) + z4 * ((k[4] + k[5] * z) + z2 * k[6])
    return r + (r * z) * est(S), 1 + z * est(C)


def kernel_worst(S, C):
    import random
    rng = random.Random(1)
    ws = wc = 0.0
    lim = float(mp.pi / 4)
    for i in range(20000):
        r = (i / 100.0) * lim if i <= 100 else rng.uniform(-lim, lim)
        s, c = kernel_eval(S, C, r)
        rs, rc = mp.sin(mp.mpf(r)), mp.cos(mp.mpf(r))
        if rs != 0:
            ws = max(ws, float(abs((s - rs) / rs)) / EPS)
        wc = max(wc, float(abs((c - rc) / rc)) / EPS)
    return ws, wc


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "include/eulervop/special/detail/theta_tables.hpp"
    tables = {"g": [], "rate": []}
    worst = {"g": 0.0, "rate": 0.0}
    for row in range(ROWS):
        for j in range(SUB):
            lo, hi = interval(row, j)
            for name, f in (("g", g_of_d), ("rate", rate_of_d)):
                cs = [float(x) for x in monomial(chebyshev_coefficients(f, lo, hi, DEGREE))]
                tables[name].append(cs)
                for k in range(401):
                    t = -1 + 2 * k / 400.0
                    d = (lo + hi) / 2 + (hi - lo) / 2 * mp.mpf(t)
                    ref = f(d)
                    got = estrin(cs, t)
                    err = float(abs((mp.mpf(got) - ref) / ref)) / EPS
                    worst[name] = max(worst[name], err)
    S, C = kernel_coefficients()
    worst["sin"], worst["cos"] = kernel_worst(S, C)
    print("worst relative error in 2^-52: g %.3f  rate %.3f  sin %.3f  cos %.3f"
          % (worst["g"], worst["rate"], worst["sin"], worst["cos"]))
    if max(worst.values()) > 1:
        sys.exit("refusing to write: error above 1 ulp")
    with open(out, "w") as fh:
        fh.write("// Generated by tools/derive_theta_tables.py; do not edit. Constants of the theta route:\n")
        fh.write("// piecewise polynomials in t = (d - centre) / halfwidth, d = kc^2, for g = q/m and\n")
        fh.write("// pi/(2K), and the sin/cos kernel (see the script). Worst relative error of the double\n")
        fh.write("// evaluation (units of 2^-52): g %.3f, pi/(2K) %.3f, sin %.3f, cos %.3f.\n"
                 % (worst["g"], worst["rate"], worst["sin"], worst["cos"]))
        fh.write("#pragma once\n\nnamespace eulervop::detail::nome_table {\n\n")
        fh.write("inline constexpr int rows = %d, per_binade = %d, coefficients = %d;\n\n" % (ROWS, SUB, DEGREE + 1))
        # g and pi/(2K) side by side: one SSE register per coefficient (jacobi_theta.hpp
        # evaluates both polynomials at once).
        fh.write("// g_rate[interval][j] = {g_j, rate_j}: coefficient of t^j of g = q/m and of pi/(2K).\n")
        fh.write("alignas(16) inline constexpr double g_rate[rows * per_binade][coefficients][2] = {\n")
        for cg, cr in zip(tables["g"], tables["rate"]):
            fh.write("    {" + ", ".join("{%s, %s}" % (a.hex(), b.hex()) for a, b in zip(cg, cr)) + "},\n")
        fh.write("};\n\n")
        fh.write("}  // namespace eulervop::detail::nome_table\n\n")
        fh.write("namespace eulervop::detail::sincos_table {\n\n")
        fh.write("// {S_j, C_j}: sin r = r + r z S(z), cos r = 1 + z C(z), z = r^2 (S has degree %d).\n" % S_DEGREE)
        fh.write("alignas(16) inline constexpr double S_C[%d][2] = {\n" % len(C))
        for a, b in zip(S, C):
            fh.write("    {%s, %s},\n" % (a.hex(), b.hex()))
        fh.write("};\n\n}  // namespace eulervop::detail::sincos_table\n")


if __name__ == "__main__":
    main()
