#!/usr/bin/env bash
# `pip install .` of the Python module in a fresh virtualenv, offline (--no-index) with Debian's
# setuptools and wheel (--no-build-isolation): setup.py drives a runtime-only CMake build. The installed
# module imports in the venv (and not from the build tree), opens a map, and mypy finds its
# types through the installed stub package (PEP 561, py.typed). Also builds a wheel with Debian's
# python3-build.
source "$(dirname "$0")/lib.sh"
SOURCE="$(cd "$(dirname "$0")/../.." && pwd)"
# A copy of the sources without build trees and maps: pip builds in the source directory.
mkdir "$WORK/src"
tar -C "$SOURCE" --exclude=./build --exclude=./maps --exclude=./.git --exclude='*.egg-info' -cf - . |
  tar -C "$WORK/src" -xf -
# --system-site-packages: the build back end (setuptools, wheel) comes from Debian, offline.
/usr/bin/python3 -m venv --system-site-packages "$WORK/venv"
VENV_PY="$WORK/venv/bin/python"
if (cd "$WORK/src" && env -u PYTHONPATH "$VENV_PY" -m pip install --no-index --no-build-isolation \
      --no-cache-dir . >"$WORK/pip.log" 2>&1); then
  pass "pip install . in a fresh venv, offline"
else
  fail "pip install: $(tail -30 "$WORK/pip.log")"
  finish
fi
site=$(env -u PYTHONPATH "$VENV_PY" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
for file in roadcross.pyi roadcross-stubs/__init__.pyi roadcross-stubs/py.typed; do
  [[ -f $site/$file ]] && pass "installed $file" || fail "not installed: $site/$file"
done
cmp -s "$site/roadcross.pyi" "$SOURCE/python/roadcross.pyi" && pass "the stub is python/roadcross.pyi" ||
  fail "the installed stub differs from python/roadcross.pyi"
where=$(cd "$WORK" && env -u PYTHONPATH "$VENV_PY" -c 'import roadcross; print(roadcross.__file__)')
[[ $where == "$site"/roadcross.* ]] && pass "imports from the venv: $where" || fail "imported from $where"
version=$(cd "$WORK" && env -u PYTHONPATH "$VENV_PY" -c 'import roadcross; print(roadcross.__version__)')
[[ $version == $("$ROADCROSS" --version | awk '{print $2}') ]] && pass "version $version" ||
  fail "version $version, roadcross says $("$ROADCROSS" --version)"
# The installed module answers a query on a real map (segment count as sqlite3 counts it).
"$ROADCROSS_BUILD" -q --osm "$PRAGUE_OSM" -o "$WORK/prague.gpkg"
count=$(cd "$WORK" && env -u PYTHONPATH "$VENV_PY" -c 'import roadcross, sys
print(roadcross.Map(sys.argv[1]).info.segment_count)' "$WORK/prague.gpkg")
[[ $count == $(sqlite3 "$WORK/prague.gpkg" "SELECT count(*) FROM segments") ]] &&
  pass "the installed module reads $count segments" || fail "segment count $count"
# mypy (Debian's, outside the venv) reads the venv's packages: a misuse is reported with the
# stub's types, which it can only know from the installed stub package.
cat >"$WORK/misuse.py" <<'PY'
import roadcross
zone: str = roadcross.Map("x.gpkg").info.utm_zone
PY
if out=$(cd "$WORK" && env -u PYTHONPATH /usr/bin/python3 -m mypy --no-incremental \
      --python-executable "$VENV_PY" misuse.py 2>&1); then
  fail "mypy accepted a misuse: $out"
elif grep -q 'Incompatible types in assignment (expression has type "int", variable has type "str")' <<<"$out"; then
  pass "mypy knows the installed module's types"
else
  fail "mypy: $out"
fi
# A wheel with Debian's python3-build (no isolation: offline).
if (cd "$WORK/src" && /usr/bin/python3 -m build --wheel --no-isolation --outdir "$WORK/dist" \
      >"$WORK/build.log" 2>&1); then
  wheel=$(ls "$WORK"/dist/roadcross-*.whl)
  # The listing whole, then searched: grep -q would close the pipe early (BrokenPipeError).
  listing=$(python3 -m zipfile -l "$wheel")
  grep -q "roadcross-stubs/py.typed" <<<"$listing" &&
    pass "python -m build: $(basename "$wheel") with the stubs" || fail "the wheel lacks the stubs"
else
  fail "python -m build: $(tail -20 "$WORK/build.log")"
fi
finish
