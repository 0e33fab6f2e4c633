#!/usr/bin/env bash
# Regenerates every measured number of the docs from one run (docs/measurements.md says what
# runs and where it writes; scripts/regen_docs.py does it). Needs a built build folder:
#   bash scripts/regen-docs.sh            uses build/ (HP_BUILD_DIR=DIR for another)
# Runs niced, in the C locale; takes about ten minutes at full size.
set -euo pipefail
cd "$(dirname "$0")/.."
B=${HP_BUILD_DIR:-build}
for p in headplan headplan-bench headplan-bench-backends headplan-bench-horizon headplan-bench-count; do
  [ -x "$B/$p" ] || { echo "regen-docs.sh: $B/$p missing: build first (cmake --build $B)" >&2; exit 66; }
done
export LC_ALL=C
exec nice -n 10 /usr/bin/python3 scripts/regen_docs.py --src "$PWD" --bin "$PWD/$B" "$@"
