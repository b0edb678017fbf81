#!/usr/bin/env bash
# The installed package works for a project outside the tree: `cmake --install` into a
# fresh prefix, then a consumer configured with find_package(sdm) and one built from pkg-config
# alone, each built and run (consumer/main.cpp checks its decoded capsule against the analytic one).
# Usage: check_install.sh BUILD_DIR
set -euo pipefail
build="$1"
here="$(cd "$(dirname "$0")" && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >/dev/null
test -x "$work/prefix/bin/sdm"
"$work/prefix/bin/sdm" --version
# The installed sdm hands the commands it does not run itself to libexec/sdm/sdm-full: a capsule's
# skeleton (sdm itself) and its map encoded (sdm-full) from the installed tree, the build moved away.
"$work/prefix/bin/sdm" primitive capsule -o "$work/capsule.ply" >/dev/null
"$work/prefix/bin/sdm" skeleton "$work/capsule.ply" -o "$work/capsule.json" >/dev/null 2>&1
"$work/prefix/bin/sdm" encode "$work/capsule.ply" -o "$work/capsule.exr" --size 64 >/dev/null 2>&1
test -s "$work/capsule.exr"
test -f "$work/prefix/share/doc/sdm/LICENSE"

cmake -S "$here/consumer" -B "$work/cmake-build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
cmake --build "$work/cmake-build" >/dev/null
"$work/cmake-build/consumer"

export PKG_CONFIG_PATH="$work/prefix/lib/pkgconfig:$work/prefix/lib/x86_64-linux-gnu/pkgconfig"
# shellcheck disable=SC2046
c++ -std=c++17 -O1 "$here/consumer/main.cpp" -o "$work/pc-consumer" $(pkg-config --cflags --libs sdm)
"$work/pc-consumer"
echo "install: cmake package and pkg-config consumers built and passed"
