#!/usr/bin/env bash
# Installs, builds and runs the full default test suite. Long accuracy runs carry the CTest label
# "long" and run only with EULERVOP_LONG_TESTS=1. The one-node Slurm run of the job array in
# docs/batch.md (label "cluster") installs packages and starts daemons, so it runs only with
# EULERVOP_CLUSTER_TESTS=1; the two switches are independent.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${EULERVOP_BUILD_DIR:-$root/build}
"$root/tools/build.sh" eulervop_test_programs  # the program, the module and the tests (not the benchmarks)
cd "$build"
skip=()
[[ "${EULERVOP_LONG_TESTS:-0}" == 1 ]] || skip+=(long)
[[ "${EULERVOP_CLUSTER_TESTS:-0}" == 1 ]] || skip+=(cluster)
exclude=$(IFS='|'; echo "${skip[*]}")
exec ctest --output-on-failure -j "$(nproc)" ${exclude:+-LE "$exclude"}
