#!/usr/bin/env bash
# Regenerates the shipped reference datasets in data/reference/ (docs/datasets.md).
#
#   tools/make_reference_datasets.sh [path/to/eulervop]     (default: build/eulervop)
#
# Every dataset is made by `eulervop reference ... --verify --certify`, so it carries an honest
# `# estimated_max_error` (one precision up) and a proven radius on every row
# (`# certified_max_error`, docs/certified.md), and its `# command:` line is the command below
# (run from the repository root, so the scene paths in it are relative). Sample counts are
# modest to keep data/reference/ at about a megabyte. Only the `# wall_seconds*` lines change
# from one regeneration to the next (same binary, same machine); tests/test_batch.cpp reruns
# torque-free-short.csv and compares its data rows byte for byte.
set -euo pipefail
cd "$(dirname "$0")/.."
eulervop=${1:-build/eulervop}
[[ -x $eulervop ]] || { echo "make_reference_datasets.sh: no eulervop binary at $eulervop (build first, or pass its path)" >&2; exit 2; }
out=data/reference
mkdir -p "$out"

# name | scene | extra flags
datasets=(
  "paper-fig1|data/scenes/paper-fig1.toml|--samples 501"
  "torque-free-short|data/scenes/torque-free-k0.5.toml|--tau-end 20 --samples 201"
  "torque-free-k0.5|data/scenes/torque-free-k0.5.toml|--samples 501"
  "spacecraft-physical|data/scenes/spacecraft-physical.toml|"
  "spacecraft-attitude|data/scenes/spacecraft-attitude.toml|"
  "axisymmetric|data/scenes/axisymmetric.toml|"
)
for scene in data/scenes/hard/*.toml; do
  name=$(basename "$scene" .toml)
  datasets+=("$name|$scene|--samples 501")
done
# The published test problems (docs/test-problems.md), at their scenes' own samples.
for scene in data/scenes/problems/*.toml; do
  datasets+=("$(basename "$scene" .toml)|$scene|")
done

# Torques of the attitude: the rates and q as one problem (docs/attitude.md).
for scene in data/scenes/attitude/*.toml; do
  datasets+=("$(basename "$scene" .toml)|$scene|")
done

for entry in "${datasets[@]}"; do
  IFS='|' read -r name scene flags <<<"$entry"
  echo "== $name: eulervop reference $scene $flags --verify --certify" >&2
  # shellcheck disable=SC2086  # $flags is a list of words
  "$eulervop" reference "$scene" $flags --verify --certify --out "$out/$name.csv"
done
du -ch "$out"/*.csv | tail -1 >&2
