#!/usr/bin/env bash
# Installs, builds (when needed) and runs eulervop. With no arguments it runs the main job on the
# embedded default scene (the paper's): the quad reference, the double-precision VOP and Euler
# runs, and their Eq. 20 errors with the paper's Fig. 1, in ./eulervop-report/.
# With arguments they go to eulervop itself, e.g. tools/run.sh reference --out ref.csv
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${EULERVOP_BUILD_DIR:-$root/build}
EULERVOP_WITH_PLOTS=1 "$root/tools/build.sh" eulervop
if (($# == 0)); then
  set -- report
fi
exec "$build/eulervop" "$@"
