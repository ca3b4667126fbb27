#!/usr/bin/env python3
"""Draws the regime map of an eulervop map: for each torque scale (columns) and max-error level
(rows), the speed-up of the cheapest VOP configuration over the cheapest configuration of the
direct Euler equations, as a colour (log2 scale: blue where VOP is faster, red where Euler is)
with the factor and both configurations written in the cell. Cells that only one side reaches
are grey and say which. Writes regime_map.png and regime_map.svg.

Usage: tools/plot_regime_map.py MAP_DIR
Needs matplotlib (Debian: apt-get install python3-matplotlib)."""
import json
import math
import os

import plot_common


def short(config):
    """'dop853 tol 1e-9' -> 'dop853 1e-9'; 'rk8 K/25' stays."""
    return config.replace(" tol ", " ")


def main() -> int:
    out_dir, plt = plot_common.setup("plot_regime_map", "MAP_DIR")
    from matplotlib.colors import TwoSlopeNorm
    with open(os.path.join(out_dir, "summary.json")) as f:
        s = json.load(f)
    scales = s["scales"]
    levels = s["levels"]
    nx, ny = len(scales), len(levels)
    values = [[math.nan] * nx for _ in range(ny)]
    texts = [[""] * nx for _ in range(ny)]
    for x, scale in enumerate(scales):
        for cell in scale["cells"]:
            y = levels.index(cell["level"])
            by = cell["by_formulation"]
            euler = by.get("euler")
            vop = by.get(cell["best_vop"]) if cell["best_vop"] else None
            if cell["speedup"] is not None:
                values[y][x] = math.log2(cell["speedup"])
                texts[y][x] = (f"{cell['speedup']:.2f}x\n{cell['best_vop']} {short(vop['configuration'])}"
                               f"\neuler {short(euler['configuration'])}")
            elif vop is not None:
                texts[y][x] = f"only VOP\n{cell['best_vop']} {short(vop['configuration'])}"
            elif euler is not None:
                texts[y][x] = f"only Euler\neuler {short(euler['configuration'])}"
            else:
                texts[y][x] = "not reached"

    finite = [abs(v) for row in values for v in row if not math.isnan(v)]
    span = max([1.0] + finite)
    fig, ax = plt.subplots(figsize=(2.6 * nx + 2.2, 1.15 * ny + 2.2))
    cmap = plt.get_cmap("RdBu").copy()
    cmap.set_bad("0.88")
    image = ax.imshow(values, cmap=cmap, norm=TwoSlopeNorm(vcenter=0, vmin=-span, vmax=span),
                      aspect="auto", origin="upper")
    for y in range(ny):
        for x in range(nx):
            dark = not math.isnan(values[y][x]) and abs(values[y][x]) > 0.6 * span
            ax.text(x, y, texts[y][x], ha="center", va="center", fontsize=7,
                    color="white" if dark else "black")
    ax.set_xticks(range(nx))
    ax.set_xticklabels([f"{sc['scale_text']}\nG = {sc['torque']}" for sc in scales], fontsize=8)
    ax.set_yticks(range(ny))
    ax.set_yticklabels([f"{lv:.0e}" for lv in levels])
    ax.set_xlabel("torque scale (the scene's G times the scale)")
    ax.set_ylabel("max Eq. 20 error over the span <=")
    bar = fig.colorbar(image, ax=ax, fraction=0.04, pad=0.02)
    bar.set_label(r"$\log_2$ (Euler time / VOP time): > 0 where VOP pays")
    ax.set_title(f"Where VOP pays: scene {s['scene']}, to {plot_common.span_text(s, s['tau_end'])}, runs in double\n"
                 f"cheapest of fixed steps and tolerances, all methods; reference {s['precision']}\n"
                 f"{s['timing']}", fontsize=9)
    fig.tight_layout()
    plot_common.save(fig, out_dir, "regime_map")
    return 0


if __name__ == "__main__":
    plot_common.run(main)
