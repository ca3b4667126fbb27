#!/usr/bin/env bash
# Installs eulervop's Debian build dependencies when any is missing (needs root for apt-get).
set -euo pipefail
packages=(
  build-essential cmake pkg-config
  libboost1.81-dev libmpfr-dev libgmp-dev libmpfi-dev libflint-arb-dev
  libtomlplusplus-dev libcli11-dev libfmt-dev nlohmann-json3-dev
  googletest libgtest-dev libbenchmark-dev
  parallel  # the tests run the GNU parallel recipes of docs/batch.md
  python3   # tools/check_layers.py (the test `layers`)
  python3-dev pybind11-dev python3-pybind11 python3-numpy python3-pytest  # the Python module
)
[[ "${EULERVOP_WITH_PLOTS:-0}" == 1 ]] && packages+=(python3-matplotlib)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
((${#missing[@]} == 0)) && exit 0
echo "setup: installing ${missing[*]}" >&2
sudo=""
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "setup: need root to install: ${missing[*]}" >&2; exit 1; }
  sudo=sudo
fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
