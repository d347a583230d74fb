#!/usr/bin/env bash
# Builds the fuzz targets (the `fuzz` preset: clang, libFuzzer, ASan+UBSan, in build-fuzz/) and runs
# each for SECONDS (default 20), one after the other (fuzz/README.md).
#
#   scripts/fuzz.sh [SECONDS]
#
# Each target starts from its seeds (fuzz/corpus/<target>/, fuzz/regressions/<target>/, read only)
# and writes what it finds into a working corpus in a temporary directory; crashes, leaks, timeouts
# and out-of-memory inputs go into that directory's artifacts/ folder. Exits non-zero when any
# target found something, naming the artifacts. Environment:
#   PENUMBRA_FUZZ_TARGETS    the targets to run (default: all five)
#   PENUMBRA_FUZZ_TOLERATE   open findings the structure-aware target tolerates until they are
#                            fixed (default: fuzz/tolerated_findings.txt; empty: tolerate none)
#   PENUMBRA_FUZZ_WORK       where to put the working corpora and artifacts (default: mktemp)
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${1:-20}
targets=${PENUMBRA_FUZZ_TARGETS:-json_scene obj_scene gltf_scene points_file dm_geometry}
# The engine findings reported and not fixed yet (fuzz/tolerated_findings.txt): without tolerating
# them the structure-aware target stops at them within seconds and fuzzes nothing new.
tolerated=$(grep -v -e '^#' -e '^$' fuzz/tolerated_findings.txt | paste -sd, - || true)
export PENUMBRA_FUZZ_TOLERATE=${PENUMBRA_FUZZ_TOLERATE-$tolerated}
# Leak detection stays on (ASan's default under libFuzzer); UBSan reports come with their stack
# (they abort: the code is built with -fno-sanitize-recover=undefined).
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1}

cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j "$(nproc)"

work=${PENUMBRA_FUZZ_WORK:-$(mktemp -d "${TMPDIR:-/tmp}/penumbra-fuzz-run.XXXXXX")}
echo "fuzz: ${seconds} s per target, working corpora and artifacts in $work"
failed=0
for target in $targets; do
  dir="$work/$target"
  mkdir -p "$dir/corpus" "$dir/artifacts"
  seeds=(fuzz/corpus/"$target")
  [ -d fuzz/regressions/"$target" ] && seeds+=(fuzz/regressions/"$target")
  options=(-max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1
           -artifact_prefix="$dir/artifacts/")
  [ -f fuzz/dict/"$target".dict ] && options+=(-dict=fuzz/dict/"$target".dict)
  # The first corpus directory is the one libFuzzer writes to; the seeds stay as they are.
  if build-fuzz/bin/"$target"_fuzzer "${options[@]}" "$dir/corpus" "${seeds[@]}" >"$dir/log.txt" 2>&1
  then
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$dir/log.txt")
    coverage=$(sed -n 's/^#[0-9]*[[:space:]]*DONE[[:space:]]*\(cov: [0-9]* ft: [0-9]*\).*/\1/p' "$dir/log.txt")
    echo "fuzz: $target ok: $runs runs, $coverage, $(ls "$dir/corpus" | wc -l) new corpus inputs"
  else
    failed=1
    echo "fuzz: $target FAILED: see $dir/log.txt; the input is in $dir/artifacts/:"
    ls -l "$dir/artifacts"
    grep -E 'FINDING|ERROR|SUMMARY|runtime error' "$dir/log.txt" | head -20 || true
  fi
done
exit "$failed"
