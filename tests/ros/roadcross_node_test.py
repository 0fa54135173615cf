#!/usr/bin/python3
"""roadcross_node end to end: a ROS master on a free local port, the node started by its launch
file on the bundled Prague map, every service called and the published assessment read with
rospy. Answers are compared with the `roadcross` CLI on the same DB and position (an independent
process and output path), and headings and monitor states with values derived by hand.
Every process this test starts is stopped on exit.

Environment (set by tests/CMakeLists.txt): ROADCROSS, ROADCROSS_BUILD, ROADCROSS_MAPS_DIR,
ROADCROSS_ROS_DEVEL (the build tree's devel space), ROADCROSS_NODE (the node executable).
"""
import json
import math
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

ENV = os.environ
try:
    DEVEL = ENV["ROADCROSS_ROS_DEVEL"]
    ROADCROSS = ENV["ROADCROSS"]
    NODE = ENV["ROADCROSS_NODE"]
    OSM = os.path.join(ENV["ROADCROSS_MAPS_DIR"], "prague", "prague_nove_mesto_roads_2017.osm")
    BUILD = ENV["ROADCROSS_BUILD"]
except KeyError as e:
    sys.exit(f"missing environment variable {e}: run through ctest")

sys.path.insert(0, os.path.join(DEVEL, "lib", "python3", "dist-packages"))
try:
    import rosgraph
    import rospy
    from geometry_msgs.msg import Quaternion
    from nav_msgs.msg import Odometry
    from sensor_msgs.msg import NavSatFix, NavSatStatus
except ImportError as e:  # setup.sh installs these; say what is missing instead of failing
    print(f"SKIPPED: ROS Python packages absent ({e}); run scripts/setup.sh")
    sys.exit(77)
from roadcross_ros.msg import Assessment, Position, TrackedVehicle, VehicleList
from roadcross_ros.srv import Assess, BetterPlace, GapDecision, Monitor, Reload, RoadHeading
from diagnostic_msgs.msg import DiagnosticArray

FAILURES = []
PROCESSES = []  # (Popen, name): every process group we started, stopped in stop_all()
WORK = tempfile.mkdtemp(prefix="roadcross_ros_test.")


def check(condition, what):
    if condition:
        print(f"ok: {what}")
    else:
        print(f"FAIL: {what}", file=sys.stderr)
        FAILURES.append(what)
    return condition


def near(a, b, tol):
    return a is not None and b is not None and abs(a - b) <= tol


def children_of(pid):
    """Every live descendant of pid (roslaunch starts each node in a session of its own, so
    the process group of roslaunch does not hold them)."""
    parents = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat") as f:
                    parents[int(entry)] = int(f.read().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                pass
    found, frontier = [], [pid]
    while frontier:
        parent = frontier.pop()
        kids = [p for p, pp in parents.items() if pp == parent]
        found += kids
        frontier += kids
    return found


def alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    # A zombie is dead; only its parent has yet to reap it.
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def stop_all():
    for proc, name in reversed(PROCESSES):
        descendants = children_of(proc.pid)
        if proc.poll() is None:
            # SIGINT first: roslaunch then shuts its nodes down cleanly; SIGTERM, SIGKILL after.
            for sig, wait_s in [(signal.SIGINT, 20), (signal.SIGTERM, 5), (signal.SIGKILL, 5)]:
                os.killpg(proc.pid, sig)
                try:
                    proc.wait(timeout=wait_s)
                    break
                except subprocess.TimeoutExpired:
                    continue
        # Nothing it started may survive it (roslaunch's nodes included).
        deadline = time.time() + 5
        while any(alive(p) for p in descendants) and time.time() < deadline:
            time.sleep(0.1)
        for pid in descendants:
            if alive(pid):
                os.kill(pid, signal.SIGKILL)
                check(False, f"{name}: its child {pid} outlived it")
    PROCESSES.clear()


def start(cmd, name, env):
    log = open(os.path.join(WORK, name + ".log"), "w")
    proc = subprocess.Popen(cmd, env=env, stdout=log, stderr=subprocess.STDOUT,
                            start_new_session=True)
    PROCESSES.append((proc, name))
    return proc


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def cli(*args, stdin=""):
    out = subprocess.run([ROADCROSS, *args, "--json"], input=stdin, capture_output=True,
                         text=True, check=True)
    return json.loads(out.stdout)


def wgs84(lat, lon):
    return Position(kind=Position.WGS84, latitude_deg=lat, longitude_deg=lon)


def utm(e, n):
    return Position(kind=Position.UTM, easting_m=e, northing_m=n)


def normalize(a):
    a = math.fmod(a + math.pi, 2 * math.pi)
    if a <= 0:
        a += 2 * math.pi
    return a - math.pi


def ang_diff(a, b):
    return abs(normalize(a - b))


def same_assessment(node, ref, what):
    """The node's Assessment against `roadcross assess --json` at the same position."""
    ok = (node.valid == ref["valid"] and node.suitable == ref["suitable"]
          and list(node.reasons) == ref["reasons"] and node.segment_id == ref["segment_id"]
          and node.osm_way_id == ref["osm_way_id"] and node.highway == ref["highway"]
          and node.name == ref["name"] and near(node.distance_m, ref["distance_m"], 1e-6)
          and near(node.closest_easting_m, ref["closest_utm_m"][0], 1e-6)
          and near(node.closest_northing_m, ref["closest_utm_m"][1], 1e-6)
          and node.has_score == (ref["score"] is not None)
          and (not node.has_score or (node.score == ref["score"]
                                      and node.context_score == ref["context_score"]))
          and node.threshold == ref["threshold"]
          and node.valid_distance_m == ref["valid_distance_m"]
          and node.rank == (ref["rank"] if ref["rank"] is not None else -1)
          and node.lanes == (ref["lanes"] if ref["lanes"] is not None else -1)
          and (math.isnan(node.maxspeed_kmh) if ref["maxspeed_kmh"] is None
               else node.maxspeed_kmh == ref["maxspeed_kmh"])
          and (math.isnan(node.junction_distance_m) if ref["junction_distance_m"] is None
               else near(node.junction_distance_m, ref["junction_distance_m"], 1e-9))
          and node.tunnel == ref["tunnel"] and node.error == ""
          and len(node.reason_sentences) == len(node.reasons))
    return check(ok, f"{what}: same as `roadcross assess` (suitable={ref['suitable']}, "
                     f"reasons={ref['reasons']}, score={ref['score']}+{ref['context_score']})")


def main():
    db = os.path.join(WORK, "prague.gpkg")
    subprocess.run([BUILD, "--osm", OSM, "-o", db, "-q"], check=True)

    port = free_port()
    env = dict(ENV)
    env.update({
        "ROS_MASTER_URI": f"http://127.0.0.1:{port}",
        "ROS_IP": "127.0.0.1",
        "ROS_HOME": os.path.join(WORK, "ros_home"),
        "CMAKE_PREFIX_PATH": DEVEL,
        "ROS_PACKAGE_PATH": os.path.join(DEVEL, "share"),
        "PYTHONPATH": os.path.join(DEVEL, "lib", "python3", "dist-packages") + os.pathsep +
                      ENV.get("PYTHONPATH", ""),
    })
    os.environ.update(env)  # for rospy in this process
    start(["rosmaster", "--core", "-p", str(port)], "rosmaster", env)
    master = rosgraph.Master("/roadcross_test")
    deadline = time.time() + 30
    while not master.is_online():
        if time.time() > deadline:
            sys.exit("rosmaster did not come up in 30 s")
        time.sleep(0.2)
    print(f"ok: rosmaster on port {port}")

    not_only_maps = os.path.join(WORK, "not_only_maps")
    os.makedirs(not_only_maps, exist_ok=True)
    shutil.copy(db, os.path.join(not_only_maps, "map.gpkg"))
    with open(os.path.join(not_only_maps, "notes.txt"), "w") as f:
        f.write("not a map\n")

    # Bad parameters: the node exits non-zero with a message naming the parameter or file.
    for index, (args, expected, what) in enumerate([
        ([], "parameter ~db is not set", "no ~db"),
        (["_db:=" + os.path.join(WORK, "missing.gpkg")], "cannot open ~db '" +
         os.path.join(WORK, "missing.gpkg"), "missing DB file"),
        (["_db:=" + db, "_max_distance_m:=-5"], "~max_distance_m = -5 is out of range",
         "negative ~max_distance_m"),
        (["_db:=" + db, "_gap/policy:=fast"], "~gap/policy = 'fast'", "unknown ~gap/policy"),
        # A list of maps (a set): the one that cannot be opened is named.
        (["_db:=[" + db + ", " + os.path.join(WORK, "missing.gpkg") + "]"],
         os.path.join(WORK, "missing.gpkg") + ": no such file", "a missing map in a list"),
        (["_db:=" + not_only_maps], os.path.join(not_only_maps, "notes.txt"),
         "a directory with a file that is not a map"),
    ]):
        name = f"bad_parameters_{index}"
        res = subprocess.run([NODE, "__name:=" + name, *args], env=env, capture_output=True,
                             text=True, timeout=60)
        text = res.stdout + res.stderr
        check(res.returncode != 0 and expected in text,
              f"{what}: exit {res.returncode}, says '{expected}'" +
              ("" if expected in text else f" (it said: {text.strip()[-400:]})"))
        subprocess.run(["rosparam", "delete", "/" + name], env=env, capture_output=True)

    # No --wait: the master is up, and on a fresh master roslaunch --wait hangs in its first
    # getParam (Debian 12, Python 3.11).
    start(["roslaunch", "roadcross_ros", "roadcross.launch", "db:=" + db,
           "fix_topic:=/gps/fix", "odom_topic:=/odom", "vehicles_topic:=/tracks"],
          "roslaunch", env)
    rospy.init_node("roadcross_test", anonymous=True, disable_signals=True)
    for service in ["assess", "better_place", "road_heading", "monitor", "gap_decision"]:
        rospy.wait_for_service("/roadcross/" + service, timeout=120)
    print("ok: the launch file started the node with its five services")
    assess = rospy.ServiceProxy("/roadcross/assess", Assess)
    better = rospy.ServiceProxy("/roadcross/better_place", BetterPlace)
    heading = rospy.ServiceProxy("/roadcross/road_heading", RoadHeading)
    monitor = rospy.ServiceProxy("/roadcross/monitor", Monitor)
    gap = rospy.ServiceProxy("/roadcross/gap_decision", GapDecision)

    # Before any fix, CURRENT has no answer, and says why.
    r = assess(position=Position(kind=Position.CURRENT))
    check(not r.success and "no GPS fix received yet on /gps/fix" in r.message,
          f"assess CURRENT before a fix: {r.message}")
    r = assess(position=wgs84(95.0, 14.4))
    check(not r.success and "95" in r.message, f"assess at latitude 95: {r.message}")

    # --- assess: Resslova (busy primary road, not suitable) and a quiet street by a zebra.
    resslova = (50.075769, 14.416015)
    # (where the DB sees 248 m / 300 m along the road, so that the vehicles decide the gap)
    quiet = (50.071493, 14.426372)
    for lat, lon in [resslova, quiet]:
        r = assess(position=wgs84(lat, lon))
        check(r.success, f"assess {lat},{lon} succeeds")
        same_assessment(r.assessment, cli("assess", "--db", db, "--lat", str(lat), "--lon",
                                          str(lon)), f"assess {lat},{lon}")
    ref_r = cli("assess", "--db", db, "--lat", str(resslova[0]), "--lon", str(resslova[1]))
    check(not ref_r["suitable"], "Resslova is not a place to cross (README)")
    ref_q = cli("assess", "--db", db, "--lat", str(quiet[0]), "--lon", str(quiet[1]))
    check(ref_q["suitable"], "the quiet street is a place to cross (README)")
    # UTM input and a threshold override.
    qe, qn = r.assessment.query_easting_m, r.assessment.query_northing_m
    r = assess(position=utm(qe, qn), use_threshold=True, threshold=99.0)
    same_assessment(r.assessment, cli("assess", "--db", db, "--utm", str(qe), str(qn),
                                      "--threshold", "99"), "assess UTM, threshold 99")
    check(not r.assessment.suitable and "LOW_SCORE" in r.assessment.reasons,
          "threshold 99: not suitable, LOW_SCORE")

    # --- road heading at Resslova, against the CLI and by hand.
    h = heading(position=wgs84(*resslova))
    ref = cli("heading", "--db", db, "--lat", str(resslova[0]), "--lon", str(resslova[1]))
    check(h.success and h.segment_id == ref["segment_id"]
          and near(h.road_grid_yaw_rad, ref["road_heading_rad"], 1e-12)
          and near(h.crossing_grid_yaw_rad, ref["crossing_heading_rad"], 1e-12)
          and near(h.convergence_rad, ref["convergence_rad"], 1e-12)
          and h.on_centreline == ref["on_centreline"],
          "road heading: grid yaws and convergence as `roadcross heading`")
    # Meridian convergence by hand: UTM zone 33 (central meridian 15 E); to first order the
    # grid is turned by (lon - 15 deg) sin(lat) clockwise, so true = grid - that.
    conv = -math.radians(resslova[1] - 15.0) * math.sin(math.radians(resslova[0]))
    check(near(h.convergence_rad, conv, 2e-5),
          f"convergence {h.convergence_rad:.6f} rad = -(lon - 15) sin(lat) = {conv:.6f}")
    check(near(normalize(h.road_grid_yaw_rad + conv), h.road_yaw_rad, 2e-5)
          and near(normalize(h.crossing_grid_yaw_rad + conv), h.crossing_yaw_rad, 2e-5),
          "road and crossing yaws are true ENU = grid + convergence")
    # Resslova runs west from node 25936560 (50.0757619, 14.4165932) to node 21456616
    # (50.0756926, 14.4155482): true ENU yaw of that chord on a local tangent plane.
    d_north = math.radians(50.0756926 - 50.0757619) * 6371000.0
    d_east = math.radians(14.4155482 - 14.4165932) * 6371000.0 * math.cos(math.radians(50.0757))
    chord_yaw = math.atan2(d_north, d_east)
    check(ang_diff(h.road_yaw_rad, chord_yaw) < 0.03,
          f"Resslova's true yaw {h.road_yaw_rad:.4f} = its OSM chord's {chord_yaw:.4f} (westwards)")
    # The robot stands north of the road (query northing > closest): it faces south across a
    # westward road, i.e. the road's yaw + pi/2 (a left turn from the road's direction).
    north_of_road = ref["query_utm_m"][1] > ref["closest_utm_m"][1]
    check(north_of_road and ang_diff(h.crossing_yaw_rad, normalize(chord_yaw + math.pi / 2)) < 0.03
          and math.sin(h.crossing_yaw_rad) < -0.99,
          f"crossing yaw {h.crossing_yaw_rad:.4f}: chord yaw + pi/2, southwards across the road")
    q = h.crossing_orientation
    check(near(2 * math.atan2(q.z, q.w), h.crossing_yaw_rad, 1e-9) and q.x == 0 and q.y == 0,
          "crossing orientation: quaternion of the crossing yaw about +z")

    # --- better place near Resslova (200 m, as the README).
    b = better(position=wgs84(*resslova), search_radius_m=200.0)
    ref = cli("better", "--db", db, "--lat", str(resslova[0]), "--lon", str(resslova[1]),
              "--radius", "200")
    ok = b.success and len(b.candidates) == len(ref["candidates"]) > 0 and b.reason == ref["reason"]
    for c, rc in zip(b.candidates, ref["candidates"]):
        nh = cli("heading", "--db", db, "--utm", str(c.easting_m), str(c.northing_m))
        back = cli("nearest", "--db", db, "--lat", repr(c.latitude_deg), "--lon",
                   repr(c.longitude_deg))
        ok = ok and (near(c.easting_m, rc["point_utm_m"][0], 1e-6)
                     and near(c.northing_m, rc["point_utm_m"][1], 1e-6)
                     and near(c.walking_distance_m, rc["walking_distance_m"], 1e-6)
                     and c.segment_id == rc["segment_id"] and c.suitable == rc["suitable"]
                     and c.score == rc["score_plus_context"]
                     and c.designated_crossing == rc["designated_crossing"]
                     and list(c.reasons) == rc["reasons"]
                     and near(c.crossing_yaw_rad,
                              normalize(rc["crossing_heading_rad"] + nh["convergence_rad"]), 1e-9)
                     # its latitude/longitude project back onto its UTM point
                     and near(back["query_utm_m"][0], c.easting_m, 1e-3)
                     and near(back["query_utm_m"][1], c.northing_m, 1e-3))
    check(ok, f"better place: {len(b.candidates)} candidates as `roadcross better`, "
              "true yaws, WGS84 round trip")
    b2 = better(position=wgs84(*resslova), search_radius_m=200.0, max_candidates=2)
    check(b2.success and len(b2.candidates) == min(2, len(ref["candidates"])),
          "better place: max_candidates 2")

    # --- monitor: a crossing planned at the quiet street.
    ref_plan = cli("monitor", "--db", db, "--lat", str(quiet[0]), "--lon", str(quiet[1]),
                   "--at", "0", "0", "--yaw", "0")
    (se, sn), (te, tn) = ref_plan["plan_start_utm_m"], ref_plan["plan_target_utm_m"]
    grid_yaw = ref_plan["plan_heading_rad"]
    qh = cli("heading", "--db", db, "--lat", str(quiet[0]), "--lon", str(quiet[1]))
    conv_q = qh["convergence_rad"]
    left = (-math.sin(grid_yaw), math.cos(grid_yaw))
    cases = [  # pose (UTM E, N, grid yaw), expected state, progress, lateral (by hand)
        ((se + (te - se) / 2, sn + (tn - sn) / 2, grid_yaw), "ON_TRACK", 0.5, 0.0),
        ((se + (te - se) / 2 + left[0], sn + (tn - sn) / 2 + left[1], grid_yaw),
         "DRIFTING", 0.5, 1.0),
        ((se + (te - se) / 4 - 2 * left[0], sn + (tn - sn) / 4 - 2 * left[1], grid_yaw),
         "LEAVING_CORRIDOR", 0.25, -2.0),
        ((te, tn, grid_yaw), "DONE", 1.0, 0.0),
    ]
    for (e, n, yaw), state, progress, lateral in cases:
        m = monitor(start=wgs84(*quiet), easting_m=e, northing_m=n, yaw_rad=yaw + conv_q)
        rc = cli("monitor", "--db", db, "--lat", str(quiet[0]), "--lon", str(quiet[1]), "--at",
                 str(e), str(n), "--yaw", str(yaw))
        check(m.success and m.state_name == state == rc["state"]
              and near(m.progress, progress, 1e-6) and near(m.progress, rc["progress"], 1e-9)
              and near(m.lateral_deviation_m, lateral, 1e-6)
              and near(m.lateral_deviation_m, rc["lateral_deviation_m"], 1e-9)
              and near(m.heading_error_rad, rc["heading_error_rad"], 1e-9)
              and near(m.heading_error_rad, 0.0, 1e-6)
              and near(m.plan_yaw_rad, normalize(grid_yaw + conv_q), 1e-9)
              and near(m.target_easting_m, te, 1e-9),
              f"monitor: {state} at progress {progress}, lateral {lateral:+.1f} m (hand and CLI)")
    m = monitor(start=Position(kind=Position.CURRENT))
    check(not m.success and "not CURRENT" in m.message, f"monitor from CURRENT: {m.message}")

    # --- the published assessment, the fix as CURRENT, and the odometry yaw for the monitor.
    received = []
    sub = rospy.Subscriber("/roadcross/assessment", Assessment, received.append)
    fix_pub = rospy.Publisher("/gps/fix", NavSatFix, queue_size=10)
    odom_pub = rospy.Publisher("/odom", Odometry, queue_size=10)
    tracks_pub = rospy.Publisher("/tracks", VehicleList, queue_size=10)
    deadline = time.time() + 30
    while (fix_pub.get_num_connections() == 0 or sub.get_num_connections() == 0
           or odom_pub.get_num_connections() == 0 or tracks_pub.get_num_connections() == 0):
        if time.time() > deadline:
            check(False, "the node did not connect to /gps/fix, /odom, /tracks, ~assessment")
            return
        time.sleep(0.1)

    def publish_fix(lat, lon, status, covariance=None, covariance_type=0):
        fix = NavSatFix()
        fix.header.stamp = rospy.Time.now()
        fix.header.frame_id = "gps"
        fix.status.status = status
        fix.latitude, fix.longitude = lat, lon
        if covariance is not None:
            fix.position_covariance = covariance
        fix.position_covariance_type = covariance_type
        fix_pub.publish(fix)
        return fix.header.stamp

    publish_fix(quiet[0], quiet[1], NavSatStatus.STATUS_NO_FIX)
    time.sleep(1.0)
    check(not received, "a fix without a position (STATUS_NO_FIX) is not assessed")
    stamp = publish_fix(*quiet, NavSatStatus.STATUS_FIX)
    deadline = time.time() + 10
    while not received and time.time() < deadline:
        time.sleep(0.05)
    if check(len(received) == 1, "one assessment published for the fix"):
        a = received[0]
        same_assessment(a, ref_q, "published assessment")
        check(a.header.stamp == stamp and a.header.frame_id == "utm",
              "published assessment: the fix's stamp, frame utm")
    # A fix whose covariance is known (DIAGONAL_KNOWN, 9 m^2 east and north: a circular 3 m
    # sigma, the same in any frame) is assessed over its region, as `roadcross assess --sigma 3`;
    # the same covariance marked UNKNOWN is not used (~uncertainty/sigma_m is 0: exact).
    ref_s = cli("assess", "--db", db, "--lat", str(quiet[0]), "--lon", str(quiet[1]),
                "--sigma", "3")
    received.clear()
    publish_fix(*quiet, NavSatStatus.STATUS_FIX, [9.0, 0, 0, 0, 9.0, 0, 0, 0, 100.0],
                NavSatFix.COVARIANCE_TYPE_DIAGONAL_KNOWN)
    deadline = time.time() + 10
    while not received and time.time() < deadline:
        time.sleep(0.05)
    if check(len(received) == 1, "one assessment published for the fix with a covariance"):
        a = received[0]
        check(a.uncertain and list(a.region_segment_ids) == ref_s["region"]["segment_ids"]
              and near(a.suitable_share, ref_s["region"]["suitable_share"], 1e-9)
              and a.suitable == ref_s["suitable"] and list(a.reasons) == ref_s["reasons"]
              and near(a.region_semi_major_m, ref_s["region"]["semi_major_m"], 1e-9),
              "published assessment with a known covariance: as `roadcross assess --sigma 3` "
              f"(share {a.suitable_share:.3f})")
    r = assess(position=Position(kind=Position.CURRENT))
    check(r.success and r.assessment.uncertain, "assess CURRENT: the fix's covariance")
    r = assess(position=Position(kind=Position.CURRENT, sigma_m=1.0))
    check(r.success and near(r.assessment.region_semi_major_m, 2.4477, 1e-3),
          "assess CURRENT with the request's sigma_m 1: its own region")
    received.clear()
    publish_fix(*quiet, NavSatStatus.STATUS_FIX, [9.0, 0, 0, 0, 9.0, 0, 0, 0, 100.0],
                NavSatFix.COVARIANCE_TYPE_UNKNOWN)
    deadline = time.time() + 10
    while not received and time.time() < deadline:
        time.sleep(0.05)
    check(len(received) == 1 and not received[0].uncertain,
          "a covariance of unknown type is not used")
    r = assess(position=Position(kind=Position.CURRENT))
    check(r.success and near(r.assessment.query_easting_m, qe, 1e-6)
          and near(r.assessment.query_northing_m, qn, 1e-6),
          "assess CURRENT: the latest fix's position")
    same_assessment(r.assessment, ref_q, "assess CURRENT")
    # Odometry yaw (true ENU) facing 0.2 rad left of the plan, at the fix (the plan's start).
    odom = Odometry()
    odom.header.stamp = rospy.Time.now()
    yaw = normalize(grid_yaw + conv_q + 0.2)
    odom.pose.pose.orientation = Quaternion(0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2))
    odom_pub.publish(odom)
    time.sleep(0.5)
    publish_fix(*quiet, NavSatStatus.STATUS_FIX)
    time.sleep(0.5)
    m = monitor(start=wgs84(*quiet), use_current_pose=True)
    check(m.success and near(m.heading_error_rad, 0.2, 1e-6) and m.state_name == "ON_TRACK"
          and near(m.progress, 0.0, 1e-6),
          f"monitor from the fix and odometry: heading error {m.heading_error_rad:.4f} = 0.2, "
          f"{m.state_name} (tolerance 0.35 rad)")

    # --- gap decision at the quiet street, against `roadcross gap` with the same vehicles.
    road_yaw = qh["road_heading_rad"]
    ce, cn = qh["closest_utm_m"]
    u = (math.cos(road_yaw), math.sin(road_yaw))

    right = (-u[1], u[0])  # right of the direction -u the cars drive in: their lane's side

    def vehicle_utm(dist_m, speed_mps, age_s=0.0, now=None):
        """A car dist_m up the road (along the way's direction), in the middle of its lane
        (1.6 m right of the centreline), driving towards the crossing."""
        v = TrackedVehicle(frame=TrackedVehicle.FRAME_UTM, x_m=ce + dist_m * u[0] + 1.6 * right[0],
                           y_m=cn + dist_m * u[1] + 1.6 * right[1], vx_mps=-speed_mps * u[0],
                           vy_mps=-speed_mps * u[1], speed_uncertainty_mps=-1.0)
        if age_s:
            v.stamp = now - rospy.Duration.from_sec(age_s)
        line = {"easting": v.x_m, "northing": v.y_m, "vx_mps": v.vx_mps, "vy_mps": v.vy_mps}
        if age_s:
            line["age_s"] = age_s
        return v, json.dumps(line)

    now = rospy.Time.now()
    scenarios = [
        ("no vehicles", [], "ours"),
        ("a car 40 m away at 14 m/s", [vehicle_utm(40.0, 14.0)], "ours"),
        ("a car 150 m away at 8 m/s", [vehicle_utm(150.0, 8.0)], "ours"),
        ("a car 40 m away, HCM", [vehicle_utm(40.0, 14.0)], "hcm"),
        ("a stale track (2 s old)", [vehicle_utm(150.0, 8.0, age_s=2.0, now=now)], "ours"),
    ]
    expected_reasons = {}
    for what, vehicles, policy in scenarios:
        msg = VehicleList(vehicles=[v for v, _ in vehicles])
        msg.header.stamp = now
        g = gap(position=wgs84(*quiet), vehicles=msg, policy=policy)
        rc = cli("gap", "--db", db, "--lat", str(quiet[0]), "--lon", str(quiet[1]), "--policy",
                 policy, stdin="\n".join(line for _, line in vehicles) + "\n")

        def same(x, y):
            return (y is None and math.isnan(x)) or (y is not None and near(x, y, 1e-9))

        check(g.success and g.verdict == rc["decision"] and g.go == (rc["decision"] == "GO")
              and g.reason == rc["reason"] and g.limiting_vehicle == rc["limiting_vehicle"]
              and same(g.margin_s, rc["margin_s"])
              and same(g.earliest_start_in_s, rc["earliest_start_in_s"])
              and near(g.crossing_time_s, rc["crossing_time_s"], 1e-9)
              and near(g.required_sight_m, rc["required_sight_m"], 1e-9)
              and near(g.visible_road_m, rc["visible_road_m"], 1e-9)
              and near(g.critical_gap_s, rc["critical_gap_s"], 1e-9)
              and g.vehicles_counted == rc["vehicles_counted"]
              and g.stale_tracks == rc["stale_tracks"] and g.lanes == rc["lanes"]
              and near(g.road_width_m, rc["road_width_m"], 1e-9)
              and near(g.crossing_yaw_rad, normalize(rc["crossing_heading_rad"] + conv_q), 1e-9),
              f"gap, {what}: {g.verdict} {g.reason} as `roadcross gap` (margin {g.margin_s:.2f} s)")
        expected_reasons[what] = g.reason
    # Hand-derived: a car 40 m away at 14 m/s arrives in < 3 s, before a robot that needs
    # several seconds to cross; a 2 s old track is stale (max age 0.5 s).
    check(expected_reasons["a car 40 m away at 14 m/s"] == "VEHICLE_CONFLICT",
          "a car 40 m away at 14 m/s: WAIT VEHICLE_CONFLICT")
    check(expected_reasons["a car 40 m away, HCM"] == "GAP_TOO_SHORT",
          "HCM: a car 2.9 s away is inside the critical gap")
    check(expected_reasons["a stale track (2 s old)"] == "STALE_TRACK", "2 s old track: STALE_TRACK")
    # The tracker's topic instead of the request.
    v, _ = vehicle_utm(40.0, 14.0)
    tracks = VehicleList(vehicles=[v])
    tracks.header.stamp = rospy.Time.now()
    tracks_pub.publish(tracks)
    time.sleep(0.5)
    g = gap(position=wgs84(*quiet), use_latest_vehicles=True)
    check(g.success and g.reason == "VEHICLE_CONFLICT" and g.vehicles_counted == 1,
          f"gap from the latest list on /tracks: {g.verdict} {g.reason}")
    bad = TrackedVehicle(frame=7, x_m=ce, y_m=cn, vx_mps=1.0, length_m=4.0)
    g = gap(position=wgs84(*quiet), vehicles=VehicleList(vehicles=[bad]))
    check(not g.success and "frame 7" in g.message, f"gap with a bad frame: {g.message}")

    map_identity_and_reload(db, assess, quiet)

    # The node is still alive after all of this.
    check(PROCESSES[-1][0].poll() is None, "roslaunch and the node are still running")


def latest_diagnostics(timeout_s=10.0):
    """The next /diagnostics message's "roadcross: map" status as a dict of its values."""
    msg = rospy.wait_for_message("/diagnostics", DiagnosticArray, timeout=timeout_s)
    for status in msg.status:
        if status.name == "roadcross: map":
            return {kv.key: kv.value for kv in status.values}
    return {}


def map_identity_and_reload(db, assess, position):
    """map_id in the answers and on /diagnostics, as `roadcross info` reads it from the file;
    ~reload swaps to another map while a second thread keeps querying: no query fails and the
    answers' map_id changes once, from the old map's to the new one's."""
    import threading
    old_id = cli("info", db)["map_id"]
    r = assess(position=wgs84(*position))
    check(r.map_id == old_id and r.assessment.map_id == old_id,
          f"assess answers carry the map's map_id {old_id[:12]}")
    diag = latest_diagnostics()
    check(diag.get("map_id") == old_id and diag.get("path") == db,
          f"/diagnostics carries map_id and path: {diag}")

    # Another map: the same OSM input with 20 m segments (another content, so another id).
    new_db = os.path.join(WORK, "prague-20m.gpkg")
    subprocess.run([BUILD, "--osm", OSM, "-o", new_db, "-q",
                    "--segments.max_segment_length_m", "20"], check=True)
    new_id = cli("info", new_db)["map_id"]
    check(new_id != old_id, "a map with other parameters has another map_id")

    reload = rospy.ServiceProxy("/roadcross/reload", Reload)
    seen, errors, stop = [], [], threading.Event()
    querier = rospy.ServiceProxy("/roadcross/assess", Assess, persistent=True)

    def query_until_stopped():
        while not stop.is_set():
            try:
                a = querier(position=wgs84(*position))
                seen.append(a.map_id if a.success else "failed: " + a.message)
            except Exception as e:  # a dropped call
                errors.append(str(e))

    thread = threading.Thread(target=query_until_stopped)
    thread.start()
    time.sleep(1.0)
    before = len(seen)
    res = reload(path=new_db)
    time.sleep(1.0)
    stop.set()
    thread.join()
    check(res.success and res.map_id == new_id and res.previous_map_id == old_id and
          res.path == new_db, f"reload to {new_db}: {res.message}")
    changes = sum(1 for a, b in zip(seen, seen[1:]) if a != b)
    check(not errors and seen and seen[0] == old_id and seen[-1] == new_id and changes == 1 and
          before > 0, f"{len(seen)} queries during the reload, none dropped or failed "
          f"({len(errors)} errors, {changes} change of map_id)")
    diag = latest_diagnostics()
    check(diag.get("map_id") == new_id and diag.get("path") == new_db,
          "/diagnostics names the new map after the reload")
    # A map that cannot be opened: refused, the node keeps answering from the one it had.
    res = reload(path=os.path.join(WORK, "missing.gpkg"))
    check(not res.success and res.map_id == new_id and "missing.gpkg" in res.message,
          f"reload of a missing file is refused, the map stays: {res.message}")
    check(assess(position=wgs84(*position)).map_id == new_id, "still answering from the new map")
    # No path: reopen the current one (what a robot does after `roadcross install`).
    res = reload(path="")
    check(res.success and res.map_id == new_id and res.path == new_db,
          f"reload without a path reopens {res.path}")


def installed_package():
    """`cmake --install --component ros` lays out a prefix in which roslaunch finds the node,
    the launch file and the Python messages, as in the build tree's devel space."""
    prefix = os.path.join(WORK, "prefix")
    subprocess.run([ENV["CMAKE_COMMAND"], "--install", ENV["ROADCROSS_BINARY_DIR"], "--component",
                    "ros", "--prefix", prefix], check=True, capture_output=True)
    env = dict(ENV, CMAKE_PREFIX_PATH=prefix, ROS_PACKAGE_PATH=os.path.join(prefix, "share"),
               PYTHONPATH=os.path.join(prefix, "lib", "python3", "dist-packages"),
               ROS_HOME=os.path.join(WORK, "ros_home"))
    probe = ("import roslib.packages\n"
             "from roadcross_ros.srv import GapDecision\n"
             "print(roslib.packages.find_node('roadcross_ros', 'roadcross_node')[0])\n")
    res = subprocess.run(["/usr/bin/python3", "-c", probe], env=env, capture_output=True,
                         text=True)
    node = os.path.join(prefix, "lib", "roadcross_ros", "roadcross_node")
    check(res.returncode == 0 and res.stdout.strip() == node and os.access(node, os.X_OK),
          f"installed: roslaunch finds {res.stdout.strip() or res.stderr.strip()}")
    res = subprocess.run(["roslaunch", "--nodes", "roadcross_ros", "roadcross.launch", "db:=x"],
                         env=env, capture_output=True, text=True)
    check(res.returncode == 0 and res.stdout.strip() == "/roadcross",
          "installed: the launch file parses and names the node /roadcross")
    check(os.path.exists(os.path.join(prefix, "include", "roadcross_ros", "GapDecision.h")),
          "installed: C++ message headers")


if __name__ == "__main__":
    status = 0
    try:
        main()
        installed_package()
    except Exception as e:  # report, then clean up
        import traceback
        traceback.print_exc()
        FAILURES.append(f"exception: {e}")
    finally:
        try:
            rospy.signal_shutdown("test done")
        except Exception:
            pass
        stop_all()
        if FAILURES:
            for name in ("roslaunch", "rosmaster"):
                path = os.path.join(WORK, name + ".log")
                if os.path.exists(path):
                    print(f"--- {name}.log (tail)", file=sys.stderr)
                    print("".join(open(path).readlines()[-30:]), file=sys.stderr)
        shutil.rmtree(WORK, ignore_errors=True)
    if FAILURES:
        print(f"{len(FAILURES)} check(s) failed", file=sys.stderr)
        sys.exit(1)
    print("all checks passed")
