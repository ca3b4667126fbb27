#!/usr/bin/env bash
# Builds eulervop from clean in a scratch folder and prints the slowest and the largest translation
# units: wall seconds and peak memory of each compiler process, measured by /usr/bin/time through
# CMake's compiler launcher, and the compiler's CPU seconds (user + system) summed over the units,
# the figure to compare on a shared machine, where wall times stretch with the load. The figures
# to keep small are in docs/design.md ("Build cost").
#
# Usage: tools/tu_cost.sh [BUILD_DIR] [TARGET...]
#   BUILD_DIR defaults to build-tu-cost (removed and made anew); no TARGET builds everything.
#   e.g. tools/tu_cost.sh /tmp/tu eulervop
# Prints the total wall time of the build, then the 15 slowest and the 10 largest units.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(realpath -m "${1:-$root/build-tu-cost}")
shift || true
"$root/tools/setup.sh"
[[ -x /usr/bin/time ]] || { echo "tu_cost: needs /usr/bin/time (Debian package time)" >&2; exit 1; }
rm -rf "$build"
mkdir -p "$build"
log="$build/tu_cost.log"
: >"$log"
# The launcher appends "seconds kilobytes source cpu_seconds" for every compiler call.
launcher="$build/time_launcher.sh"
cat >"$launcher" <<LAUNCH
#!/usr/bin/env bash
src=\${@: -1}
exec /usr/bin/time -a -o "$log" -f "%e %M \$src %U %S" "\$@"
LAUNCH
chmod +x "$launcher"
cmake -S "$root" -B "$build" -G "${CMAKE_GENERATOR:-Ninja}" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_CXX_COMPILER_LAUNCHER="$launcher" >/dev/null
targets=()
for t in "$@"; do targets+=(--target "$t"); done
start=$(date +%s.%N)
cmake --build "$build" -j "$(nproc)" "${targets[@]}" >"$build/build.out" 2>&1 || {
  tail -30 "$build/build.out" >&2
  exit 1
}
end=$(date +%s.%N)
# Compile lines end with the source file (-c x.cpp); link lines with a library or object list.
awk -v start="$start" -v end="$end" -v cores="$(nproc)" 'BEGIN { printf "clean build: %.0f s wall on %s cores\n", end - start, cores }'
units=$(grep -E '\.(cpp|cxx) [0-9.]+ [0-9.]+$' "$log" || true)  # the units and the precompiled headers
echo "units compiled: $(wc -l <<<"$units")"
awk '{ cpu += $4 + $5 } END { printf "compiler CPU: %.0f s (user + system, summed over the units)\n", cpu }' <<<"$units"
echo "-- slowest (s, MB, unit)"
sort -k1,1 -g -r <<<"$units" | head -15 | awk -v r="$root/" '{ sub(r, "", $3); printf "%7.1f %6.0f  %s\n", $1, $2 / 1024, $3 }'
echo "-- largest (MB, s, unit)"
sort -k2,2 -g -r <<<"$units" | head -10 | awk -v r="$root/" '{ sub(r, "", $3); printf "%6.0f %7.1f  %s\n", $2 / 1024, $1, $3 }'
