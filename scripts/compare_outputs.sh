#!/usr/bin/env bash
# Compares two output folders (for example two `make demo DEMO_OUT=...` runs) file by file:
# every JSON, OBJ, MTL, EXR and PNG must be byte-identical. Logs and text summaries are skipped,
# since they name the folder and interleave threads' progress lines.
# usage: scripts/compare_outputs.sh BEFORE AFTER     exit 1 when a file differs or is missing
set -euo pipefail
before=$1 after=$2 status=0 n=0
for f in "$before"/*.{json,obj,mtl,exr,png}; do
  [ -e "$f" ] || continue
  b=$(basename "$f"); n=$((n + 1))
  if [ ! -e "$after/$b" ]; then echo "missing: $b"; status=1
  elif ! cmp -s "$f" "$after/$b"; then echo "differs: $b"; status=1; fi
done
echo "$n files compared"
exit $status
