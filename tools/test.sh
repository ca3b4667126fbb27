#!/usr/bin/env bash
# Installs, builds and runs the full default test suite. Long accuracy runs carry the CTest label
# "long" and run only with EULERVOP_LONG_TESTS=1.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${EULERVOP_BUILD_DIR:-$root/build}
"$root/tools/build.sh"
cd "$build"
if [[ "${EULERVOP_LONG_TESTS:-0}" == 1 ]]; then
  exec ctest --output-on-failure -j "$(nproc)"
fi
exec ctest --output-on-failure -j "$(nproc)" -LE long
