#!/usr/bin/env bash
# `make fuzz`: builds the libFuzzer targets of tests/fuzz with clang, AddressSanitizer and
# UndefinedBehaviorSanitizer (in build-fuzz/), then fuzzes each reader for FUZZ_SECONDS (default 60;
# the long runs of DECISIONS 1 are FUZZ_SECONDS=600) from the seeds in tests/fuzz/corpus/, one target at a
# time on FUZZ_JOBS processes. The corpus grows in build-fuzz/corpus/; a crash, a sanitizer report,
# a leak, a hang (-timeout) or an allocation over -malloc_limit_mb stops the target with its input
# saved in build-fuzz/findings/ and fails the script. Prints a table: executions, rate, corpus.
# FUZZ_TARGETS picks targets (default: all eleven).
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_PER_TARGET="${FUZZ_SECONDS:-60}"
JOBS="${FUZZ_JOBS:-1}"
BUILD="${FUZZ_BUILD:-build-fuzz}"
TARGETS="${FUZZ_TARGETS:-fuzz_mesh_obj fuzz_mesh_off fuzz_mesh_ply fuzz_mesh_stl fuzz_mesh_glb fuzz_mesh_gltf fuzz_skeleton_json fuzz_layout_json fuzz_mtl fuzz_ply_header fuzz_sdm_exr}"

if ! command -v clang++ >/dev/null || ! ls /usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a >/dev/null 2>&1; then
  echo "fuzz: installing clang (libFuzzer)" >&2
  SUDO=""; if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends clang >/dev/null
fi
# FUZZ_NO_BUILD=1: use the targets already built (two runs of this script side by side).
if [ -z "${FUZZ_NO_BUILD:-}" ]; then
  cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
    -DSDM_FUZZ=ON -DSDM_BUILD_TESTS=OFF >/dev/null
  cmake --build "$BUILD" --target fuzz_targets -j "$(nproc)"
fi

mkdir -p "$BUILD/findings"
status=0
printf '%-20s %12s %10s %8s %s\n' target executions "exec/s" corpus result
for t in $TARGETS; do
  corpus="$BUILD/corpus/$t"
  mkdir -p "$corpus"
  cp -n tests/fuzz/corpus/$t/* "$corpus/" 2>/dev/null || true
  log="$BUILD/findings/$t.log"
  rm -f "$BUILD/findings/$t-"*
  parallel=()
  if [ "$JOBS" -gt 1 ]; then parallel=(-jobs="$JOBS" -workers="$JOBS"); fi
  # detect_leaks: a reader that leaks on a refused input fails too.
  if ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1 UBSAN_OPTIONS=print_stacktrace=1 \
     "$BUILD/tests/fuzz/$t" "$corpus" -max_total_time="$SECONDS_PER_TARGET" "${parallel[@]}" \
       -rss_limit_mb=2048 -malloc_limit_mb=1024 -timeout=20 -max_len=131072 -print_final_stats=1 \
       -artifact_prefix="$BUILD/findings/$t-" >"$log" 2>&1; then
    result=ok
  else
    result="FAILED (see $log)"
    status=1
  fi
  runs=$({ cat "$log"; cat fuzz-*.log 2>/dev/null || true; } | awk '/stat::number_of_executed_units/ {s += $2} END {print s + 0}')
  rate=$(awk -v r="$runs" -v s="$SECONDS_PER_TARGET" 'BEGIN {printf "%.0f", r / s}')
  printf '%-20s %12s %10s %8s %s\n' "$t" "$runs" "$rate" "$(ls "$corpus" | wc -l)" "$result"
  rm -f fuzz-*.log
done
exit $status
