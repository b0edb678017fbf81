#!/usr/bin/env bash
# Packs the Blender add-on blender/sdm_blender/ into a zip that Blender installs through
# Preferences > Add-ons > Install... (the zip holds the folder sdm_blender/; no __pycache__).
# Usage: scripts/blender_addon_zip.sh [OUT.zip]   (default: build/sdm_blender.zip)
# The add-on still needs sdm_py: point its preference "sdm_py folder" at an sdm build's build/python.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-$root/build/sdm_blender.zip}
mkdir -p "$(dirname "$out")"
/usr/bin/env python3 - "$root/blender" "$out" <<'PY'
import os, sys, zipfile
src, out = sys.argv[1], sys.argv[2]
tmp = out + ".tmp"
with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
    for folder, dirs, files in os.walk(os.path.join(src, "sdm_blender")):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__")
        for f in sorted(files):
            if f.endswith(".py"):
                path = os.path.join(folder, f)
                z.write(path, os.path.relpath(path, src))
os.replace(tmp, out)
print(f"{out}: {', '.join(zipfile.ZipFile(out).namelist())}")
PY
