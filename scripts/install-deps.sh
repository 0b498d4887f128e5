#!/usr/bin/env bash
# Installs PoreSPH's build and run dependencies from Debian 12 packages (nothing else is fetched).
# Safe to run again: apt-get skips what is installed.
set -euo pipefail
PKGS=(g++ cmake ninja-build pkg-config
      libeigen3-dev libvtk9-dev libhdf5-dev libcli11-dev libyaml-cpp-dev
      libgtest-dev libbenchmark-dev python3 python3-numpy python3-matplotlib python3-vtk9)
SUDO=""
if [ "$(id -u)" != "0" ]; then SUDO="sudo"; fi
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps: installing ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "install-deps: all packages present"
fi
