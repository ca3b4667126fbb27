#!/usr/bin/env bash
# Wall time and peak resident memory of long `eulervop reference` runs (docs/benchmarks.md,
# "Memory"). The rows stream to disk and no segment is kept, so the peak should not grow with
# the span; this script shows it. It only measures: nothing is asserted. The CPU time (user)
# is the figure to compare on a busy machine.
#
# Usage: tools/measure_reference_memory.sh [TAU_END...]     (default: 1e4 1e5)
#   EULERVOP=path/to/eulervop (default build/eulervop), SCENE=... (default
#   data/scenes/hard/long-bounded.toml), SAMPLES=N (default 11), PRECISION=... (default: the
#   scene's, quad). Needs GNU time (/usr/bin/time; Debian package `time`). tau_end = 1e6 takes
#   about 15 minutes on one core.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
eulervop=${EULERVOP:-$root/build/eulervop}
scene=${SCENE:-$root/data/scenes/hard/long-bounded.toml}
samples=${SAMPLES:-11}
[[ -x /usr/bin/time ]] || { echo "needs GNU time at /usr/bin/time (apt-get install time)" >&2; exit 2; }
[[ -x "$eulervop" ]] || { echo "$eulervop: not built (cmake --build build --target eulervop)" >&2; exit 2; }
[[ $# -gt 0 ]] || set -- 1e4 1e5
precision=()
[[ -n "${PRECISION:-}" ]] && precision=(--precision "$PRECISION")

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
printf '%-10s %8s %10s %10s %10s %14s\n' tau_end samples segments "wall (s)" "cpu (s)" "peak RSS (MB)"
for tau in "$@"; do
  /usr/bin/time -o "$work/time" -f '%e %U %M' "$eulervop" reference "$scene" --tau-end "$tau" --samples "$samples" \
    "${precision[@]}" --out "$work/ref.csv"
  read -r seconds cpu kib <"$work/time"
  segments=$(sed -n 's/^# method: .* segments=\([0-9]*\).*/\1/p' "$work/ref.csv")
  awk -v t="$tau" -v n="$samples" -v s="$segments" -v w="$seconds" -v c="$cpu" -v k="$kib" \
    'BEGIN { printf "%-10s %8s %10s %10s %10s %14.1f\n", t, n, s, w, c, k / 1024 }'
done
