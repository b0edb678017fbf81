#!/usr/bin/env bash
# Runs every command of the README's examples block (the ```sh block under "### Examples") as
# written, each in the same fresh temporary folder, with S set to the built sdm (sdm-full beside
# it). The folder holds a link to the repository's examples/ and, one level up, to the shared
# models beside the repository, so that examples/... and ../shared/... resolve as they do from the
# repository root, while every output is written into the temporary folder.
#
#   tests/readme_examples.sh BUILD/sdm [REPOSITORY]
#
# A command fails the test when it exits otherwise than expected: 0, or N when its trailing
# comment starts with "exit N" (e.g. "# exit 2: ..."), which is checked, not ignored. The line
# that sets S (S=build/sdm) is replaced by the binary given. Lines ending with a backslash
# continue on the next. When ../shared/models is missing, the commands that use ../shared are
# skipped with a message; when every command would be skipped the script exits 77 (CTest's
# SKIP_RETURN_CODE).
set -u

sdm=${1:?usage: readme_examples.sh BUILD/sdm [REPOSITORY]}
repo=${2:-$(cd "$(dirname "$0")/.." && pwd)}
sdm=$(cd "$(dirname "$sdm")" && pwd)/$(basename "$sdm")
readme=$repo/README.md
[ -x "$sdm" ] || { echo "readme_examples: $sdm is not an executable"; exit 1; }
[ -f "$readme" ] || { echo "readme_examples: no $readme"; exit 1; }

# The block: from the first ```sh after "### Examples" to its closing ```. Each entry is
# "LINE<TAB>COMMAND" with continuation lines joined; LINE is the README line it starts on.
commands=$(awk '
  /^### Examples/ { in_section = 1; next }
  in_section && /^#/ && !in_block { in_section = 0 }
  in_section && !in_block && /^```sh/ { in_block = 1; next }
  in_block && /^```/ { exit }
  in_block {
    line = $0
    if (pending != "") { cmd = cmd " " line } else { start = NR; cmd = line }
    if (cmd ~ /\\[ \t]*$/) { sub(/\\[ \t]*$/, "", cmd); pending = 1; next }
    pending = ""
    if (cmd ~ /^[ \t]*$/) next
    printf "%d\t%s\n", start, cmd
  }' "$readme")
[ -n "$commands" ] || { echo "readme_examples: no sh block under '### Examples' in $readme"; exit 1; }

tmp=$(mktemp -d "${TMPDIR:-/tmp}/sdm-readme.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
work=$tmp/work
mkdir -p "$work"
ln -s "$repo/examples" "$work/examples"
shared_present=0
if [ -d "$repo/../shared/models" ]; then
  ln -s "$(cd "$repo/../shared" && pwd)" "$tmp/shared"
  shared_present=1
fi

ran=0 skipped=0 failed=0
while IFS=$'\t' read -r line cmd; do
  if [[ $cmd =~ ^[[:space:]]*S= ]]; then
    echo "README:$line: S is $sdm"
    continue
  fi
  if [ $shared_present = 0 ] && [[ $cmd == *../shared/* ]]; then
    echo "README:$line: skipped, ../shared/models is missing beside the repository: $cmd"
    skipped=$((skipped + 1))
    continue
  fi
  expected=0
  comment=${cmd#*#}
  if [ "$comment" != "$cmd" ] && [[ $comment =~ ^[[:space:]]*exit[[:space:]]+([0-9]+) ]]; then
    expected=${BASH_REMATCH[1]}
  fi
  log=$tmp/line$line.log
  start=$(date +%s.%N)
  (cd "$work" && S=$sdm bash -c "$cmd") </dev/null >"$log" 2>&1
  rc=$?
  seconds=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
  ran=$((ran + 1))
  if [ "$rc" = "$expected" ]; then
    echo "README:$line: exit $rc as expected, ${seconds} s: $cmd"
  else
    failed=$((failed + 1))
    echo "README:$line: FAILED, exit $rc where $expected was expected (${seconds} s): $cmd"
    tail -n 20 "$log" | sed 's/^/    /'
  fi
done <<<"$commands"

echo "readme_examples: $ran run, $failed failed, $skipped skipped"
if [ $failed -gt 0 ]; then exit 1; fi
if [ $ran = 0 ] && [ $skipped -gt 0 ]; then exit 77; fi
exit 0
