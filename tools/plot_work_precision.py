#!/usr/bin/env python3
"""Draws the work-precision diagram of an eulervop sweep: log10 of the max Eq. 20 error over
the span against log10 of the wall time, one line per formulation x method x kind with a marker
at each step or tolerance (DiffEqDevTools style): fixed-step runs as solid lines with filled
markers, adaptive runs (a tolerance ladder) dashed with open markers. Diverged runs (no error)
are left out. Writes work_precision.png and work_precision.svg.

Usage: tools/plot_work_precision.py SWEEP_DIR
Needs matplotlib (Debian: apt-get install python3-matplotlib)."""
import csv
import json
import math
import os

import plot_common

LEVELS = (1e-4, 1e-6, 1e-8, 1e-10, 1e-12)
MARKERS = ("o", "s", "^", "D", "v", "P", "X", "*")


def main() -> int:
    out_dir, plt = plot_common.setup("plot_work_precision", "SWEEP_DIR")
    with open(os.path.join(out_dir, "sweep.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    title = "Work-precision"
    summary = os.path.join(out_dir, "summary.json")
    if os.path.exists(summary):
        with open(summary) as f:
            s = json.load(f)
        title += (f": scene {s.get('scene', '')}, to {plot_common.span_text(s, s['reference']['tau_end'])}"
                  f"\nreference {s['reference']['precision']}; time = min of {s.get('repeat', '?')} run(s)"
                  + (f", --jobs {s['jobs']} (parallel)" if s.get("jobs", 1) > 1 else ""))

    formulations, methods = [], []
    for r in rows:
        if r["formulation"] not in formulations:
            formulations.append(r["formulation"])
        if r["method"] not in methods:
            methods.append(r["method"])
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]

    fig, ax = plt.subplots(figsize=(10, 7))
    for level in LEVELS:
        ax.axhline(math.log10(level), color="0.85", linewidth=0.6, zorder=0)
    for fi, form in enumerate(formulations):
        for mi, method in enumerate(methods):
            for adaptive in (False, True):
                pts = []
                for r in rows:
                    if r["formulation"] != form or r["method"] != method or (r["tol"] != "") != adaptive:
                        continue
                    if r["diverged"] == "true" or r["max_error"] == "":
                        continue  # diverged: no error number, never plotted as a result
                    e, t = float(r["max_error"]), float(r["seconds"])
                    if e > 0 and t > 0:
                        rung = float(r["tol"]) if adaptive else float(r["h"])
                        pts.append((rung, math.log10(t), math.log10(e)))
                if not pts:
                    continue
                pts.sort(reverse=True)  # loosest first
                color = colors[fi % len(colors)]
                ax.plot([p[1] for p in pts], [p[2] for p in pts], color=color,
                        linestyle="--" if adaptive else "-", marker=MARKERS[mi % len(MARKERS)],
                        markerfacecolor="none" if adaptive else color,
                        markersize=4, linewidth=1.0,
                        label=f"{form} / {method}" + (" (adaptive)" if adaptive else ""))
    ax.set_xlabel(r"$\log_{10}$ wall time [s]")
    ax.set_ylabel(r"$\log_{10}$ max error over the span, $\|\Omega - \Omega^*\|_2$ (Eq. 20)")
    ax.set_title(title, fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, ncol=max(1, len(formulations)), loc="best")
    fig.tight_layout()
    plot_common.save(fig, out_dir, "work_precision")
    return 0


if __name__ == "__main__":
    plot_common.run(main)
