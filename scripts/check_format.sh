#!/usr/bin/env bash
# Checks that the C and C++ sources follow .clang-format (clang-format 14, Debian 12's; other
# versions format some constructs differently, so another major version is refused rather
# than trusted). Prints clang-format's FILE:LINE:COL for every line that would change and
# exits 1 if any would; 0 when all are formatted. Changes nothing.
#   bash scripts/check_format.sh            every tracked .c/.h/.cpp file (every such file
#                                           under the source folders when not a git checkout)
#   bash scripts/check_format.sh FILE...    only these (the pre-commit hook passes the staged ones)
set -euo pipefail
cd "$(dirname "$0")/.."
CF=${CLANG_FORMAT:-clang-format}
command -v "$CF" >/dev/null || { echo "check_format.sh: $CF not found (apt-get install clang-format)" >&2; exit 69; }
major=$("$CF" --version | sed -n 's/.*version \([0-9]*\)\..*/\1/p')
[ "$major" = 14 ] || { echo "check_format.sh: clang-format $major found, the style is pinned to 14" >&2; exit 69; }

files=()
if [ "$#" -gt 0 ]; then
  files=("$@")
elif git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  mapfile -t files < <(git ls-files '*.c' '*.h' '*.cpp')
else
  mapfile -t files < <(find common iab kinematics planner scene calib horizon cli bench include \
                         python tests fuzz examples -name '*.[ch]' -o -name '*.cpp' | sort)
fi
checked=0 bad=0
for f in "${files[@]}"; do
  case "$f" in *.c|*.h|*.cpp) ;; *) continue ;; esac
  checked=$((checked + 1))
  if ! out=$("$CF" --style=file --dry-run --Werror "$f" 2>&1); then
    grep -E '^[^ ].*: error:' <<<"$out" || echo "$f: clang-format failed: $out"
    bad=$((bad + 1))
  fi
done
if [ "$bad" -gt 0 ]; then
  echo "check_format.sh: $bad of $checked files not formatted (clang-format -i FILE)" >&2
  exit 1
fi
echo "check_format.sh: $checked files formatted"
