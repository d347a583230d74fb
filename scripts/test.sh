#!/usr/bin/env bash
# Installs dependencies, builds and runs every test: the release preset, then the ASan+UBSan preset
# (skip the sanitizer pass with PENUMBRA_SKIP_ASAN=1 for a quicker local run), then on CI (CI=true)
# or when PENUMBRA_FUZZ_SECONDS is set a short fuzzing run: every fuzz target for
# PENUMBRA_FUZZ_SECONDS (default 20) seconds, under two minutes in all (scripts/fuzz.sh; skip it with
# PENUMBRA_SKIP_FUZZ=1).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
jobs=$(nproc)

cmake --preset release >/dev/null
cmake --build --preset release -j "$jobs"
ctest --preset release -j "$jobs"

if [ "${PENUMBRA_SKIP_ASAN:-0}" != 1 ]; then
  cmake --preset asan >/dev/null
  cmake --build --preset asan -j "$jobs"
  ctest --preset asan -j "$jobs"
fi

if [ "${PENUMBRA_SKIP_FUZZ:-0}" != 1 ] && { [ "${CI:-}" = true ] || [ -n "${PENUMBRA_FUZZ_SECONDS:-}" ]; }; then
  bash scripts/fuzz.sh "${PENUMBRA_FUZZ_SECONDS:-20}"
fi
