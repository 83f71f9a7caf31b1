#!/usr/bin/env bash
# Style gate (ctest FormatCheck, part of make test): every tracked C++ source is formatted by
# the committed .clang-format (Debian's clang-format). `make format` fixes the tree.
# Exit 77 (skipped) without clang-format or outside a git checkout.
set -uo pipefail
cd "$(dirname "$0")/../.."
command -v clang-format > /dev/null || { echo "clang-format not installed: skipped"; exit 77; }
files=$(git ls-files 'sim/*.cpp' 'sim/*.h' 'tests/*.cpp' 'tests/*.h' 'bench/*.cpp' 'python/*.cpp' 2> /dev/null) ||
  { echo "not a git checkout: skipped"; exit 77; }
bad=0
for f in $files; do
  if ! clang-format --dry-run -Werror "$f" > /dev/null 2>&1; then
    echo "not formatted: $f (run: clang-format -i $f, or make format)"
    bad=$((bad + 1))
  fi
done
n=$(echo "$files" | wc -w)
echo "format: $((n - bad)) passed, $bad failed"
[ "$bad" -eq 0 ]
