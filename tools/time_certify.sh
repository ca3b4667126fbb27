#!/usr/bin/env bash
# The cost of --certify: whole-process wall times of `eulervop reference SCENE` with and without
# --certify, run alternately, and the ratio of the medians (docs/certified.md). It only measures:
# nothing is asserted.
#
# Usage: tools/time_certify.sh [REPEAT] [-- REFERENCE ARGS...]   (default 3 runs; the paper scene)
#   EULERVOP=path   the program (default build/eulervop)
set -euo pipefail
shopt -s inherit_errexit  # a failed run inside $(...) stops the script instead of timing an error
root=$(cd "$(dirname "$0")/.." && pwd)
eulervop=${EULERVOP:-$root/build/eulervop}
repeat=3
if [[ $# -gt 0 && "$1" != "--" ]]; then repeat=$1; shift; fi
[[ $# -gt 0 && "$1" == "--" ]] && shift
[[ -x "$eulervop" ]] || { echo "$eulervop: not built (cmake --build build --target eulervop)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

seconds() {  # wall seconds of one run of the program with the given arguments
  local start end
  start=$(date +%s.%N)
  "$eulervop" reference "$@" --out "$work/out.csv" >/dev/null
  end=$(date +%s.%N)
  awk -v a="$start" -v b="$end" 'BEGIN {print b - a}'
}
median() { sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }

plain=() certified=()
for ((i = 0; i < repeat; i++)); do
  plain+=("$(seconds "$@")")
  certified+=("$(seconds "$@" --certify)")
done
p=$(printf '%s\n' "${plain[@]}" | median)
c=$(printf '%s\n' "${certified[@]}" | median)
radius=$(grep '^# certified_max_error:' "$work/out.csv" | cut -d' ' -f3)
printf 'reference %s: %.3f s; with --certify %.3f s; ratio %.2f; certified_max_error %s\n' \
  "${*:-(paper scene)}" "$p" "$c" "$(awk -v a="$c" -v b="$p" 'BEGIN {print a / b}')" "$radius"
