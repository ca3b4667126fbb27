"""What the plotting scripts share: the one argument (the output folder of an eulervop command)
and matplotlib without a display. Exit codes: 2 for a wrong command line, 4 when matplotlib is
missing (the C++ caller reports the figure as skipped and keeps the data files)."""
import os
import sys


class PlotSetupError(Exception):
    def __init__(self, code: int, message: str):
        super().__init__(message)
        self.code = code


def setup(script: str, what: str):
    """Returns (out_dir, pyplot) or raises PlotSetupError. `what` names the argument in the usage line."""
    if len(sys.argv) != 2:
        raise PlotSetupError(2, f"usage: {script}.py {what}")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        raise PlotSetupError(4, f"{script}: matplotlib is not installed (apt-get install python3-matplotlib)")
    return sys.argv[1], plt


def span_text(summary: dict, tau_end: float) -> str:
    """'t = 600 s', 't = 100' or 'tau = 136': the span's end in the scene's own time, as the
    summary's "time" states it (a summary without it is in tau)."""
    time = summary.get("time")
    if not time:
        return f"tau = {tau_end:.6g}"
    unit = f" {time['unit']}" if time.get("unit") else ""
    return f"{time['name']} = {time['end']:.6g}{unit}"


def save(fig, out_dir: str, stem: str) -> None:
    """Writes stem.png and stem.svg in out_dir, each to a temporary name first and then renamed,
    so that a reader never sees half a figure."""
    for ext in ("png", "svg"):
        path = os.path.join(out_dir, f"{stem}.{ext}")
        tmp = path + ".tmp"
        fig.savefig(tmp, format=ext, dpi=120)
        os.replace(tmp, path)


def run(main) -> None:
    """Calls main() and exits with its code, or with the code of a setup error after printing it."""
    try:
        code = main()
    except PlotSetupError as e:
        print(e, file=sys.stderr)
        code = e.code
    sys.exit(code)
