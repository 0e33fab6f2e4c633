#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite with ctest.
#   scripts/test.sh              release build in build/
#   scripts/test.sh --sanitize   ASan + UBSan build in build-asan/
# HP_CTEST_JOBS sets how many tests run at once (default: the number of cores); .ci/run
# sets it above the core count to show that no test depends on time or load.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
export LC_ALL=C
dir=build; flags=(); timeout=1200
if [ "${1:-}" = "--sanitize" ]; then
  dir=build-asan; flags=(-DHP_SANITIZE=ON -DCMAKE_BUILD_TYPE=Debug)
  # Three to ten times slower (-O1 with both sanitizers), and .ci/run loads the machine on
  # purpose: the slowest tests took 30 to 40 min there before they were made smaller under
  # the sanitizers (HP_TEST_SMALL, CONTRIBUTING.md). The bound is a hang's.
  timeout=3600
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1
  export LSAN_OPTIONS=suppressions=$PWD/tests/lsan.supp:print_suppressions=0
  export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
fi
cmake -S . -B "$dir" "${flags[@]}" >/dev/null
cmake --build "$dir" -j"$(nproc)"
# The Debian package test (label package: a clean Debian root, downloads on its first run)
# runs on its own in .ci/run.
ctest --test-dir "$dir" --output-on-failure -j"${HP_CTEST_JOBS:-$(nproc)}" --timeout "$timeout" \
      -LE package
