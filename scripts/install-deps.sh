#!/usr/bin/env bash
# Installs the Debian 12 packages sdm needs, and only those that are missing.
# Idempotent: a second run installs nothing and does not touch the network.
# `--tests` adds what only the tests use (Blender for the add-on's test: 535 MB installed; Chromium
# for the batch report's), so `make demo` does not fetch them; `make test` passes it.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libopenmesh-dev libopenexr-dev libosd-dev
  libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri
  catch2 libcli11-dev nlohmann-json3-dev libstb-dev libsuitesparse-dev libspectra-dev python3
  pybind11-dev python3-dev python3-numpy libtinygltf-dev zlib1g-dev libpng-dev
  python3-distributed  # sdm batch (python/sdm_batch.py)
)
if [ "${1:-}" = "--tests" ]; then
  PACKAGES+=(
    blender  # the Blender add-on's test (tests/blender): about 80 MB to fetch, 535 MB installed
    chromium  # the batch report's test (tests/python/test_batch_report.py) opens the page headless
  )
fi

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "install-deps: installing ${missing[*]}" >&2
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
