#!/usr/bin/env python3
"""Draws the paper's Fig. 1 from an eulervop report: log10 of the Eq. 20 two-norm error
against tau, one line per run. errors.csv holds either one column per run (fixed-step runs,
common tau) or one row per sample with formulation, method and tol (adaptive runs, each at its
own step points). Writes fig1.png and fig1.svg.

A scene with an attitude ([initial] q) adds each run's attitude error, the rotation angle from
the reference's q to the run's in radians (docs/attitude-runs.md): fixed-step columns named
`<run>_attitude` after the runs' columns, or an `attitude_error` column after `error` in the
adaptive rows. It is drawn in a second panel below the first, with the same runs and colours.

A physical scene's errors.csv leads with t (s) and the rates' error (rad/s); its normalized
columns (`tau`, `<run>_normalized`, `error_normalized`) follow and are not drawn.

Usage: tools/plot_fig1.py REPORT_DIR
Needs matplotlib (Debian: apt-get install python3-matplotlib)."""
import csv
import json
import math
import os

import plot_common


def add_point(series, key, tau, cell):
    """Appends (tau, log10 cell) to series[key] when the cell holds a positive number."""
    if cell in ("", "nan"):
        return  # not reached, or after divergence: no value, never plotted as a result
    e = float(cell)
    if e > 0:
        xs, ys = series.setdefault(key, ([], []))
        xs.append(tau)
        ys.append(math.log10(e))


def read_series(header, data):
    """Returns (rates, attitude): dicts of label -> (taus, log10 errors), in the file's run order."""
    rates, attitude = {}, {}
    skipped = {"tau", "error_normalized"}
    if header[:3] == ["formulation", "method", "tol"]:
        has_attitude = len(header) > 5 and header[5] == "attitude_error"
        for r in data:
            key = f"{r[0]} / {r[1]} / tol {float(r[2]):.0e}"
            add_point(rates, key, float(r[3]), r[4])
            if has_attitude and len(r) > 5:
                add_point(attitude, key, float(r[3]), r[5])
    else:
        for col in range(1, len(header)):
            name = header[col]
            if name in skipped or name.endswith("_normalized"):
                continue
            target = attitude if name.endswith("_attitude") else rates
            label = (name[: -len("_attitude")] if target is attitude else name).replace("_", " / ")
            target.setdefault(label, ([], []))
            for r in data:
                add_point(target, label, float(r[0]), r[col])
    return rates, attitude


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
    rates, attitude = read_series(header, data)
    physical = header[0] == "t" or (len(header) > 3 and header[3] == "t")
    if attitude:
        fig, (ax, ax_q) = plt.subplots(2, 1, figsize=(8, 8.5), sharex=True)
    else:
        fig, ax = plt.subplots(figsize=(8, 5))
    colours = {}
    for label, (xs, ys) in rates.items():
        (line,) = ax.plot(xs, ys, label=label, linewidth=0.8)
        colours[label] = line.get_color()
    ax.set_ylabel(r"$\log_{10} e$,  $e = \|\omega - \omega^*\|_2$ (rad/s)" if physical
                  else r"$\log_{10} e$,  $e = \|\Omega - \Omega^*\|_2$ (Eq. 20)")
    ax.set_title("Two-norm errors: normalized Euler equations (non-VOP) and VOP"
                 + (f"\nscene: {scene}" if scene else ""))
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7 if len(ax.get_lines()) > 8 else 10)
    if attitude:
        for label, (xs, ys) in attitude.items():
            ax_q.plot(xs, ys, label=label, linewidth=0.8, color=colours.get(label))
        ax_q.set_ylabel(r"$\log_{10} \angle(q^*, q)$ (rad)")
        ax_q.set_title("Attitude errors: angle of the rotation from the reference's q to the run's",
                       fontsize=10)
        ax_q.grid(True, alpha=0.3)
        ax_q.set_xlabel("t (s)" if physical else r"$\tau$")
    else:
        ax.set_xlabel("t (s)" if physical else r"$\tau$")
    fig.tight_layout()
    plot_common.save(fig, out_dir, "fig1")
    return 0


if __name__ == "__main__":
    plot_common.run(main)
