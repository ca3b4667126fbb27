#!/usr/bin/env bash
# Installs eulervop's Debian build dependencies when any is missing (needs root for apt-get), and
# unpacks Boost 1.81's headers from Debian's own libboost1.81-dev package into .deps/ (no root).
#
# Why Boost is unpacked and not installed: Debian 12's python3-scipy depends on pythran, which
# depends on the default libboost-dev (1.74), and libboost1.81-dev conflicts with it. eulervop needs
# 1.81 (Boost.PFR, per-thread MPFR precision), but only its header-only parts, so the headers live
# in the source tree's .deps/ and the system's Boost is left to scipy (docs/python.md, "Install").
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
packages=(
  build-essential cmake ninja-build pkg-config
  libmpfr-dev libgmp-dev libflint-arb-dev
  libtomlplusplus-dev libcli11-dev libfmt-dev nlohmann-json3-dev
  googletest libgtest-dev libbenchmark-dev
  parallel  # the tests run the GNU parallel recipes of docs/batch.md
  python3   # tools/check_layers.py (the test `layers`)
  python3-dev pybind11-dev python3-pybind11 python3-numpy python3-pytest  # the Python module
  python3-scipy  # examples/python: other solvers judged against the reference
)
[[ "${EULERVOP_WITH_PLOTS:-0}" == 1 ]] && packages+=(python3-matplotlib)

sudo=""
as_root() {
  if [[ $(id -u) -ne 0 ]]; then
    command -v sudo >/dev/null || { echo "setup: need root to run: $*" >&2; exit 1; }
    sudo=sudo
  fi
  DEBIAN_FRONTEND=noninteractive $sudo "$@"
}

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
updated=0
if ((${#missing[@]} > 0)); then
  echo "setup: installing ${missing[*]}" >&2
  if dpkg-query -W -f='${Status}' libboost1.81-dev 2>/dev/null | grep -q "install ok installed"; then
    echo "setup: libboost1.81-dev conflicts with scipy's Boost; apt removes it (eulervop uses .deps/)" >&2
  fi
  as_root apt-get update -qq
  updated=1
  as_root apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# Boost 1.81's headers and CMake package files, from the package's .deb as Debian ships it (apt
# checks its signature), unpacked once per version.
deps="$root/.deps"
boost="$deps/boost1.81"
version=$(apt-cache policy libboost1.81-dev 2>/dev/null | awk '/Candidate:/ { print $2 }')
if [[ -z "$version" || "$version" == "(none)" ]] && ((updated == 0)); then
  as_root apt-get update -qq
  version=$(apt-cache policy libboost1.81-dev | awk '/Candidate:/ { print $2 }')
fi
[[ -n "$version" && "$version" != "(none)" ]] || { echo "setup: apt knows no libboost1.81-dev" >&2; exit 1; }
if [[ "$(cat "$boost/.version" 2>/dev/null)" != "$version" ]]; then
  echo "setup: unpacking libboost1.81-dev $version into .deps/" >&2
  mkdir -p "$deps"
  scratch=$(mktemp -d "$deps/download.XXXXXX")
  trap 'rm -rf "$scratch"' EXIT
  # apt's sandbox user cannot write a private folder: download as the caller, into the scratch.
  (cd "$scratch" && apt-get download -q "libboost1.81-dev=$version" -o APT::Sandbox::User="$(id -un)" >/dev/null)
  dpkg-deb -x "$scratch"/libboost1.81-dev_*.deb "$scratch/tree"
  echo "$version" >"$scratch/tree/.version"
  rm -rf "$boost"
  mv "$scratch/tree" "$boost"
fi
