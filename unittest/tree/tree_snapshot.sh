#!/bin/bash
# A listing of the source tree (files with size and modification time, and
# `git status` where the tree is a git clone), leaving out the build folder
# the tests run in.  The suite takes one before its tests and one after;
# they must be equal: tests never write into the source tree.
# usage: tree_snapshot.sh SRC BUILD OUT
set -euo pipefail
SRC=$(cd "$1" && pwd); BIN=$(cd "$2" && pwd); OUT=$3
{
  find "$SRC" \( -path "$BIN" -o -path "$SRC/.git" \) -prune -o \
    \( -type d -printf 'dir  %P\n' \) -o -printf 'file %P %s %T@\n' | LC_ALL=C sort
  if command -v git > /dev/null && [ -e "$SRC/.git" ]; then
    echo "== git status"
    git -C "$SRC" status --porcelain=v1 --untracked-files=all
  fi
} > "$OUT"
