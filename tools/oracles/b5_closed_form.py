#!/usr/bin/python3
"""Enright and Pryce's B5 (DETEST) in closed form, as an oracle for the certified reference.

    y1' = y2 y3,  y2' = -y1 y3,  y3' = -0.51 y1 y2,  y(0) = (0, 1, 1)

is solved by the Jacobi elliptic functions y = (sn t, cn t, dn t) with parameter m = k^2 = 0.51
(DLMF 22.13.1-3: sn' = cn dn, cn' = -sn dn, dn' = -m sn cn). mpmath's ellipfun evaluates them;
each value is computed at two working precisions and the file records their largest difference.
It shares no code with the C++ library.

Usage (from the repository root; needs Debian python3-mpmath):
    /usr/bin/python3 tools/oracles/b5_closed_form.py --out tests/data/general_oracles/b5.csv
"""
import argparse
import shlex
import sys

from mpmath import mp, mpf


def values(dps, times):
    mp.dps = dps
    m = mpf('0.51')
    # sn 0 = 0 exactly; ellipfun returns rounding noise there, which chop removes.
    return [[mp.chop(mp.ellipfun(f, mpf(t), m=m), tol=mpf(10) ** (-dps + 10)) for f in ('sn', 'cn', 'dn')]
            for t in times]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--out', required=True)
    ap.add_argument('--digits', type=int, default=45)
    args = ap.parse_args()
    times = list(range(0, 21, 2))
    low, high = values(60, times), values(90, times)
    mp.dps = 100
    diff = max(abs(a - b) for ra, rb in zip(low, high) for a, b in zip(ra, rb))
    cmd = ' '.join(shlex.quote(a) for a in ['/usr/bin/python3'] + sys.argv)
    lines = ['# Enright-Pryce B5 in closed form: (sn, cn, dn)(t | m = 0.51), mpmath ellipfun, by '
             'tools/oracles/b5_closed_form.py.',
             f'# Regenerate (from the repository root): {cmd}',
             f'# Values from the 90-digit evaluation, {args.digits} significant digits; the 60-digit one '
             f'differs by at most {mp.nstr(diff, 3)}.',
             't,y1,y2,y3']
    for t, row in zip(times, high):
        lines.append(','.join([str(t)] + [mp.nstr(v, args.digits) for v in row]))
    with open(args.out, 'w') as f:
        f.write('\n'.join(lines) + '\n')


if __name__ == '__main__':
    main()
