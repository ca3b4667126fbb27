#!/usr/bin/env bash
# Our reference against a peer of bench_problems, whole processes: `eulervop reference SCENE
# [ARGS]` (parsing the scene, integrating, writing the CSV) and `bench_problems --only PEER SCENE`
# (parsing the scene, integrating the same samples in float128: PEER = taylor, the Taylor-series
# peer of benchmarks/taylor_peer.hpp, or odeint, Boost.Odeint's bulirsch_stoer at 1e-28), run
# alternately; prints the medians and their ratio (docs/benchmarks.md). It only measures: nothing
# is asserted.
#
# Usage: tools/time_vs_peer.sh [REPEAT] PEER SCENE.toml [REFERENCE ARGS...]   (default 5 runs)
#   e.g. tools/time_vs_peer.sh 5 taylor data/scenes/paper-fig1.toml
#        tools/time_vs_peer.sh 5 odeint data/scenes/paper-fig1.toml --precision mpfr:256 --tolerance 1e-60
#   EULERVOP=path, BENCH_PROBLEMS=path   the programs (default build/eulervop, build/benchmarks/bench_problems)
set -euo pipefail
shopt -s inherit_errexit  # a failed run inside $(...) stops the script instead of timing an error
root=$(cd "$(dirname "$0")/.." && pwd)
eulervop=${EULERVOP:-$root/build/eulervop}
bench=${BENCH_PROBLEMS:-$root/build/benchmarks/bench_problems}
repeat=5
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

seconds() {  # wall seconds of one run of the command
  local start end
  start=$(date +%s.%N)
  "$@" >/dev/null
  end=$(date +%s.%N)
  awk -v a="$start" -v b="$end" 'BEGIN {print b - a}'
}
median() { sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }

ours=() theirs=()
for ((i = 0; i < repeat; i++)); do
  ours+=("$(seconds "$eulervop" reference "$scene" --quiet "$@" --out "$work/out.csv")")
  theirs+=("$(seconds "$bench" --only "$peer" "$scene")")
done
o=$(printf '%s\n' "${ours[@]}" | median)
t=$(printf '%s\n' "${theirs[@]}" | median)
printf '%s %s: eulervop reference %.3f s; %s peer %.3f s; ratio %.3f (medians of %d, alternating)\n' \
  "$scene" "$*" "$o" "$peer" "$t" "$(awk -v a="$o" -v b="$t" 'BEGIN {print a / b}')" "$repeat"
