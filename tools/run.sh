#!/usr/bin/env bash
# Installs, builds (when needed) and runs eulervop. With no arguments it runs the main job on the
# embedded default scene (the paper's): the quad reference, written to paper-fig1-reference.csv.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${EULERVOP_BUILD_DIR:-$root/build}
"$root/tools/build.sh" eulervop
if (($# == 0)); then
  set -- reference --out paper-fig1-reference.csv
fi
exec "$build/eulervop" "$@"
