"""A work-precision study: scipy.integrate.solve_ivp's methods on the SciML rigid body
(y1' = -2 y2 y3, y2' = 1.25 y1 y3, y3' = -0.5 y1 y2 + 0.25 sin(t)^2, y(0) = (1, 0, 0.9)), each
over a ladder of tolerances (atol = rtol), judged at the reference's sample times against
eulervop's certified reference. Per run: the max error (the two-norm of y - y_ref at the worst
sample, eulervop.check's max_error), the cost in calls of the right-hand side, and the wall time.
Copy it and put your own solver in `integrate`.

Run: PYTHONPATH=build/python /usr/bin/python3 examples/python/work_precision.py \
         [--plot docs/scipy_work_precision.png] [--full] [--scene sciml-rigid-body-100]
"""
import argparse
import math
import os
import time
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

import eulervop

# Both scenes are this system; they differ in the span (t = 10, 101 samples; t = 100, 1001).
SCENES = ("sciml-rigid-body", "sciml-rigid-body-100")
Y0 = (1.0, 0.0, 0.9)
METHODS = ("DOP853", "RK45", "Radau", "LSODA")
SMALL_LADDER = tuple(10.0 ** -k for k in (4, 6, 8, 10))
FULL_LADDER = tuple(10.0 ** -k for k in range(3, 14))


def rigid_body(forcing=lambda t: 0.25 * math.sin(t) ** 2):
    """The right-hand side; `forcing` is y3's term (the tests plant a bug there)."""
    def rhs(t, y):
        return np.array([-2.0 * y[1] * y[2], 1.25 * y[0] * y[2], -0.5 * y[0] * y[1] + forcing(t)])
    return rhs


class Counted:
    """Counts every call of the right-hand side. solve_ivp's nfev leaves out the calls that
    Radau's and BDF's finite-difference Jacobians make (one per column, at least, for each of
    njev), so the cost of an implicit method is counted here, where it is spent."""

    def __init__(self, rhs):
        self.rhs, self.calls = rhs, 0

    def __call__(self, t, y):
        self.calls += 1
        return self.rhs(t, y)


@dataclass
class Run:
    method: str
    rtol: float
    steps: int      # accepted steps
    calls: int      # calls of the right-hand side, finite-difference Jacobians included
    nfev: int       # solve_ivp's own counts
    njev: int
    seconds: float  # best of the repeats
    max_error: float


def certified_reference(scene_name):
    return eulervop.reference(eulervop.problems()[scene_name], certify=True)


def integrate(ref, method, rtol, rhs, dense_output=False):
    """solve_ivp from the reference's first sample time to its last, at atol = rtol, the state
    at every sample time of the reference."""
    sol = solve_ivp(rhs, (ref.t[0], ref.t[-1]), Y0, method=method, t_eval=ref.t, rtol=rtol,
                    atol=rtol, dense_output=dense_output)
    if not sol.success:
        raise RuntimeError(f"{method} at rtol={rtol:g}: {sol.message}")
    return sol


def solve(ref, method, rtol, rhs, repeats=3):
    """One rung: `integrate` timed `repeats` times, the last run judged."""
    seconds = math.inf
    for _ in range(repeats):
        counted = Counted(rhs)
        start = time.perf_counter()
        sol = integrate(ref, method, rtol, counted)
        seconds = min(seconds, time.perf_counter() - start)
    # The steps, from a run that keeps every step's interpolant: the same steps and values,
    # though more calls (every step's dense output is built, not only those holding a sample).
    dense = integrate(ref, method, rtol, rhs, dense_output=True)
    if not np.array_equal(dense.y, sol.y):
        raise RuntimeError(f"{method} at rtol={rtol:g}: dense_output=True changed the solution")
    # Against the Reference itself (not the scene): every row of sol is one of its samples.
    result = eulervop.check(ref, sol.t, sol.y.T)
    return Run(method, rtol, len(dense.sol.ts) - 1, counted.calls, sol.nfev, sol.njev, seconds,
               result.max_error)


def ladder(ref, method, rtols, rhs=None, repeats=3):
    return [solve(ref, method, rtol, rhs or rigid_body(), repeats) for rtol in rtols]


def slope(runs, work="calls"):
    """Least-squares slope of log(error) against log(work), work "calls" or "steps". Against the
    steps it tends to -p for a method of order p (error ~ h^p, steps ~ 1/h over a fixed span);
    against the calls it is steeper where the calls per step fall as the tolerance tightens."""
    x = [getattr(r, work) for r in runs]
    return np.polyfit(np.log(x), np.log([r.max_error for r in runs]), 1)[0]


def print_table(results, radius):
    print(f"{'method':<7} {'rtol':>7} {'steps':>6} {'calls':>7} {'nfev':>7} {'njev':>5} "
          f"{'seconds':>8} {'max error':>10}")
    for runs in results.values():
        for r in runs:
            print(f"{r.method:<7} {r.rtol:7.0e} {r.steps:6d} {r.calls:7d} {r.nfev:7d} {r.njev:5d} "
                  f"{r.seconds:8.4f} {r.max_error:10.3e}")
    for work in ("calls", "steps"):
        print(f"slope of log(error) vs log({work}): "
              + ", ".join(f"{m} {slope(runs, work):.2f}" for m, runs in results.items()))
    print(f"largest certified radius of the reference: {radius:.3e}")


def plot(results, scene_name, radius, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (by_calls, by_time) = plt.subplots(1, 2, figsize=(11, 4.5), sharey=True)
    for method, runs in results.items():
        errors = [r.max_error for r in runs]
        by_calls.loglog([r.calls for r in runs], errors, "o-", label=method)
        by_time.loglog([r.seconds for r in runs], errors, "o-", label=method)
    by_calls.set_xlabel("calls of the right-hand side")
    by_time.set_xlabel("wall time, s (best of the repeats)")
    by_calls.set_ylabel("max error (2-norm) against the certified reference")
    for ax in (by_calls, by_time):
        ax.grid(True, which="both", alpha=0.3)
    by_calls.legend()
    fig.suptitle(f"scipy solve_ivp on {scene_name}, atol = rtol; "
                 f"the reference's largest certified radius {radius:.1e}")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def check_plot_path(parser, path):
    """Before the runs, not after: a directory that is not there, a format matplotlib lacks."""
    from matplotlib.figure import Figure
    formats = Figure().canvas.get_supported_filetypes()
    if not os.path.isdir(os.path.dirname(path) or "."):
        parser.error(f"--plot {path}: no directory {os.path.dirname(path)}")
    if os.path.splitext(path)[1][1:].lower() not in formats:
        parser.error(f"--plot {path}: not one of matplotlib's formats ({', '.join(formats)})")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--plot", metavar="FILE", help="draw the two panels into FILE (png, svg)")
    parser.add_argument("--full", action="store_true",
                        help="rtol 1e-3 .. 1e-13 and BDF too (default: 1e-4 .. 1e-10)")
    parser.add_argument("--scene", choices=SCENES, default=SCENES[0])
    parser.add_argument("--repeats", type=int, default=3, help="timed runs per rung (default 3)")
    args = parser.parse_args()
    if args.repeats < 1:
        parser.error(f"--repeats: must be at least 1, got {args.repeats}")
    if args.plot:
        check_plot_path(parser, args.plot)
    ref = certified_reference(args.scene)
    methods = METHODS + ("BDF",) if args.full else METHODS
    rtols = FULL_LADDER if args.full else SMALL_LADDER
    results = {m: ladder(ref, m, rtols, repeats=args.repeats) for m in methods}
    radius = float(np.max(ref.radius))
    print_table(results, radius)
    # Each error is known to +- the radius: below 1e-4 of it, the 4 digits printed are certain.
    smallest = min(r.max_error for runs in results.values() for r in runs)
    if not radius < 1e-4 * smallest:
        raise SystemExit(f"the reference's radius {radius:.3e} is not far below the smallest "
                         f"error {smallest:.3e}: the errors are not resolved")
    if args.plot:
        plot(results, args.scene, radius, args.plot)


if __name__ == "__main__":
    main()
