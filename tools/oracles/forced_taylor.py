#!/usr/bin/python3
"""Independent high-precision oracle for Euler's equations forced by a function of time.

Writes the values of
    y1' = a1 y2 y3,  y2' = a2 y3 y1,  y3' = a3 y1 y2 + A sin(t)^2 [t in the window]
at the output times, for the test problems whose forcing is not a polynomial: SciML's rigid body
(a = (-2, 1.25, -0.5), A = 0.25 at every time, y(0) = (1, 0, 0.9)) and Hairer, Norsett and Wanner's
EULR (the same equations, for omega of I = (0.5, 2, 3), with the forcing only for 3 pi <= t < 4 pi).
It shares no code with the C++ library: the equations are written here from the problems' texts
(the Taylor step's sum and step rule come from coupled_taylor.py beside it, the same method).

Method: Taylor series in t of order N about each step's start, the coefficients by the jet
recurrences of the products (Cauchy products, mpmath.fdot: exact accumulation, one rounding) and
of s = sin t, c = cos t (s' = c, c' = -s, restarted from mp.sin, mp.cos at each step's start).
N = 1.15 dps + 6. The step is the largest for which the last two terms |x_k| h^k (k = N-1, N) of
every component are at most 10^-(dps+3) of max_{j<=3} |x_j| h^j; steps land exactly on the output
times and on the window's ends (3 pi and 4 pi at the working precision), where the forcing switches.

Accuracy: each case runs at several working precisions (different orders, steps and rounding); the
file stores the most precise run, and its header records the largest difference between
consecutive runs. Each step also compares the series' derivative at mid-step with the equations
evaluated directly (rhs()), to 10^(-dps+5).

Usage (from the repository root; needs Debian python3-mpmath):
    /usr/bin/python3 tools/oracles/forced_taylor.py --case sciml_10 --dps 45,70,100,120 --digits 95 \\
        --out tests/data/general_oracles/sciml_10.csv
    /usr/bin/python3 tools/oracles/forced_taylor.py --case CASE --dps 45,70 \\
        --out tests/data/general_oracles/CASE.csv       (CASE: sciml_100 eulr)
"""
import argparse
import shlex
import sys

from mpmath import mp, mpf

# The series' sum and the step rule are those of the coupled oracle beside this file (the same
# Taylor method); the equations and their jets below are this problem's own.
from coupled_taylor import horner, step_size

SCIML = dict(a=('-2', '1.25', '-0.5'), A='0.25', y0=('1', '0', '0.9'))
CASES = {
    'sciml_10': dict(SCIML, window=None, times=list(range(0, 11))),
    'sciml_100': dict(SCIML, window=None, times=list(range(0, 101, 10))),
    # EULR: omega' = I^-1 (M - omega x I omega) with I = (0.5, 2, 3): a_i = (I_j - I_l) / I_i, and
    # M3 / I3 = 0.75 sin^2 t / 3 on [3 pi, 4 pi).
    'eulr': dict(a=('-2', '1.25', '-0.5'), A='0.25', y0=('1', '0', '0.9'), window=('3', '4'),
                 times=list(range(0, 21, 2))),
}


def jets(a, A, forced, t0, y, N):
    """Taylor coefficients (orders 0..N) of y about t0."""
    x = [[v] for v in y]
    s, c = [mp.sin(t0)], [mp.cos(t0)]
    ss = []
    for k in range(N):
        def cp(u, v):
            return mp.fdot(u[:k + 1], v[k::-1])
        ss.append(cp(s, s))
        d = [a[0] * cp(x[1], x[2]), a[1] * cp(x[2], x[0]), a[2] * cp(x[0], x[1])]
        if forced:
            d[2] += A * ss[k]
        for i in range(3):
            x[i].append(d[i] / (k + 1))
        s.append(c[k] / (k + 1))
        c.append(-s[k] / (k + 1))
    return x


def rhs(a, A, forced, t, y):
    f = [a[0] * y[1] * y[2], a[1] * y[2] * y[0], a[2] * y[0] * y[1]]
    if forced:
        f[2] += A * mp.sin(t) ** 2
    return f


def derivative(x, h):
    acc = mpf(0)
    for k in range(len(x) - 1, 0, -1):
        acc = acc * h + k * x[k]
    return acc


def run(spec, dps):
    mp.dps = dps
    a = [mpf(v) for v in spec['a']]
    A = mpf(spec['A'])
    y = [mpf(v) for v in spec['y0']]
    window = None if spec['window'] is None else [mpf(v) * mp.pi for v in spec['window']]
    N = int(1.15 * dps) + 6
    log_tol = -(dps + 3) * mp.log(10)
    check = mpf(10) ** (-dps + 5)
    t = mpf(0)
    out = []
    for target in (mpf(v) for v in spec['times']):
        while t < target:
            forced = window is None or (window[0] <= t < window[1])
            x = jets(a, A, forced, t, y, N)
            h = min(step_size(x, N, log_tol), target - t)
            if window is not None:
                for edge in window:
                    if t < edge:
                        h = min(h, edge - t)
            # The series' derivative at mid-step against the equations.
            mid = [horner(xi, h / 2) for xi in x]
            f = rhs(a, A, forced, t + h / 2, mid)
            for i in range(3):
                scale = max(abs(f[i]), max(abs(v) for v in mid), mpf(1))
                if abs(derivative(x[i], h / 2) - f[i]) > check * scale:
                    sys.exit(f'forced_taylor: the recurrences disagree with the equations at t = {t} (dps {dps})')
            y = [horner(xi, h) for xi in x]
            t = t + h
            if window is not None:
                for edge in window:
                    if abs(t - edge) < mpf(10) ** (-dps):
                        t = edge  # land exactly on the switch
        out.append(list(y))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--case', required=True, choices=sorted(CASES))
    ap.add_argument('--dps', default='45,70')
    ap.add_argument('--digits', type=int, default=45)
    ap.add_argument('--out', required=True)
    args = ap.parse_args()
    spec = CASES[args.case]
    precisions = [int(v) for v in args.dps.split(',')]
    runs = [run(spec, d) for d in precisions]
    mp.dps = max(precisions) + 10
    notes = []
    for (d0, r0), (d1, r1) in zip(zip(precisions, runs), zip(precisions[1:], runs[1:])):
        diff = max(abs(u - v) for ra, rb in zip(r0, r1) for u, v in zip(ra, rb))
        notes.append(f'# dps {d0} vs dps {d1}: largest |difference| {mp.nstr(diff, 3)}')
    cmd = ' '.join(shlex.quote(v) for v in ['/usr/bin/python3'] + sys.argv)
    names = ('omega1', 'omega2', 'omega3') if args.case == 'eulr' else ('y1', 'y2', 'y3')
    lines = [f'# Independent Taylor-series integration in mpmath by tools/oracles/forced_taylor.py (case {args.case}).',
             f'# Regenerate (from the repository root): {cmd}',
             f'# Working precisions compared (decimal digits): {args.dps}; values from the last, '
             f'{args.digits} significant digits.'] + notes + ['t,' + ','.join(names)]
    for tv, row in zip(spec['times'], runs[-1]):
        lines.append(str(tv) + ',' + ','.join(mp.nstr(v, args.digits, strip_zeros=False) if v else '0' for v in row))
    with open(args.out, 'w') as f:
        f.write('\n'.join(lines) + '\n')


if __name__ == '__main__':
    main()
