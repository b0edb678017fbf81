#!/usr/bin/env bash
# Runs the add-on's tests in Blender without a window (CTest's blender.addon and blender.addon_zip):
#   run_test_addon.sh [--zip] --sdm-py DIR [--examples DIR]
# Without --zip: tests/blender/test_addon.py on the add-on in the repository. With --zip: the zip of
# scripts/blender_addon_zip.sh installed into temporary user folders (tests/blender/test_addon_zip.py).
# Blender is `blender` on PATH, or $BLENDER; without it the test fails, saying how to install it
# (scripts/install-deps.sh --tests does).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
blender=${BLENDER:-blender}
if ! command -v "$blender" >/dev/null 2>&1; then
  echo "blender.addon: '$blender' was not found: install Debian's Blender (bash scripts/install-deps.sh --tests, or" \
       "apt-get install --no-install-recommends blender), or set BLENDER=/path/to/blender" >&2
  exit 1
fi
run=("$blender" -b --factory-startup --python-exit-code 1 --python)
if [ "${1:-}" != "--zip" ]; then
  exec "${run[@]}" "$here/test_addon.py" -- "$@"
fi
shift
tmp=$(mktemp -d -t sdm-addon-zip.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
bash "$here/../../scripts/blender_addon_zip.sh" "$tmp/sdm_blender.zip"
BLENDER_USER_SCRIPTS=$tmp/scripts BLENDER_USER_CONFIG=$tmp/config \
  "${run[@]}" "$here/test_addon_zip.py" -- --zip "$tmp/sdm_blender.zip" "$@"
