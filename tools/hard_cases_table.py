#!/usr/bin/env python3
"""Regenerates docs/hard-cases.md: for every scene in data/scenes/hard/,
runs

    eulervop report SCENE --methods rk4,rk8 --formulations euler,vop,vop-theta --no-plot

(`--formulations euler` for a scene that lists euler only: a body in the direct form of Eq. 1) at
the scene's own step ([run] step, K/200 of the initial modulus for the normalized scenes), reads
each summary.json and writes one table of final and max Eq. 20 error, divergence and the VOP
fallback bands (separatrix and small k) per scene x formulation x method.

Usage: tools/hard_cases_table.py [--binary PATH] [--scenes DIR] [--out FILE] [--keep DIR]
  --binary  the eulervop program (default: $EULERVOP_BUILD_DIR/eulervop, else build/eulervop)
  --scenes  the scene directory (default: data/scenes/hard)
  --out     the Markdown file written (default: docs/hard-cases.md)
  --keep    keep the report directories here (default: a temporary directory, removed)
Python 3 standard library only. Exit code: 0, or 1 if a report failed (its stderr is printed)."""
import argparse
import json
import os
import re
import shlex
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
METHODS = "rk4,rk8"
FORMULATIONS = "euler,vop,vop-theta"


def scene_description(path):
    """The scene's name and description (tomllib where available, else the two top-level keys)."""
    with open(path, "rb") as f:
        data = f.read()
    try:
        import tomllib
        t = tomllib.loads(data.decode("utf-8"))
        return t.get("name", ""), t.get("description", "")
    except ImportError:
        text = data.decode("utf-8")
        def key(k):
            m = re.search(r'^%s\s*=\s*"((?:[^"\\]|\\.)*)"' % k, text, re.M)
            return m.group(1).replace('\\"', '"') if m else ""
        return key("name"), key("description")


def sci(x, digits=2):
    return "-" if x is None else f"{x:.{digits}e}"


def bands_text(run):
    parts = []
    for key, what in (("separatrix_bands", "separatrix"), ("small_k_bands", "small-k")):
        bands = run.get(key) or []
        if not bands:
            continue
        shown = ", ".join(f"{a:.4g}..{b:.4g}" for a, b in bands[:3])
        more = f" +{len(bands) - 3} more" if len(bands) > 3 else ""
        parts.append(f"{what} {shown}{more}")
    if not parts:
        return ""
    extra = f"{run.get('direct_steps', 0)} direct steps"
    if run.get("regime_changes"):
        extra += f", {run['regime_changes']} regime change" + ("s" if run["regime_changes"] > 1 else "")
    return "; ".join(parts) + f" ({extra})"


def run_of(summary, formulation, method):
    for r in summary["runs"]:
        if r["formulation"] == formulation and r["method"] == method:
            return r
    return None


def acceptance(results):
    """The acceptance figures that this table measures, where their scenes are present: the bounds
    that tests/test_long_vop_theta.cpp and tests/test_vop_theta.cpp assert."""
    by_name = {name: summary for _, name, _, summary, _ in results}
    L = ["## Acceptance figures", ""]
    s = by_name.get("long-bounded")
    if s:
        e, v, t = (run_of(s, f, "rk4")["final_error"] for f in ("euler", "vop", "vop-theta"))
        L.append(f"- **Long bounded run** (`long-bounded`, rk4 at K/200, tau = 1e4): final error euler {sci(e)}, "
                 f"vop {sci(v)}, vop-theta {sci(t)}: vop-theta is {e / t:.0f}x smaller than euler and "
                 f"{v / t:.0f}x smaller than vop (required: >= 100x both).")
    s = by_name.get("crossing")
    if s:
        for m in ("rk4", "rk8"):
            e = run_of(s, "euler", m)["max_error"]
            parts = []
            for f in ("vop", "vop-theta"):
                r = run_of(s, f, m)
                bands = ", ".join(f"{a:.4g}..{b:.4g}" for a, b in r["separatrix_bands"]) or "none"
                parts.append(f"{f} {sci(r['max_error'])} ({r['max_error'] / e:.2g}x euler; band tau {bands})")
            L.append(f"- **Crossing** (`crossing`, {m}): max error euler {sci(e)}, " + ", ".join(parts)
                     + " (required: no NaN, band reported, VOP <= 10x euler).")
    if len(L) == 2:
        return []
    return L + [""]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    default_binary = os.path.join(os.environ.get("EULERVOP_BUILD_DIR", os.path.join(ROOT, "build")), "eulervop")
    ap.add_argument("--binary", default=default_binary)
    ap.add_argument("--scenes", default=os.path.join(ROOT, "data", "scenes", "hard"))
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "hard-cases.md"))
    ap.add_argument("--keep", default=None)
    args = ap.parse_args()

    scenes = sorted(f for f in os.listdir(args.scenes) if f.endswith(".toml"))
    if not scenes:
        print(f"hard_cases_table: no scenes in {args.scenes}", file=sys.stderr)
        return 1
    version = subprocess.run([args.binary, "--version"], capture_output=True, text=True).stdout.strip()

    work_ctx = tempfile.TemporaryDirectory(prefix="eulervop-hard-") if args.keep is None else None
    work = work_ctx.name if work_ctx else args.keep
    os.makedirs(work, exist_ok=True)
    results = []
    try:
        for f in scenes:
            path = os.path.join(args.scenes, f)
            stem = f[:-5]
            out_dir = os.path.join(work, stem)
            # A body in the direct form of Eq. 1 (its scene lists euler only) has no VOP runs.
            with open(path) as sf:
                euler_only = re.search(r'^formulations\s*=\s*\["euler"\]', sf.read(), re.M)
            cmd = [args.binary, "report", path, "--methods", METHODS, "--formulations",
                   "euler" if euler_only else FORMULATIONS,
                   "--no-plot", "--out-dir", out_dir]
            print(f"hard_cases_table: {stem} ...", file=sys.stderr, flush=True)
            t0 = time.monotonic()
            p = subprocess.run(cmd, capture_output=True, text=True)
            seconds = time.monotonic() - t0
            if p.returncode != 0:
                print(f"hard_cases_table: {stem}: exit code {p.returncode}\n{p.stderr}", file=sys.stderr)
                return 1
            with open(os.path.join(out_dir, "summary.json")) as s:
                summary = json.load(s)
            name, description = scene_description(path)
            results.append((f, name or stem, description, summary, seconds))
    finally:
        if work_ctx:
            work_ctx.cleanup()

    rel = lambda p: os.path.relpath(os.path.abspath(p), ROOT)
    # The build directory is the regenerator's choice; the command names it generically.
    regen = "tools/hard_cases_table.py [--binary BUILD_DIR/eulervop]"
    if os.path.abspath(args.scenes) != os.path.join(ROOT, "data", "scenes", "hard"):
        regen += f" --scenes {shlex.quote(rel(args.scenes))}"
    if os.path.abspath(args.out) != os.path.join(ROOT, "docs", "hard-cases.md"):
        regen += f" --out {shlex.quote(rel(args.out))}"

    L = []
    L.append("# Hard cases: Euler and VOP on the hard-case suite")
    L.append("")
    L.append("Generated by `tools/hard_cases_table.py`; do not edit by hand. Regenerate with")
    L.append("")
    L.append(f"    {regen}")
    L.append("")
    L.append("which runs, for every scene in `data/scenes/hard/`,")
    L.append("")
    L.append(f"    eulervop report data/scenes/hard/SCENE.toml --methods {METHODS} --formulations {FORMULATIONS} --no-plot")
    L.append("")
    L.append(f"({version}) and reads each `summary.json`. Every run is in double at the scene's fixed step")
    L.append("(`[run] step = \"K/200\"`: K of the initial modulus over 200 times the phase rate, the paper's")
    L.append("step; with k0 > 1 the reciprocal modulus; the value of h is in the table). Errors are Eq. 20")
    L.append("(two-norm of the Omega difference) against the quad Chebyshev-Picard reference that `report`")
    L.append("computes, at about `[span] samples` step points. *final* is the error at the last sample")
    L.append("reached (its tau if the run stopped early), *max* the largest over the samples, */ euler*")
    L.append("the final error over Euler's with the same method. *fallback* lists the stretches")
    L.append("(tau in..out) where a VOP run left its elements and took direct Euler steps")
    L.append("(docs/vop-strategies.md sections 4 and 5), as reported in `summary.json`")
    L.append("(`separatrix_bands`, `small_k_bands`, `direct_steps`, `regime_changes`).")
    L.append("")
    L.append("| scene | h | formulation | method | final error | max error | / euler | diverged | fallback |")
    L.append("|---|---|---|---|---|---|---|---|---|")
    for f, name, description, summary, seconds in results:
        runs = summary["runs"]
        euler_final = {r["method"]: r["final_error"] for r in runs if r["formulation"] == "euler"}
        euler_diverged = {r["method"]: r["diverged"] for r in runs if r["formulation"] == "euler"}
        first = True
        for r in runs:
            final = sci(r["final_error"])
            if r["diverged"] and r["final_tau"] is not None:
                final += f" (tau {r['final_tau']:.6g})"
            ratio = "-"
            e = euler_final.get(r["method"]) if not euler_diverged.get(r["method"]) else None
            if r["formulation"] != "euler" and e and r["final_error"] is not None:
                ratio = f"{r['final_error'] / e:.2g}"
            div = "no"
            if r["diverged"]:
                at = r["diverged_at"]
                div = f"at tau {at:.6g}: {r['why']}" if at is not None else f"yes: {r['why']}"
            L.append("| {} | {} | {} | {} | {} | {} | {} | {} | {} |".format(
                f"`{name}`" if first else "", f"{r['step']:.6g}" if first else "", r["formulation"], r["method"],
                final, sci(r["max_error"]), ratio, div, bands_text(r)))
            first = False
    L.append("")
    L.extend(acceptance(results))
    L.append("## The scenes")
    L.append("")
    for f, name, description, summary, seconds in results:
        ref = summary["reference"]
        L.append(f"### `{name}` (`data/scenes/hard/{f}`)")
        L.append("")
        L.append(description)
        L.append("")
        L.append(f"- step: {summary['step_rule']}")
        steps = max(r["steps"] for r in summary["runs"])
        L.append(f"- {steps} steps; reference {ref['precision']}"
                 + (f", {ref['segments']} segments" if ref.get("segments") is not None else "")
                 + (f", {ref['seconds']:.1f} s" if ref.get("seconds") is not None else "")
                 + f"; whole report {seconds:.1f} s")
        L.append("")
    text = "\n".join(L).rstrip("\n") + "\n"
    if re.search(r"\|\s*[-+]?(nan|inf)\b", text.lower()):  # a table cell (the prose says "no NaN")
        print("hard_cases_table: warning: a table cell is nan or inf", file=sys.stderr)
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    with open(args.out, "w") as out:
        out.write(text)
    print(f"hard_cases_table: wrote {args.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
