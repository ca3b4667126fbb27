#!/usr/bin/env bash
# Times `check` on large trajectories, as whole processes: the command line on a CSV and the Python
# module on NumPy arrays, each against the SciML rigid body to t = 100 (its quad reference
# evaluated at every row). The trajectory is scipy's DOP853 at rtol = atol = 1e-12, at N equally
# spaced times. Prints, per size and way: the median wall time of RUNS runs, the user CPU and the
# peak memory (/usr/bin/time), and the processor.
#
# Usage: tools/time_check.sh [RUNS] [SIZES...]     e.g. tools/time_check.sh 5 100000 1000000
# Needs the build (tools/build.sh), /usr/bin/time (Debian package time) and scipy (tools/setup.sh).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${EULERVOP_BUILD_DIR:-$root/build}
runs=${1:-5}
shift || true
sizes=("$@")
((${#sizes[@]})) || sizes=(100000 1000000)
[[ -x /usr/bin/time ]] || { echo "time_check: needs /usr/bin/time (Debian package time)" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
scene=sciml-rigid-body-100
export PYTHONPATH="$build/python"

echo "processor: $(lscpu | sed -n 's/^Model name: *//p' | head -n 1), $(nproc) cores"
printf '%-10s %-8s %10s %10s %10s\n' rows way "median s" "user s" "peak MB"
for n in "${sizes[@]}"; do
  /usr/bin/python3 - "$n" "$work" <<'EOF'
import sys
import numpy as np
from scipy.integrate import solve_ivp

n, work = int(sys.argv[1]), sys.argv[2]
f = lambda t, y: [-2 * y[1] * y[2], 1.25 * y[0] * y[2], -0.5 * y[0] * y[1] + 0.25 * np.sin(t) ** 2]
t = np.linspace(0.0, 100.0, n)
sol = solve_ivp(f, (0.0, 100.0), [1.0, 0.0, 0.9], method="DOP853", rtol=1e-12, atol=1e-12, t_eval=t)
np.savez(f"{work}/traj.npz", t=sol.t, y=sol.y.T)
with open(f"{work}/traj.csv", "w") as out:  # each float64 as its shortest round-trip text
    out.write("t,y1,y2,y3\n")
    for ti, yi in zip(sol.t, sol.y.T):
        out.write(f"{ti!r},{yi[0]!r},{yi[1]!r},{yi[2]!r}\n")
EOF
  cat >"$work/check.py" <<EOF
import numpy as np, eulervop
d = np.load("$work/traj.npz")
assert eulervop.check("$scene", d["t"], d["y"], tol=1e-8).passed
EOF
  for way in cli python; do
    : >"$work/times"
    for ((r = 0; r < runs; ++r)); do
      if [[ $way == cli ]]; then
        /usr/bin/time -a -o "$work/times" -f '%e %U %M' "$build/eulervop" check "$scene" "$work/traj.csv" --tol 1e-8 \
          >/dev/null
      else
        /usr/bin/time -a -o "$work/times" -f '%e %U %M' /usr/bin/python3 "$work/check.py"
      fi
    done
    sort -n "$work/times" | awk -v n="$n" -v way="$way" '{ e[NR] = $1; u[NR] = $2; m[NR] = $3 }
      END { k = int((NR + 1) / 2); printf "%-10s %-8s %10.2f %10.2f %10.0f\n", n, way, e[k], u[k], m[k] / 1024 }'
  done
done
