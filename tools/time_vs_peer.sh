#!/usr/bin/env bash
# Our reference against a peer of bench_problems, whole processes: `eulervop reference SCENE
# [ARGS]` (parsing the scene, integrating, writing the CSV) and `bench_problems --only PEER SCENE`
# (parsing the scene, integrating the same samples in float128: PEER = taylor, the Taylor-series
# peer of benchmarks/taylor_peer.hpp, or odeint, Boost.Odeint's bulirsch_stoer at 1e-28), run
# alternately; prints the medians of their CPU times (user + sys, from bash's `time`) and of
# their wall times, and the ratios of the medians (docs/benchmarks.md). CPU time is the measure on
# a shared machine, where other jobs stretch wall times. It only measures: nothing is asserted.
#
# Usage: tools/time_vs_peer.sh [REPEAT] PEER SCENE.toml [REFERENCE ARGS...]   (default 9 runs)
#   e.g. tools/time_vs_peer.sh 9 taylor data/scenes/paper-fig1.toml
#        tools/time_vs_peer.sh 9 odeint data/scenes/paper-fig1.toml --precision mpfr:256 --tolerance 1e-60
#   EULERVOP=path, BENCH_PROBLEMS=path   the programs (default build/eulervop, build/benchmarks/bench_problems)
set -euo pipefail
shopt -s inherit_errexit  # a failed run inside $(...) stops the script instead of timing an error
root=$(cd "$(dirname "$0")/.." && pwd)
eulervop=${EULERVOP:-$root/build/eulervop}
bench=${BENCH_PROBLEMS:-$root/build/benchmarks/bench_problems}
repeat=9
if [[ $# -gt 0 && "$1" =~ ^[0-9]+$ ]]; then repeat=$1; shift; fi
[[ $# -ge 2 && ( "$1" == taylor || "$1" == odeint ) ]] ||
  { echo "usage: tools/time_vs_peer.sh [REPEAT] taylor|odeint SCENE.toml [REFERENCE ARGS...]" >&2; exit 2; }
peer=$1
scene=$2
shift 2
[[ -x "$eulervop" ]] || { echo "$eulervop: not built (cmake --build build --target eulervop)" >&2; exit 2; }
[[ -x "$bench" ]] || { echo "$bench: not built (cmake --build build --target bench_problems)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

times_of() {  # "WALL CPU" seconds of one run of the command (CPU = user + sys, children included)
  local TIMEFORMAT='%R %U %S' t
  if ! t=$( { time "$@" >/dev/null 2>"$work/stderr"; } 2>&1 ); then
    cat "$work/stderr" >&2
    echo "time_vs_peer: failed: $*" >&2
    exit 1
  fi
  awk '{print $1, $2 + $3}' <<<"$t"
}
median() { sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }

ours=() theirs=()
for ((i = 0; i < repeat; i++)); do
  ours+=("$(times_of "$eulervop" reference "$scene" --quiet "$@" --out "$work/out.csv")")
  theirs+=("$(times_of "$bench" --only "$peer" "$scene")")
done
median_of() { printf '%s\n' "${@:2}" | awk -v c="$1" '{print $c}' | median; }
ow=$(median_of 1 "${ours[@]}") oc=$(median_of 2 "${ours[@]}")
tw=$(median_of 1 "${theirs[@]}") tc=$(median_of 2 "${theirs[@]}")
printf '%s%s: CPU eulervop reference %.3f s, %s peer %.3f s, ratio %.3f; wall %.3f s, %.3f s, ratio %.3f' \
  "$scene" "${*:+ $*}" "$oc" "$peer" "$tc" "$(awk -v a="$oc" -v b="$tc" 'BEGIN {print a / b}')" \
  "$ow" "$tw" "$(awk -v a="$ow" -v b="$tw" 'BEGIN {print a / b}')"
printf ' (medians of %d, alternating)\n' "$repeat"
