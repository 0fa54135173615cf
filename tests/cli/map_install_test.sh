#!/usr/bin/env bash
# roadcross install NEW TARGET: a verified copy renamed over TARGET. A process that has the old
# map open keeps answering from it throughout (a `roadcross batch` queried before, during and
# after); TARGET is never written in place (a hard link to the old file keeps its bytes); a
# map that fails verify and a TARGET that is not a regular file are refused, TARGET unchanged,
# no temporary file left behind.
source "$(dirname "$0")/lib.sh"

"$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/old.gpkg" -q
"$ROADCROSS_BUILD" --osm "$PRAGUE_OSM" -o "$WORK/new.gpkg" -q --segments.max_segment_length_m 20
id_of() { sqlite3 "$1" "SELECT value FROM roadcross_metadata WHERE key = 'map_id'"; }
old_id=$(id_of "$WORK/old.gpkg"); new_id=$(id_of "$WORK/new.gpkg")
mkdir "$WORK/robot"
target="$WORK/robot/map.gpkg"

# A first install: TARGET absent.
"$ROADCROSS" install "$WORK/old.gpkg" "$target" >"$WORK/out" 2>&1 && cmp -s "$WORK/old.gpkg" "$target" &&
  grep -q "map_id $old_id" "$WORK/out" && pass "first install: $(cat "$WORK/out")" || fail "first install: $(cat "$WORK/out")"
chmod 0640 "$target"
ln "$target" "$WORK/old-inode.gpkg"  # the old file itself, whatever happens to the name

# A robot process with the old map open, answering throughout the replacement.
python3 - "$ROADCROSS" "$target" "$WORK/new.gpkg" "$old_id" "$new_id" <<'PY' && pass "a running process kept answering from the old map; a new one opens the new map" || fail "live replacement"
import json, os, subprocess, sys
roadcross, target, new, old_id, new_id = sys.argv[1:]
query = '{"op":"assess","lat":50.075769,"lon":14.416015}\n'
# stdbuf preloads its library ahead of an ASan build's runtime, which ASan refuses unless told.
env = dict(os.environ, ASAN_OPTIONS=(os.environ.get("ASAN_OPTIONS", "") +
                                     ":verify_asan_link_order=0").lstrip(":"))
robot = subprocess.Popen(["stdbuf", "-oL", roadcross, "batch", "--db", target], env=env,
                         stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, bufsize=1)
def ask():
    robot.stdin.write(query); robot.stdin.flush()
    answer = json.loads(robot.stdout.readline())
    assert answer["ok"], answer
    return answer["result"]["segment_id"], answer["result"]["distance_m"]
before = ask()
# Segment ids differ between the two maps (10 m vs 20 m segments): an answer from the new file
# would show it.
installer = subprocess.Popen([roadcross, "install", new, target], stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT, text=True)
during = []
while installer.poll() is None:
    during.append(ask())
out = installer.communicate()[0]
assert installer.returncode == 0, out
after = [ask() for _ in range(50)]
robot.stdin.close()
assert robot.wait() == 0
assert all(a == before for a in during + after), (before, set(during + after))
fresh = json.loads(subprocess.run([roadcross, "batch", "--db", target], input=query, text=True,
                                  capture_output=True, check=True).stdout)
fresh = fresh["result"]
assert (fresh["segment_id"], fresh["distance_m"]) != before, "the new map answers like the old one"
info = json.loads(subprocess.run([roadcross, "info", "--json", target], capture_output=True,
                                 text=True, check=True).stdout)
assert info["map_id"] == new_id, info["map_id"]
print(f"{len(during)} answers during the install, {len(after)} after, all from the old map; "
      f"segment {before[0]} old, {fresh['segment_id']} new")
PY
cmp -s "$WORK/old.gpkg" "$WORK/old-inode.gpkg" && pass "the old file was never written (its inode keeps the old bytes)" ||
  fail "the old file changed in place"
[[ $(stat -c %a "$target") == 640 ]] && pass "the installed file keeps the target's mode 640" ||
  fail "mode $(stat -c %a "$target")"
cmp -s "$WORK/new.gpkg" "$target" && pass "TARGET is now a byte copy of NEW" || fail "TARGET differs from NEW"

no_leftovers() {
  local left
  left=$(find "$WORK/robot" -name '.*install-*')
  [[ -z $left ]] && pass "$1: no temporary file left" || fail "$1: left $left"
}
no_leftovers "after the install"

# A map that fails verify: refused, TARGET untouched.
cp "$WORK/old.gpkg" "$WORK/bad.gpkg"
sqlite3 "$WORK/bad.gpkg" "DROP TRIGGER rtree_segments_geom_update3; DROP TRIGGER rtree_segments_geom_update4; UPDATE segments SET score = score + 1 WHERE fid = 1"
expect_failure "a map failing verify" "segments.score differs" "left unchanged" -- "$ROADCROSS" install "$WORK/bad.gpkg" "$target"
cmp -s "$WORK/new.gpkg" "$target" && pass "refused: TARGET unchanged" || fail "refused, but TARGET changed"
expect_failure "--expect-id of another map" "expected $old_id" -- "$ROADCROSS" install --expect-id "$old_id" "$WORK/new.gpkg" "$target"
no_leftovers "after the refusals"

# TARGETs that are not regular files. The device is a private node in this test's directory
# (a copy of the null device's numbers), never one of the machine's.
mkdir "$WORK/robot/dir.gpkg"
mkfifo "$WORK/robot/fifo.gpkg"
ln -s "$target" "$WORK/robot/link.gpkg"
kinds=(dir.gpkg fifo.gpkg link.gpkg)
if mknod "$WORK/robot/device.gpkg" c 1 3 2>/dev/null; then
  kinds+=(device.gpkg)
else
  echo "note: mknod not permitted here; the device case is not run"
fi
for kind in "${kinds[@]}"; do
  expected="not a regular file"
  [[ $kind == link.gpkg ]] && expected="is a symbolic link"
  expect_failure "TARGET $kind" "$kind: $expected" -- "$ROADCROSS" install "$WORK/new.gpkg" "$WORK/robot/$kind"
done
[[ -d $WORK/robot/dir.gpkg && -p $WORK/robot/fifo.gpkg && -L $WORK/robot/link.gpkg ]] &&
  pass "the directory, FIFO and link are still what they were" || fail "a refused TARGET was replaced"
[[ ! -e $WORK/robot/device.gpkg || -c $WORK/robot/device.gpkg ]] && pass "the device node is still one" ||
  fail "the device node was replaced"
no_leftovers "after the refused targets"
expect_failure "TARGET in a missing directory" "nowhere" -- "$ROADCROSS" install "$WORK/new.gpkg" "$WORK/nowhere/map.gpkg"
finish
