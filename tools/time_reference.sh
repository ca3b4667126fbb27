#!/usr/bin/env bash
# Whole-process wall times of `eulervop reference` on the cases of docs/benchmarks.md ("Reference
# speed"), with the same-run peer: Boost.Odeint bulirsch_stoer<float128> at tol 1e-28 on the
# paper scene, timed by bench_reference --targets in this same invocation. It only measures:
# nothing is asserted.
#
# Usage: tools/time_reference.sh [REPEAT]        (default 3; each figure is the median)
#   EULERVOP=path   the program (default build/eulervop)
#   OLD=path        an older build to time side by side, run alternately with the new one
#   BENCH=path      bench_reference (default build/benchmarks/bench_reference; skipped if absent)
#   LONG_TAU=1e4    the span of the long-bounded case
# Each case also prints the error its output reached against a higher precision: `--verify`
# (one precision up, 64 more bits) in a separate, untimed run.
set -euo pipefail
shopt -s inherit_errexit  # a failed run inside $(...) stops the script instead of timing an error
root=$(cd "$(dirname "$0")/.." && pwd)
eulervop=${EULERVOP:-$root/build/eulervop}
bench=${BENCH:-$root/build/benchmarks/bench_reference}
old=${OLD:-}
repeat=${1:-3}
long_tau=${LONG_TAU:-1e4}
[[ -x "$eulervop" ]] || { echo "$eulervop: not built (cmake --build build --target eulervop)" >&2; exit 2; }
[[ -z "$old" || -x "$old" ]] || { echo "OLD=$old: not an executable" >&2; exit 2; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

cases=("paper, quad, default|"
       "paper, mpfr:256 tol 1e-60|--precision mpfr:256 --tolerance 1e-60"
       "long-bounded tau=$long_tau, 11 samples, quad|$root/data/scenes/hard/long-bounded.toml --tau-end $long_tau --samples 11")

# Wall time (s) of one run of a program on a case.
run_time() {
  local program=$1 args=$2 t0 t1
  t0=$(date +%s.%N)
  # shellcheck disable=SC2086
  "$program" reference $args --out "$work/out.csv"
  t1=$(date +%s.%N)
  awk -v a="$t0" -v b="$t1" 'BEGIN {print b - a}'
}
median() { sort -g | awk '{a[NR] = $1} END {printf "%.3f", a[int((NR + 1) / 2)]}'; }

printf '%-45s %10s %10s %8s %12s\n' case "new (s)" "old (s)" "old/new" "error"
for c in "${cases[@]}"; do
  name=${c%%|*}
  args=${c#*|}
  new_times=() old_times=()
  for ((i = 0; i < repeat; ++i)); do  # alternately, so that both see the same machine
    new_times+=("$(run_time "$eulervop" "$args")")
    [[ -z "$old" ]] || old_times+=("$(run_time "$old" "$args")")
  done
  new_t=$(printf '%s\n' "${new_times[@]}" | median)
  old_t=-
  ratio=-
  if [[ -n "$old" ]]; then
    old_t=$(printf '%s\n' "${old_times[@]}" | median)
    ratio=$(awk -v a="$old_t" -v b="$new_t" 'BEGIN {printf "%.2f", a / b}')
  fi
  # shellcheck disable=SC2086
  "$eulervop" reference $args --verify --out "$work/verify.csv"
  err=$(sed -n 's/^# estimated_max_error: //p' "$work/verify.csv")
  printf '%-45s %10s %10s %8s %12s\n' "$name" "$new_t" "$old_t" "$ratio" "$err"
done

if [[ -x "$bench" ]]; then
  echo
  echo "Same run, in process (bench_reference --targets; error against mpfr:320):"
  "$bench" --targets 2>/dev/null
else
  echo "($bench not built: no Odeint peer; cmake --build build --target bench_reference)"
fi
