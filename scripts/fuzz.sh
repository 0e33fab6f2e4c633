#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (ASan + UBSan) and runs each for a bounded time.
#   scripts/fuzz.sh [SECONDS_PER_TARGET]   (default 60; the reliability runs used 1800)
# Seed corpora: scenarios/ (scenes) and scenarios/traces/ (traces), plus fuzz/corpus/*.
# Crashes are written to fuzz-artifacts/; each one found becomes a regression test in
# tests/regress/.
set -euo pipefail
cd "$(dirname "$0")/.."
secs=${1:-60}
bash scripts/install-deps.sh
export LC_ALL=C
CC=clang CXX=clang++ cmake -S . -B build-fuzz -DHP_FUZZ=ON -DHP_BUILD_TESTS=OFF \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build-fuzz --target fuzz_scene fuzz_trace -j"$(nproc)"
mkdir -p fuzz-artifacts build-fuzz/corpus/scene build-fuzz/corpus/trace
find scenarios -name '*.yaml' -exec cp {} build-fuzz/corpus/scene/ \;
[ -d tests/scenes_bad ] && find tests/scenes_bad -name '*.yaml' -exec cp {} build-fuzz/corpus/scene/ \;
# The trace target's first byte picks the format (even: CSV, odd: JSON Lines).
for f in scenarios/traces/*.csv; do [ -e "$f" ] && { printf '0'; head -c 4000 "$f"; } > "build-fuzz/corpus/trace/$(basename "$f")"; done
for f in scenarios/traces/*.jsonl; do [ -e "$f" ] && { printf '1'; head -c 4000 "$f"; } > "build-fuzz/corpus/trace/$(basename "$f")"; done
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export LSAN_OPTIONS=suppressions=$PWD/tests/lsan.supp
for t in scene trace; do
  echo "fuzz_$t: ${secs}s" >&2
  ./build-fuzz/fuzz/fuzz_$t -max_total_time="$secs" -max_len=65536 -timeout=10 \
    -rss_limit_mb=2048 -artifact_prefix=fuzz-artifacts/ -print_final_stats=1 \
    build-fuzz/corpus/$t 2>&1 | grep -E "stat::number_of_executed_units|stat::peak_rss|Done|ERROR|SUMMARY" >&2
done
# Reaching here means neither target found anything (set -e and pipefail stop on a finding).
echo "fuzz: 2 passed, 0 failed"
