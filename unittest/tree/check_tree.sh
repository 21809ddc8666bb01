#!/bin/bash
# After the suite: the source tree must be as it was before it.
# usage: check_tree.sh SRC BUILD BEFORE
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
bash "$HERE/tree_snapshot.sh" "$1" "$2" "$3.after"
if ! diff "$3" "$3.after"; then
  echo "FAIL: the test suite changed the source tree $1 (lines above: < before, > after)"
  exit 1
fi
echo "source tree unchanged: $(grep -c '^file' "$3") files"
