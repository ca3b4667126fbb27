#!/usr/bin/env python3
"""Holds every certified row of the shipped datasets (data/reference/*.csv) against an independent
higher-precision run (docs/datasets.md): for each file, `eulervop reference` of the same scene in
mpfr:200 (default) at the rows' exact binary times, and each radius column must bound the 2-norm
of the printed values' distance to that run's: `radius` for Omega1..3 or y1..3 (skipped in a
physical scene, where it is a statement at the row's binary tau, not at its t), `radius_omega` for
omega1..3, `radius_q` for q0..q3. The printed time is a decimal that rounds back to the row's
binary128 time; the run gets that binary number as an exact decimal, since the values differ by up
to a unit of the decimal's last digit times the rate. Prints the largest error/radius per column;
exits 1 if any row's error exceeds its radius.

Usage: tools/check_dataset_radii.py [path/to/eulervop] [PRECISION]   (about 3 minutes)
"""
import csv
import os
import shlex
import subprocess
import sys
import tempfile
from decimal import Decimal, getcontext
from fractions import Fraction

getcontext().prec = 100
root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
program = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "build", "eulervop")
precision = sys.argv[2] if len(sys.argv) > 2 else "mpfr:200"
groups = {"radius": ["Omega1", "Omega2", "Omega3", "y1", "y2", "y3"], "radius_omega": ["omega1", "omega2", "omega3"],
          "radius_q": ["q0", "q1", "q2", "q3"]}


def read(path):
    with open(path) as f:
        lines = f.readlines()
    header = [l for l in lines if l.startswith("#")]
    rows = list(csv.reader(l for l in lines if not l.startswith("#")))
    return header, rows[0], rows[1:]


def binary128(text):
    """The binary128 number (113-bit significand, to nearest, ties to even) a decimal rounds to,
    as an exact decimal."""
    f = Fraction(Decimal(text))
    if f == 0:
        return "0"
    e = f.numerator.bit_length() - f.denominator.bit_length()
    while Fraction(2) ** e > abs(f):
        e -= 1
    while Fraction(2) ** (e + 1) <= abs(f):
        e += 1
    k = 112 - e
    m = f * Fraction(2) ** k
    n, rest = divmod(m.numerator, m.denominator)
    if 2 * rest > m.denominator or (2 * rest == m.denominator and n % 2):
        n += 1
    if k <= 0:
        return str(n * 2 ** -k)
    digits = str(abs(n) * 5 ** k).rjust(k + 1, "0")
    return ("-" if n < 0 else "") + digits[:-k] + "." + digits[-k:]


def reference_rows(scene, flags, times, work):
    rows = []
    for first in range(0, len(times), 200):  # the command line's length
        out = os.path.join(work, "run.csv")
        run = subprocess.run([program, "reference", scene, *flags, "--precision", precision, "--times",
                              ",".join(times[first:first + 200]), "--quiet", "--out", out],
                             cwd=root, capture_output=True, text=True)
        if run.returncode != 0:
            raise RuntimeError(run.stderr.strip())
        header_names, part = read(out)[1:]
        rows += part
    return header_names, rows


def main():
    failed = False
    with tempfile.TemporaryDirectory() as work:
        for name in sorted(os.listdir(os.path.join(root, "data", "reference"))):
            header, names, rows = read(os.path.join(root, "data", "reference", name))
            command = [l.split(": ", 1)[1] for l in header if l.startswith("# command:")][0]
            args = shlex.split(command)[2:]
            flags, i = [], 1
            while i < len(args):  # the scene's own flags, without the sample count and the checks
                if args[i] in ("--verify", "--certify"):
                    i += 1
                elif args[i] == "--samples":
                    i += 2
                else:
                    flags.append(args[i])
                    i += 1
            ref_names, ref = reference_rows(args[0], flags, [binary128(r[0]) for r in rows], work)
            report = []
            for radius, columns in groups.items():
                if radius not in names or (radius == "radius" and "omega1" in names):
                    continue
                columns = [c for c in columns if c in names]
                worst = Decimal(0)
                for a, b in zip(rows, ref):
                    error = sum((Decimal(a[names.index(c)]) - Decimal(b[ref_names.index(c)])) ** 2
                                for c in columns).sqrt()
                    bound = Decimal(a[names.index(radius)])
                    failed |= error > bound
                    if bound > 0:
                        worst = max(worst, error / bound)
                report.append(f"{radius} {float(worst):.6f}")
            print(f"{name}: largest error/radius {', '.join(report)}", flush=True)
    if failed:
        print("a row's error exceeds its radius", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
