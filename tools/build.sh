#!/usr/bin/env bash
# Configures (once) and builds eulervop in Release. Usage: tools/build.sh [TARGET...]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${EULERVOP_BUILD_DIR:-$root/build}
"$root/tools/setup.sh"  # EULERVOP_WITH_PLOTS=1 adds matplotlib for the figures
# Ninja unless the caller names a generator (CMAKE_GENERATOR): it starts a library's units while
# the libraries it links still compile, where Make waits for them (docs/design.md 5.8).
if [[ ! -f "$build/CMakeCache.txt" ]]; then
  cmake -S "$root" -B "$build" -G "${CMAKE_GENERATOR:-Ninja}" -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
targets=()
for t in "$@"; do targets+=(--target "$t"); done
# Build chatter goes to standard error so that standard output stays the program's.
cmake --build "$build" -j "$(nproc)" "${targets[@]}" >&2
