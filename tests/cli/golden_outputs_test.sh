#!/usr/bin/env bash
# Golden outputs: --print-config, assess --json at Prague positions and digests of the bundled
# maps' tables, against tests/golden/expected (see tests/golden/make-golden.sh, which says how to
# update them on purpose).
source "$(dirname "$0")/lib.sh"
golden=$(cd "$(dirname "$0")/../golden" && pwd)
build_dir=$(dirname "$(dirname "$ROADCROSS_BUILD")")
bash "$golden/make-golden.sh" "$build_dir" "$WORK/actual"
for file in "$golden"/expected/*; do
  name=$(basename "$file")
  if diff -u "$file" "$WORK/actual/$name" >"$WORK/diff"; then
    pass "$name as committed"
  else
    fail "$name differs from tests/golden/expected/$name:"
    head -n 60 "$WORK/diff" >&2
    echo "If the change is intended: bash tests/golden/make-golden.sh build/release tests/golden/expected" >&2
  fi
done
[[ $(ls "$golden"/expected | wc -l) == 3 ]] || fail "expected 3 golden files in tests/golden/expected"
finish
