#!/usr/bin/env python3
"""Draws the paper's Fig. 1 from an eulervop report: log10 of the Eq. 20 two-norm error
against tau, one line per run. errors.csv holds either one column per run (fixed-step runs,
common tau) or one row per sample with formulation, method and tol (adaptive runs, each at its
own step points). Writes fig1.png and fig1.svg.

Usage: tools/plot_fig1.py REPORT_DIR
Needs matplotlib (Debian: apt-get install python3-matplotlib)."""
import csv
import json
import math
import os

import plot_common


def main() -> int:
    out_dir, plt = plot_common.setup("plot_fig1", "REPORT_DIR")
    with open(os.path.join(out_dir, "errors.csv"), newline="") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    header, data = rows[0], rows[1:]
    scene = ""
    summary = os.path.join(out_dir, "summary.json")
    if os.path.exists(summary):
        with open(summary) as f:
            scene = json.load(f).get("scene", "")
    fig, ax = plt.subplots(figsize=(8, 5))
    if header[:3] == ["formulation", "method", "tol"]:
        runs = {}
        for r in data:
            e = float(r[4])
            if e > 0:
                key = f"{r[0]} / {r[1]} / tol {float(r[2]):.0e}"
                runs.setdefault(key, ([], []))
                runs[key][0].append(float(r[3]))
                runs[key][1].append(math.log10(e))
        for label, (xs, ys) in runs.items():
            ax.plot(xs, ys, label=label, linewidth=0.8)
    else:
        for col in range(1, len(header)):
            xs, ys = [], []
            for r in data:
                if r[col] in ("", "nan"):
                    continue  # after divergence: no value, never plotted as a result
                e = float(r[col])
                if e > 0:
                    xs.append(float(r[0]))
                    ys.append(math.log10(e))
            label = header[col].replace("_", " / ")
            ax.plot(xs, ys, label=label, linewidth=0.8)
    ax.set_xlabel(r"$\tau$")
    ax.set_ylabel(r"$\log_{10} e$,  $e = \|\Omega - \Omega^*\|_2$ (Eq. 20)")
    ax.set_title("Two-norm errors: normalized Euler equations (non-VOP) and VOP"
                 + (f"\nscene: {scene}" if scene else ""))
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7 if len(ax.get_lines()) > 8 else 10)
    fig.tight_layout()
    plot_common.save(fig, out_dir, "fig1")
    return 0


if __name__ == "__main__":
    plot_common.run(main)
