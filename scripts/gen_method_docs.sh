#!/usr/bin/env bash
# Regenerates the method parameter tables in docs/methods.md and configs/README.md from the
# methods' declarations (`fovsim methods --markdown`), between the BEGIN/END GENERATED markers.
# Usage: scripts/gen_method_docs.sh [BUILD_DIR]   (make docs). tests/app/docs_test.cpp checks it.
set -euo pipefail
cd "$(dirname "$0")/.."
B=${1:-build}
gen=$(mktemp)
"$B/fovsim" methods --markdown > "$gen"
for f in docs/methods.md configs/README.md; do
  python3 - "$f" "$gen" <<'PY'
import sys
path, gen = sys.argv[1], open(sys.argv[2]).read()
s = open(path).read()
b = s.index("<!-- BEGIN GENERATED")
b = s.index("\n", b) + 1
e = s.index("<!-- END GENERATED -->")
open(path, "w").write(s[:b] + "\n" + gen + s[e:])
PY
done
rm -f "$gen"
echo "updated docs/methods.md and configs/README.md"
