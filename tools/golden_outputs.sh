#!/usr/bin/env bash
# Runs a fixed set of eulervop invocations with one binary and keeps every output, stdout and
# stderr, and exit code, with the fields that depend on timing masked. Two binaries' folders then
# compare with `diff -r`: the check behind every "outputs byte-identical" claim of a refactor.
#
# Usage: tools/golden_outputs.sh EULERVOP_BINARY OUT_DIR [--quick]
#   e.g. tools/golden_outputs.sh build-before/eulervop /tmp/g-before
#        tools/golden_outputs.sh build/eulervop /tmp/g-after && diff -r /tmp/g-before /tmp/g-after
# It covers reference (every shipped scene, each precision, --verify, --certify, stdout), report
# (fixed and --tols, --reference, json), sweep, map, check (scene, file, failing bar, bad file),
# batch, and bad inputs. What depends on measured cost (the cheapest configurations, the regime
# map, and sweep's and map's summaries and tables) is compared by its line count; their per-run
# rows (sweep.csv, runs.csv) are compared whole. --quick leaves
# out the slow cases (mpfr:256 at 1e-60, --certify on both paths, sweep, map): about 1 minute instead of 5.
set -uo pipefail
bin=$(realpath "$1")
out=$(realpath -m "$2")
quick=${3:-}
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
rm -rf "$out"
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

mask() {  # timing fields: wall seconds, run seconds, the seconds column of the tables
  sed -E \
    -e "s#$work#WORK#g" \
    -e 's/(wall_seconds[a-z_]*: )[0-9.e+-]+/\1#/' \
    -e 's/("(seconds|wall_seconds|reference_seconds|total_seconds)": )[0-9.e+-]+/\1#/g' \
    -e 's/(computed, )[0-9.]+ s/\1# s/' \
    -e 's/(in |after )[0-9.]+ ?s\b/\1# s/g' \
    -e 's/ (ok|up to date) \([0-9.]+ s\)/ \1 (# s)/' \
    "$@"
}

mask_table() {  # a text table with a right-aligned "seconds" column: that column's cells become #
  awk '
    / seconds / && end == 0 { end = index($0, " seconds ") + 7; print; next }
    end > 0 && length($0) >= end {
      head = substr($0, 1, end)
      if (match(head, /[0-9.]+$/)) { print substr(head, 1, RSTART - 1) "#" substr($0, end + 1); next }
    }
    { print }' "$@"
}

mask_csv() {  # a CSV with a seconds-like column: that column's cells become #
  awk -F, -v OFS=, '
    /^#/ { print; next }
    !hdr { for (i = 1; i <= NF; ++i) if ($i ~ /seconds|^wall/) cols[i] = 1; hdr = 1; print; next }
    { for (i in cols) $i = "#"; print }' "$@"
}

n=0
run() {  # run NAME ARGS...: stdout, stderr, exit code and every file written into work/NAME/
  local name=$1
  shift
  n=$((n + 1))
  local dir="$work/$name"
  mkdir -p "$dir"
  (cd "$dir" && "$bin" "$@" >stdout 2>stderr; echo $? >exit_code)
  local dest="$out/$name" timed=0
  [[ $name == sweep || $name == map ]] && timed=1
  mkdir -p "$dest"
  (cd "$dir" && find . -type f | sort) | while read -r f; do
    mkdir -p "$dest/$(dirname "$f")"
    if ((timed)) && [[ $f == ./out/summary.json || $f == ./stdout ]]; then
      wc -l <"$dir/$f" >"$dest/$f.lines"
      continue
    fi
    case "$f" in
      */cheapest.csv | */map.csv | *.png | *.svg) wc -l <"$dir/$f" >"$dest/$f.lines" ;;
      *.csv) mask "$dir/$f" | mask_csv >"$dest/$f" ;;
      *) mask "$dir/$f" | mask_table >"$dest/$f" ;;
    esac
  done
}

S=$root/data/scenes
for s in "$S"/*.toml "$S"/hard/*.toml; do
  run "reference-$(basename "$s" .toml)" reference "$s" --out ref.csv
done
run reference-default-stdout reference --samples 50
run reference-double reference --precision double --out ref.csv
run reference-mpfr160 reference --precision mpfr:160 --samples 200 --out ref.csv
run reference-verify reference --verify --samples 100 --out ref.csv
run reference-times reference --times 0,0.5,1,13.25,136 --out ref.csv
run report-default report --no-plot --out-dir out
run report-json report --no-plot --format json --out-dir out
run report-all-formulations report --no-plot --formulations euler,vop,vop-theta \
  --methods rk4,rkf45,dp45,rk8 --out-dir out
run report-tols report --no-plot --tols 1e-6,1e-9 --out-dir out
run report-reference-file report --no-plot --reference "$root/data/reference/paper-fig1.csv" \
  --step 0.0085 --out-dir out
for s in small-torque torque-free-k0.5 spacecraft-physical axisymmetric hard/crossing hard/k-above-one \
  hard/omega3-negative hard/small-k hard/c1-zero hard/near-separatrix-torque hard/near-symmetric; do
  run "report-${s//\//-}" report "$S/$s.toml" --no-plot --out-dir out
done
# attitude beside the rates (where the binary knows the scene; an older one reports its error)
run report-spacecraft-attitude report "$S/spacecraft-attitude.toml" --no-plot --out-dir out

# check: a trajectory made from the reference file with a known offset
traj=$work/traj.csv
awk -F, '/^#/ { next } !h { print; h = 1; next } { printf "%s,%.17g,%s,%s\n", $1, $2 + 1e-9, $3, $4 }' \
  "$root/data/reference/paper-fig1.csv" >"$traj"
head -200 "$traj" >"$work/traj-short.csv"
run check-scene check "$S/paper-fig1.toml" "$work/traj-short.csv" --tol 1e-6 --format json --errors-out e.csv
run check-file check "$root/data/reference/paper-fig1.csv" "$traj" --tol 1e-6
run check-failing-bar check "$root/data/reference/paper-fig1.csv" "$traj" --tol 1e-12
printf 'tau,Omega1,Omega2,Omega3\n0,1,2\n' >"$work/bad.csv"
run check-bad-trajectory check "$S/paper-fig1.toml" "$work/bad.csv"

run batch batch "$S/torque-free-k0.5.toml" "$S/hard/small-k.toml" --out-dir out --report --verify --jobs 1

printf 'name = "bad"\n[body]\ninertia = [2.0, 1.0, 1.0e400]\n' >"$work/bad-inertia.toml"
run bad-inertia reference "$work/bad-inertia.toml" --out ref.csv
run bad-precision reference --precision mpfr:1 --out ref.csv
run bad-step report --step -1 --no-plot --out-dir out
run bad-samples reference --samples 0 --out ref.csv

if [[ "$quick" != --quick ]]; then
  run reference-mpfr256-1e-60 reference --precision mpfr:256 --tolerance 1e-60 --samples 200 --out ref.csv
  run certify-paper reference --certify --out ref.csv
  run certify-spacecraft reference "$S/spacecraft-physical.toml" --certify --out ref.csv
  run certify-general-attitude reference "$S/spacecraft-attitude.toml" --certify --out ref.csv
  run certify-general-pd-slew reference "$S/attitude/pd-slew.toml" --certify --out ref.csv
  run certify-general-b5 reference "$S/problems/enright-pryce-b5.toml" --certify --out ref.csv
  run sweep sweep --jobs 1 --tau-end 20 --no-plot --out-dir out
  run map map --jobs 1 --tau-end 20 --torque-scales 1e-4,1 --no-plot --out-dir out
fi
echo "golden_outputs: $n invocations into $out" >&2
