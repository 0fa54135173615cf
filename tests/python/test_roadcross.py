"""Tests of the roadcross Python module, run by ctest with Debian's /usr/bin/python3.

Values are compared with the `roadcross` CLI's --json output for the same map and positions:
the CLI is an independent path (C++, nlohmann::json) to the same runtime, so every field must be
equal exactly (JSON doubles round-trip). Other checks are derived by hand: a position 500 m from
the only road, the crossing heading perpendicular to the road, monitor on a plan drawn by hand,
and the exceptions for a missing file, a non-roadcross file and a NaN latitude.

Environment (set by tests/CMakeLists.txt): PYTHONPATH (the built module), ROADCROSS (the CLI),
ROADCROSS_BUILD (roadcross-build; absent in the runtime-only build, where the tests that need a
map are skipped), ROADCROSS_TEST_DATA_DIR, ROADCROSS_MAPS_DIR, ROADCROSS_BINARY_DIR, CMAKE_COMMAND.
"""

import contextlib
import json
import math
import os
import re
import shutil
import sqlite3
import subprocess
import sys
import tempfile
import unittest

import roadcross

BUILD = os.environ.get("ROADCROSS_BUILD", "")
CLI = os.environ["ROADCROSS"]
DATA = os.environ["ROADCROSS_TEST_DATA_DIR"]
MAPS = os.environ["ROADCROSS_MAPS_DIR"]
NEEDS_BUILD = unittest.skipUnless(
    BUILD, "needs roadcross-build to make a map (not in the runtime-only build)")

# Positions on the bundled Prague map (lat, lon): Resslova street and a quiet Apolinarska street
# by a zebra crossing (scripts/run-default.sh), Karlovo namesti, Vaclavske namesti, Ke Karlovu,
# the map's edges, and one between blocks away from any road centreline.
PRAGUE_POSITIONS = [
    (50.075769, 14.416015),
    (50.071507, 14.42651),
    (50.0755, 14.4186),
    (50.0800, 14.4260),
    (50.0720, 14.4215),
    (50.0790, 14.4100),
    (50.0700, 14.4300),
    (50.0810, 14.4350),
    (50.0745, 14.4195),
    (50.0765, 14.4205),
]

tmp = None
prague_db = ""
straight_db = ""


def setUpModule():
    global tmp, prague_db, straight_db
    tmp = tempfile.TemporaryDirectory()
    if not BUILD:
        return
    prague_db = os.path.join(tmp.name, "prague.gpkg")
    subprocess.run([BUILD, "--osm", os.path.join(MAPS, "prague", "prague_nove_mesto_roads_2017.osm"),
                    "--elevation", os.path.join(MAPS, "prague", "N50E014.hgt"),
                    "-o", prague_db, "-q"], check=True)
    straight_db = os.path.join(tmp.name, "straight.gpkg")
    subprocess.run([BUILD, "--osm", os.path.join(DATA, "install_straight_road.osm"),
                    "-o", straight_db, "-q"], check=True)


def tearDownModule():
    tmp.cleanup()


def utm33n_to_lat_lon(easting_m, northing_m):
    """WGS84 latitude, longitude (degrees) of a UTM 33N point, by GDAL (an independent tool)."""
    from osgeo import osr
    utm, wgs84 = osr.SpatialReference(), osr.SpatialReference()
    utm.ImportFromEPSG(32633)
    wgs84.ImportFromEPSG(4326)  # GDAL 3: EPSG axis order, latitude first
    lat, lon, _ = osr.CoordinateTransformation(utm, wgs84).TransformPoint(easting_m, northing_m)
    return lat, lon


def without_lat_lon(value, testcase=None):
    """The CLI's JSON without its *_lat_lon_deg fields, which the Python objects do not carry
    (they give UTM positions and the map's zone). With a testcase, each one with a *_utm_m
    partner is first checked against GDAL's projection of it (the answers here are in UTM 33N,
    printed to 7 decimals of a degree)."""
    if isinstance(value, list):
        return [without_lat_lon(v, testcase) for v in value]
    if not isinstance(value, dict):
        return value
    out = {}
    for key, v in value.items():
        if key.endswith("_lat_lon_deg"):
            partner = value.get(key[:-len("_lat_lon_deg")] + "_utm_m")
            if testcase is not None and partner is not None:
                lat, lon = utm33n_to_lat_lon(*partner)
                testcase.assertAlmostEqual(v[0], lat, delta=6e-8, msg=key)
                testcase.assertAlmostEqual(v[1], lon, delta=6e-8, msg=key)
            continue
        out[key] = without_lat_lon(v, testcase)
    return out


def cli_json(*args, stdin="", lat_lon_checked_by=None):
    """The CLI's --json answer without its *_lat_lon_deg fields (see without_lat_lon)."""
    out = subprocess.run([CLI, *[str(a) for a in args], "--json"], input=stdin,
                         capture_output=True, text=True, check=True)
    return without_lat_lon(json.loads(out.stdout), lat_lon_checked_by)


def cli_error(*args):
    """The CLI's error message (stderr without the 'roadcross: ' prefix); it must fail."""
    out = subprocess.run([CLI, *[str(a) for a in args]], capture_output=True, text=True)
    assert out.returncode != 0, out
    return out.stderr.strip().removeprefix("roadcross: ")


def lat_lon_args(lat, lon):
    return ["--lat", repr(lat), "--lon", repr(lon)]


def road_fields(road):
    return {"segment_id": road.segment_id, "osm_way_id": road.osm_way_id,
            "highway": road.highway, "name": road.name, "distance_m": road.distance_m,
            "query_utm_m": list(road.query), "closest_utm_m": list(road.closest)}


@NEEDS_BUILD
class AgreesWithCli(unittest.TestCase):
    """Every field equals the CLI's --json output on the same map and position."""

    @classmethod
    def setUpClass(cls):
        cls.map = roadcross.Map(prague_db)

    @classmethod
    def tearDownClass(cls):
        cls.map.close()

    def test_info(self):
        expected = cli_json("info", prague_db)
        info = self.map.info
        self.assertEqual(info.path, expected["path"])
        self.assertEqual(info.schema_version, expected["schema_version"])
        self.assertEqual(info.tool_version, expected["tool_version"])
        self.assertEqual(info.map_id, expected["map_id"])
        self.assertRegex(info.map_id, "^[0-9a-f]{64}$")
        self.assertEqual(info.osm_timestamp, expected["osm_timestamp"])
        self.assertEqual(info.utm_zone, expected["utm_zone"])
        self.assertEqual(info.utm_northern, expected["utm_northern"])
        self.assertEqual(info.epsg, expected["epsg"])
        self.assertEqual(info.segment_count, expected["segment_count"])
        self.assertEqual(list(info.extent_utm_m), expected["extent_utm_m"])
        self.assertEqual(info.metadata, expected["metadata"])
        self.assertEqual(info.epsg, 32633)  # Prague is in UTM zone 33N

    def test_nearest_and_heading(self):
        for lat, lon in PRAGUE_POSITIONS:
            with self.subTest(lat=lat, lon=lon):
                expected = cli_json("nearest", "--db", prague_db, *lat_lon_args(lat, lon),
                                    lat_lon_checked_by=self)
                self.assertEqual(road_fields(self.map.nearest(lat=lat, lon=lon)), expected)
                expected = cli_json("heading", "--db", prague_db, *lat_lon_args(lat, lon))
                h = self.map.road_heading(lat=lat, lon=lon)
                got = road_fields(h.road)
                got.update(road_heading_rad=h.road_heading_rad,
                           road_bearing_deg=h.road_bearing_deg,
                           crossing_heading_rad=h.crossing_heading_rad,
                           crossing_bearing_deg=h.crossing_bearing_deg,
                           convergence_rad=h.convergence_rad, on_centreline=h.on_centreline)
                self.assertEqual(got, expected)
                self.assertEqual(h.distance_m, expected["distance_m"])

    def assert_assessment(self, a, expected):
        got = {}
        for key in expected:
            if key == "closest_utm_m":
                got[key] = list(a.road.closest)
            else:
                got[key] = getattr(a, key)
        self.assertEqual(got, expected)

    def test_assess(self):
        suitable = 0
        for lat, lon in PRAGUE_POSITIONS:
            with self.subTest(lat=lat, lon=lon):
                expected = cli_json("assess", "--db", prague_db, *lat_lon_args(lat, lon),
                                    lat_lon_checked_by=self)
                a = self.map.assess(lat=lat, lon=lon)
                self.assert_assessment(a, expected)
                suitable += a.suitable
                # Per-call thresholds reach the runtime the same way as the CLI's options.
                expected = cli_json("assess", "--db", prague_db, *lat_lon_args(lat, lon),
                                    "--threshold", "5", "--valid-distance", "3")
                a = self.map.assess(lat=lat, lon=lon, threshold=5, valid_distance_m=3.0)
                self.assert_assessment(a, expected)
                self.assertEqual(a.threshold, 5.0)
                self.assertEqual(a.valid_distance_m, 3.0)
        # The sample positions include both answers (run-default.sh: Resslova no, Apolinarska yes).
        self.assertFalse(self.map.assess(lat=50.075769, lon=14.416015).suitable)
        self.assertTrue(self.map.assess(lat=50.071507, lon=14.42651).suitable)
        self.assertGreater(suitable, 0)
        self.assertLess(suitable, len(PRAGUE_POSITIONS))

    def test_assess_under_uncertainty(self):
        # sigma_m= and the batch's/CLI's --sigma reach the same runtime call: every field of the
        # region equals the CLI's, and a circular ENU covariance (rotation-invariant) is the
        # same region as sigma_m.
        for lat, lon in PRAGUE_POSITIONS:
            with self.subTest(lat=lat, lon=lon):
                expected = cli_json("assess", "--db", prague_db, *lat_lon_args(lat, lon),
                                    "--sigma", "3")
                a = self.map.assess(lat=lat, lon=lon, sigma_m=3.0)
                region = expected.pop("region")
                self.assert_assessment(a, expected)
                self.assertEqual({key: getattr(a.region, key) for key in region}, region)
                enu = self.map.assess(lat=lat, lon=lon, covariance_enu_m2=[[9.0, 0.0], [0.0, 9.0]])
                self.assertEqual(enu.region.segment_ids, a.region.segment_ids)
                self.assertAlmostEqual(enu.region.suitable_share, a.region.suitable_share)
                self.assertEqual(enu.suitable, a.suitable)
                heading = cli_json("heading", "--db", prague_db, *lat_lon_args(lat, lon),
                                   "--sigma", "3")
                self.assertEqual(self.map.road_heading(lat=lat, lon=lon, sigma_m=3.0)
                                 .heading_spread_rad, heading["heading_spread_rad"])
        self.assertIsNone(self.map.assess(lat=50.0755, lon=14.4186).region)

    def test_assess_by_utm_equals_by_wgs84(self):
        for lat, lon in PRAGUE_POSITIONS:
            with self.subTest(lat=lat, lon=lon):
                e, n = self.map.to_utm(lat=lat, lon=lon)
                expected = cli_json("assess", "--db", prague_db, "--utm", repr(e), repr(n))
                self.assert_assessment(self.map.assess(easting=e, northing=n), expected)

    def test_assess_segment_on_centreline(self):
        a = self.map.assess(lat=50.071507, lon=14.42651)
        s = self.map.assess_segment(a.segment_id)
        self.assertEqual(s.distance_m, 0.0)
        self.assertTrue(s.valid)
        self.assertEqual((s.score, s.context_score, s.reasons), (a.score, a.context_score, a.reasons))

    def test_better_place(self):
        for lat, lon in PRAGUE_POSITIONS:
            with self.subTest(lat=lat, lon=lon):
                expected = cli_json("better", "--db", prague_db, *lat_lon_args(lat, lon),
                                    "--radius", "150", "--max", "4", lat_lon_checked_by=self)
                places = self.map.better_place(lat=lat, lon=lon, search_radius_m=150,
                                               max_candidates=4)
                got = {"candidates": [
                    {"point_utm_m": list(c.point), "walking_distance_m": c.walking_distance_m,
                     "segment_id": c.segment_id, "suitable": c.suitable,
                     "score_plus_context": c.score, "designated_crossing": c.designated_crossing,
                     "crossing_heading_rad": c.crossing_heading_rad, "reasons": c.reasons}
                    for c in places], "reason": places.reason}
                self.assertEqual(got, expected)
                self.assertEqual(len(places), len(expected["candidates"]))
                self.assertLessEqual(len(places), 4)

    def test_monitor(self):
        lat, lon = PRAGUE_POSITIONS[1]
        plan = self.map.plan_crossing(lat=lat, lon=lon)
        # Poses: at the start, 0.8 m beside the line halfway, at the target.
        sx, sy = plan.start
        tx, ty = plan.target
        poses = [(sx, sy, plan.heading_rad),
                 ((sx + tx) / 2 - 0.8 * math.sin(plan.heading_rad),
                  (sy + ty) / 2 + 0.8 * math.cos(plan.heading_rad), plan.heading_rad),
                 (tx, ty, plan.heading_rad + 0.1)]
        states = []
        for x, y, yaw in poses:
            expected = cli_json("monitor", "--db", prague_db, *lat_lon_args(lat, lon),
                                "--at", repr(x), repr(y), "--yaw", repr(yaw))
            p = roadcross.monitor(plan, easting=x, northing=y, yaw_rad=yaw)
            got = {"state": p.state, "progress": p.progress,
                   "lateral_deviation_m": p.lateral_deviation_m,
                   "heading_error_rad": p.heading_error_rad,
                   "plan_start_utm_m": list(plan.start), "plan_target_utm_m": list(plan.target),
                   "plan_heading_rad": plan.heading_rad}
            self.assertEqual(got, expected)
            states.append(p.state)
        self.assertEqual(states, ["ON_TRACK", "DRIFTING", "DONE"])

    def gap_case(self, lat, lon, vehicles, policy):
        """The same vehicles through the CLI (stdin JSON, now = 0) and the module."""
        stdin = "\n".join(json.dumps(v) for v in vehicles)
        expected = cli_json("gap", "--db", prague_db, *lat_lon_args(lat, lon),
                            "--policy", policy, stdin=stdin)
        crossing = self.map.gap_crossing(lat=lat, lon=lon)
        tracked = [roadcross.Vehicle(east_m=v["east_m"], north_m=v["north_m"],
                                     vx_mps=v["vx_mps"], vy_mps=v["vy_mps"],
                                     time_s=-v.get("age_s", 0.0)) for v in vehicles]
        decide = roadcross.gap_decision if policy == "ours" else roadcross.hcm_gap_decision
        d = decide(crossing, tracked, now_s=0.0)
        got = {"decision": d.verdict, "reason": d.reason, "limiting_vehicle": d.limiting_vehicle,
               "limiting_line": d.limiting_vehicle + 1 if d.limiting_vehicle >= 0 else None,
               "margin_s": d.margin_s, "earliest_start_in_s": d.earliest_start_s,
               "stage": d.stage, "refuge_island": crossing.refuge_island,
               "crossing_time_s": d.crossing_time_s, "required_sight_m": d.required_sight_m,
               "visible_road_m": d.visible_road_m, "critical_gap_s": d.critical_gap_s, "vehicles_counted": d.vehicles_counted,
               "stale_tracks": d.stale_tracks, "beyond_sensor_range": d.beyond_sensor_range,
               "lanes": crossing.lanes, "road_width_m": crossing.road_width_m,
               "maxspeed_kmh": crossing.maxspeed_kmh,
               "crossing_heading_rad": crossing.heading_rad}
        self.assertEqual(got, expected)
        self.assertEqual(d.go, d.verdict == "GO")
        return d

    def test_gap_decision(self):
        # Apolinarska, where the DB's sight distance (248 m / 300 m) covers the 200 m sensor
        # range, so that the vehicles decide (10 m east, an SRTM bump cuts the view to 102 m:
        # INSUFFICIENT_SIGHT whatever the traffic).
        lat, lon = 50.071493, 14.426372
        heading = self.map.road_heading(lat=lat, lon=lon)
        along_e, along_n = math.cos(heading.road_heading_rad), math.sin(heading.road_heading_rad)
        # A car 30 m up the road coming at 12 m/s, one far away, one standing at the crossing,
        # and a stale track (robot ENU ~ grid here: the convergence is under 0.01 rad).
        near = {"east_m": 30 * along_e, "north_m": 30 * along_n,
                "vx_mps": -12 * along_e, "vy_mps": -12 * along_n}
        far = {"east_m": -150 * along_e, "north_m": -150 * along_n,
               "vx_mps": 10 * along_e, "vy_mps": 10 * along_n}
        stopped = {"east_m": 2 * math.cos(heading.crossing_heading_rad),
                   "north_m": 2 * math.sin(heading.crossing_heading_rad),
                   "vx_mps": 0.0, "vy_mps": 0.0}
        stale = dict(far, age_s=2.0)
        reasons = set()
        for policy in ("ours", "hcm"):
            for vehicles in ([], [far], [near], [near, far], [stopped], [stale]):
                with self.subTest(policy=policy, vehicles=vehicles):
                    reasons.add(self.gap_case(lat, lon, vehicles, policy).reason)
        self.assertTrue({"CLEAR", "VEHICLE_CONFLICT", "BLOCKED", "STALE_TRACK"} <= reasons, reasons)

    def test_errors_carry_the_runtimes_message(self):
        missing = os.path.join(tmp.name, "no-such-map.gpkg")
        with self.assertRaises(roadcross.MapNotFoundError) as caught:
            roadcross.Map(missing)
        self.assertEqual(str(caught.exception), cli_error("info", missing))
        with self.assertRaises(roadcross.InvalidArgumentError) as caught:
            self.map.assess(lat=float("nan"), lon=14.4)
        self.assertEqual(str(caught.exception),
                         cli_error("assess", "--db", prague_db, "--lat", "nan", "--lon", "14.4"))


@NEEDS_BUILD
class HandDerived(unittest.TestCase):
    """One straight east-west road along lat 50.0 from lon 14.399 to 14.401 (about 143 m)."""

    @classmethod
    def setUpClass(cls):
        cls.map = roadcross.Map(straight_db)

    @classmethod
    def tearDownClass(cls):
        cls.map.close()

    def test_500_m_from_the_road_is_not_valid(self):
        # 500 m north of the road's middle: one degree of latitude is 111 229 m at 50 degrees
        # (meridian arc), and the UTM zone 33 grid scale at lon 14.4 is 0.99966: about 499.8 m.
        lat = 50.0 + 500.0 / 111229.0
        a = self.map.assess(lat=lat, lon=14.4)
        self.assertAlmostEqual(a.distance_m, 499.8, delta=1.0)
        self.assertFalse(a.valid)
        self.assertFalse(a.suitable)
        self.assertIn("TOO_FAR_FROM_ROAD", a.reasons)
        self.assertEqual(a.reasons[0], "TOO_FAR_FROM_ROAD")  # first, as documented
        with self.assertRaises(roadcross.NoRoadError) as caught:
            self.map.nearest(lat=lat, lon=14.4, max_distance_m=100.0)
        self.assertIsInstance(caught.exception, LookupError)
        self.assertEqual(caught.exception.code, "not_found")

    def test_5_m_north_is_valid_and_faces_south(self):
        lat = 50.0 + 5.0 / 111229.0
        a = self.map.assess(lat=lat, lon=14.4)
        self.assertAlmostEqual(a.distance_m, 5.0, delta=0.05)
        self.assertTrue(a.valid)
        self.assertEqual((a.highway, a.name), ("residential", "Test Street"))
        h = self.map.road_heading(lat=lat, lon=14.4)
        # Perpendicular: the crossing heading is the road heading minus a quarter turn (the
        # robot is on the road's left, north side; the way is drawn eastwards).
        diff = math.remainder(h.crossing_heading_rad - h.road_heading_rad, 2 * math.pi)
        self.assertAlmostEqual(diff, -math.pi / 2, places=12)
        # East in true terms; the grid yaw differs by the convergence (under 0.01 rad here).
        self.assertAlmostEqual(h.road_heading_rad + h.convergence_rad, 0.0, delta=1e-3)
        self.assertAlmostEqual(h.crossing_heading_rad, -math.pi / 2, delta=0.01)
        self.assertAlmostEqual(h.crossing_bearing_deg,
                               (90.0 - math.degrees(h.crossing_heading_rad)) % 360.0, places=9)
        self.assertFalse(h.on_centreline)
        # From the south side the crossing heading points north.
        south = self.map.road_heading(lat=50.0 - 5.0 / 111229.0, lon=14.4)
        self.assertAlmostEqual(south.crossing_heading_rad, h.crossing_heading_rad + math.pi,
                               places=9)

    def test_positions_in_utm_and_wgs84_agree(self):
        e, n = self.map.to_utm(lat=50.0, lon=14.4)
        # Hand-checked: zone 33 (central meridian 15 E), 0.6 degrees west: about 457 000 m E.
        self.assertEqual(self.map.info.utm_zone, 33)
        self.assertAlmostEqual(e, 457000, delta=500)
        self.assertEqual(self.map.nearest(easting=e, northing=n).distance_m,
                         self.map.nearest(lat=50.0, lon=14.4).distance_m)

    def test_plan_and_monitor(self):
        lat = 50.0 + 5.0 / 111229.0
        plan = self.map.plan_crossing(lat=lat, lon=14.4)
        # No width in the map: 6 m default, target 3 m + 0.5 m beyond the centreline.
        self.assertEqual(plan.road_width_m, 6.0)
        length = math.dist(tuple(plan.start), tuple(plan.target))
        self.assertAlmostEqual(length, 5.0 + 3.5, delta=0.05)
        p = roadcross.monitor(plan, easting=plan.start.easting_m, northing=plan.start.northing_m,
                              yaw_rad=plan.heading_rad)
        self.assertEqual((p.state, p.progress), ("ON_TRACK", 0.0))

    def test_reprs_show_the_values(self):
        lat = 50.0 + 5.0 / 111229.0
        a = self.map.assess(lat=lat, lon=14.4)
        self.assertEqual(repr(a), f"Assessment(valid=True, suitable={a.suitable}, "
                         f"score={a.score!r}, context_score={a.context_score!r}, "
                         f"distance_m={a.distance_m!r}, reasons={a.reasons!r})")
        info = self.map.info
        self.assertEqual(repr(info), f"MapInfo(path={straight_db!r}, schema_version="
                         f"{info.schema_version}, utm_zone=33, segment_count={info.segment_count})")
        p = a.road.closest
        self.assertEqual(repr(p), f"PlanePoint(easting_m={p.easting_m!r}, northing_m={p.northing_m!r})")
        for value in (self.map.road_heading(lat=lat, lon=14.4), self.map.nearest(lat=lat, lon=14.4),
                      self.map.plan_crossing(lat=lat, lon=14.4),
                      self.map.gap_crossing(lat=lat, lon=14.4),
                      self.map.better_place(lat=lat, lon=14.4)):
            self.assertTrue(repr(value).startswith(type(value).__name__ + "("), repr(value))
        self.assertEqual(repr(self.map), f"roadcross.Map({straight_db!r})")

    def test_gap_without_vehicles(self):
        # No vehicle, residential road without tags: 2 lanes of 6 m at 50 km/h. Required sight
        # (docs/runtime.md) is under the 200 m sensor range, so GO; with 50 m of range, WAIT.
        crossing = self.map.gap_crossing(lat=50.0 + 5.0 / 111229.0, lon=14.4)
        self.assertEqual((crossing.lanes, crossing.road_width_m, crossing.maxspeed_kmh),
                         (2, 6.0, 50.0))
        d = roadcross.gap_decision(crossing, [], now_s=10.0)
        self.assertEqual((d.verdict, d.reason), ("GO", "CLEAR"))
        d = roadcross.gap_decision(crossing, [], now_s=10.0, sensor_range_m=50.0)
        self.assertEqual((d.verdict, d.reason), ("WAIT", "INSUFFICIENT_SIGHT"))
        self.assertIsNone(d.earliest_start_s)


@NEEDS_BUILD
class KerbsAndIslands(unittest.TestCase):
    """tests/data/kerbs.osm (its comment describes it): way 10 along lat 50.0 has a crossing with
    a refuge island at lon 14.4 whose highest kerb is 0.12 m, and a pavement on its right (south)
    side only."""

    @classmethod
    def setUpClass(cls):
        path = os.path.join(tmp.name, "kerbs.gpkg")
        subprocess.run([BUILD, "--osm", os.path.join(DATA, "kerbs.osm"), "-o", path, "-q"],
                       check=True)
        cls.map = roadcross.Map(path)

    @classmethod
    def tearDownClass(cls):
        cls.map.close()

    def test_kerb_capability_per_call(self):
        low = self.map.assess(lat=50.00003, lon=14.4, threshold=-1000, max_kerb_height_m=0.1)
        self.assertEqual((low.kerb, low.kerb_height_m, low.crossing_island), ("lowered", 0.12, True))
        self.assertIn("KERB_TOO_HIGH", low.reasons)
        self.assertFalse(low.suitable)
        high = self.map.assess(lat=50.00003, lon=14.4, threshold=-1000, max_kerb_height_m=0.2)
        self.assertTrue(high.suitable)
        self.assertEqual((high.robot_side, high.pavement_far_side), (1, True))
        with self.assertRaises(roadcross.InvalidArgumentError):
            self.map.assess(lat=50.00003, lon=14.4, max_kerb_height_m=-1.0)

    def test_far_side_without_pavement(self):
        south = self.map.assess(lat=49.99997, lon=14.4, threshold=-1000)
        self.assertEqual((south.robot_side, south.pavement_far_side), (-1, False))
        self.assertIn("NO_PAVEMENT_FAR_SIDE", south.reasons)
        places = self.map.better_place(lat=49.99997, lon=14.3993, threshold=-1000)
        self.assertEqual(len(places), 0)

    def test_two_stages(self):
        # The crossing of gap_island_test.cpp: 6 m, 2 lanes, the robot 1 m/s, 1 s start-up,
        # radius 0.5 m: stage 1 leaves lane 0 at 1 + 4.5 = 5.5 s, stage 2 (from the island)
        # lane 1 at 1 + 3.5 = 4.5 s.
        for stage, start_y, crossing_time_s in ((1, 0.0, 5.5), (2, 4.0, 4.5)):
            c = roadcross.GapCrossing(start=roadcross.PlanePoint(easting_m=0.0, northing_m=start_y),
                                      centre=roadcross.PlanePoint(easting_m=0.0, northing_m=4.0),
                                      heading_rad=math.pi / 2, refuge_island=True, stage=stage)
            d = roadcross.gap_decision(c, [], now_s=0.0, speed_mps=1.0, startup_s=1.0,
                                       radius_m=0.5)
            self.assertEqual(d.stage, stage)
            self.assertAlmostEqual(d.crossing_time_s, crossing_time_s)


@NEEDS_BUILD
class StoredVerdict(unittest.TestCase):
    """The segments' stored `suitable` column (for GIS users) is the runtime's verdict on the
    centreline under the map's defaults: assess_segment's, segment by segment."""

    def test_equals_assess_segment_on_prague(self):
        with contextlib.closing(sqlite3.connect(prague_db)) as db:
            rows = db.execute("SELECT fid, suitable FROM segments").fetchall()
        with roadcross.Map(prague_db) as m:
            differ = [fid for fid, stored in rows if bool(stored) != m.assess_segment(fid).suitable]
        self.assertEqual(differ, [])
        self.assertEqual(len(rows), 6049)
        suitable = sum(1 for _, stored in rows if stored)
        self.assertGreater(suitable, 0)
        self.assertLess(suitable, len(rows))

    def test_profile_kerb_rule(self):
        # kerbs.osm with every score reaching the threshold and sight not forbidding: a segment
        # is unsuitable exactly when its known kerb is higher than the profile's 0.1 m.
        path = os.path.join(tmp.name, "kerbs-profile.gpkg")
        subprocess.run([BUILD, "--osm", os.path.join(DATA, "kerbs.osm"), "-o", path, "-q",
                        "--suitability.threshold", "-1000", "--sight.limited_visibility_unsuitable",
                        "0", "--suitability.max_kerb_height_m", "0.1"], check=True)
        with contextlib.closing(sqlite3.connect(path)) as db:
            wrong = db.execute("SELECT COUNT(*) FROM segments WHERE suitable != "
                               "(kerb_height_m IS NULL OR kerb_height_m <= 0.1)").fetchone()[0]
            high = db.execute("SELECT COUNT(*) FROM segments WHERE kerb_height_m > 0.1"
                              ).fetchone()[0]
        self.assertEqual(wrong, 0)
        self.assertGreater(high, 0)


class WithoutMap(unittest.TestCase):
    """Errors and the pure computations: also in the runtime-only build."""

    def test_missing_file(self):
        path = os.path.join(tmp.name, "missing.gpkg")
        with self.assertRaises(FileNotFoundError) as caught:
            roadcross.Map(path)
        self.assertIsInstance(caught.exception, roadcross.Error)
        self.assertIsInstance(caught.exception, roadcross.MapNotFoundError)
        self.assertEqual(caught.exception.code, "file_not_found")
        self.assertIn(path, str(caught.exception))

    def test_not_a_roadcross_map(self):
        plain = os.path.join(tmp.name, "plain.sqlite")
        with sqlite3.connect(plain) as db:
            db.execute("CREATE TABLE t (x)")
        text = os.path.join(tmp.name, "notes.txt")
        with open(text, "w") as f:
            f.write("not a database at all, " * 100)
        for path in (plain, text):
            with self.subTest(path=path):
                with self.assertRaises(ValueError) as caught:
                    roadcross.Map(path)
                self.assertIsInstance(caught.exception, roadcross.NotARoadcrossMapError)
                self.assertEqual(caught.exception.code, "not_a_database")
                self.assertIn(path, str(caught.exception))
                self.assertEqual(str(caught.exception), cli_error("info", path))

    def test_path_like(self):
        import pathlib
        with self.assertRaises(roadcross.MapNotFoundError):
            roadcross.Map(pathlib.Path(tmp.name) / "missing.gpkg")

    def test_monitor_by_hand(self):
        # From (0, 0) north to (0, 10): heading pi/2.
        plan = roadcross.CrossingPlan(start=roadcross.PlanePoint(easting_m=0.0, northing_m=0.0),
                                      target=roadcross.PlanePoint(easting_m=0.0, northing_m=10.0),
                                      heading_rad=math.pi / 2, road_width_m=6.0)
        p = roadcross.monitor(plan, easting=-0.8, northing=5.0, yaw_rad=math.pi / 2)
        self.assertAlmostEqual(p.progress, 0.5, places=12)
        self.assertAlmostEqual(p.lateral_deviation_m, 0.8, places=12)  # west = left of north
        self.assertEqual(p.state, "DRIFTING")
        p = roadcross.monitor(plan, easting=-0.8, northing=5.0, yaw_rad=math.pi / 2, drift_m=1.0)
        self.assertEqual(p.state, "ON_TRACK")
        self.assertEqual(roadcross.monitor(plan, easting=2.0, northing=5.0,
                                           yaw_rad=math.pi / 2).state, "LEAVING_CORRIDOR")
        with self.assertRaises(roadcross.InvalidArgumentError) as caught:
            roadcross.monitor(plan, easting=float("nan"), northing=5.0, yaw_rad=0.0)
        self.assertIsInstance(caught.exception, ValueError)
        self.assertTrue(str(caught.exception))

    def test_gap_by_hand(self):
        # A 2-lane, 6 m road running east; the robot waits 3.5 m south of the centreline and
        # crosses north at 1.2 m/s after 1 s: it clears the far lane (6.5 m + 0.4 m) at
        # 1 + 6.9 / 1.2 = 6.75 s.
        crossing = roadcross.GapCrossing(start=roadcross.PlanePoint(easting_m=0.0, northing_m=-3.5),
                                         centre=roadcross.PlanePoint(easting_m=0.0, northing_m=0.0),
                                         heading_rad=math.pi / 2, road_width_m=6.0, lanes=2,
                                         maxspeed_kmh=50.0)
        d = roadcross.gap_decision(crossing, [], now_s=0.0)
        self.assertEqual((d.verdict, d.reason, d.limiting_vehicle), ("GO", "CLEAR", -1))
        self.assertAlmostEqual(d.crossing_time_s, 1.0 + 6.9 / 1.2, places=9)
        # A car standing on the crossing line blocks it.
        car = roadcross.Vehicle(easting=0.0, northing=1.5, vx_mps=0.0, vy_mps=0.0)
        d = roadcross.gap_decision(crossing, [car], now_s=0.0)
        self.assertEqual((d.verdict, d.reason, d.limiting_vehicle), ("WAIT", "BLOCKED", 0))
        # The DB's sight: 100 m visible one way < the 16.667 m/s * (6.75 s + 1.2 s) + 0.9 m =
        # 133.4 m an unseen car needs -> WAIT, though the sensor reaches 200 m.
        hidden = roadcross.GapCrossing(start=crossing.start, centre=crossing.centre,
                                       heading_rad=math.pi / 2, road_width_m=6.0, lanes=2,
                                       maxspeed_kmh=50.0, sight_forward_m=300.0,
                                       sight_backward_m=100.0)
        d = roadcross.gap_decision(hidden, [], now_s=0.0)
        self.assertEqual((d.verdict, d.reason), ("WAIT", "INSUFFICIENT_SIGHT"))
        self.assertEqual(d.visible_road_m, 100.0)
        self.assertAlmostEqual(d.required_sight_m, 50 / 3.6 * 1.2 * (6.75 + 1.2) + 0.9, places=9)
        # A track observed after now: the clocks disagree.
        late = roadcross.Vehicle(easting=-50.0, northing=1.5, vx_mps=10.0, vy_mps=0.0, time_s=1.0)
        with self.assertRaises(roadcross.InvalidArgumentError):
            roadcross.gap_decision(crossing, [late], now_s=0.0)

    def test_keyword_only_positions(self):
        with self.assertRaises(TypeError):
            roadcross.Vehicle(vx_mps=1.0, vy_mps=0.0)  # no position
        with self.assertRaises(TypeError):
            roadcross.Vehicle(easting=1.0, east_m=1.0, northing=0.0, vx_mps=1.0, vy_mps=0.0)

    def test_describe_reason(self):
        self.assertTrue(roadcross.describe_reason("SHARP_BEND"))
        self.assertEqual(roadcross.__version__.count("."), 2)


@NEEDS_BUILD
class PositionArguments(unittest.TestCase):

    def test_argument_errors(self):
        with roadcross.Map(straight_db) as m:
            info = m.info
            road = m.assess(lat=50.0, lon=14.4).road
            with self.assertRaises(TypeError):
                m.assess()  # no position
            with self.assertRaises(TypeError):
                m.assess(lat=50.0)  # lat without lon
            with self.assertRaises(TypeError):
                m.assess(lat=50.0, lon=14.4, easting=457000.0, northing=5539000.0)
            with self.assertRaises(TypeError):
                m.assess(50.0, 14.4)  # positional: keyword-only
            with self.assertRaises(roadcross.InvalidArgumentError) as caught:
                m.assess(lat=91.0, lon=14.4)
            self.assertEqual(caught.exception.code, "invalid_argument")
            with self.assertRaises(roadcross.InvalidArgumentError):
                m.nearest(lat=50.0, lon=14.4, max_distance_m=-1.0)
            # Position uncertainty: zero, negative and non-finite sigma, a covariance that is
            # not 2x2, symmetric and positive definite, a probability outside (0, 1), or both
            # forms at once.
            for sigma in (0.0, -1.0, math.nan, math.inf):
                with self.assertRaises(roadcross.InvalidArgumentError):
                    m.assess(lat=50.0, lon=14.4, sigma_m=sigma)
            with self.assertRaises(roadcross.InvalidArgumentError):
                m.assess(lat=50.0, lon=14.4, covariance_enu_m2=[[1.0, 1.0], [1.0, 1.0]])
            with self.assertRaises(ValueError):
                m.assess(lat=50.0, lon=14.4, covariance_enu_m2=[[1.0, 0.5], [0.0, 1.0]])
            with self.assertRaises(ValueError):
                m.assess(lat=50.0, lon=14.4, covariance_enu_m2=[[1.0, 0.0, 0.0]])
            with self.assertRaises(roadcross.InvalidArgumentError):
                m.assess(lat=50.0, lon=14.4, sigma_m=1.0, region_probability=1.0)
            with self.assertRaises(TypeError):
                m.assess(lat=50.0, lon=14.4, sigma_m=1.0, covariance_enu_m2=[[1.0, 0.0], [0.0, 1.0]])
            # 5 m north of the straight road's middle, sigma 1 m: the whole region is on the one
            # road, all suitable or all not, so the share is exactly 1 or 0.
            exact = m.assess(lat=50.0 + 5.0 / 111229.0, lon=14.4)
            uncertain = m.assess(lat=50.0 + 5.0 / 111229.0, lon=14.4, sigma_m=1.0)
            self.assertEqual(uncertain.suitable, exact.suitable)
            self.assertEqual(uncertain.region.suitable_share, 1.0 if exact.suitable else 0.0)
            self.assertTrue(uncertain.region.same_road)
            self.assertAlmostEqual(uncertain.region.semi_major_m, 2.44775, places=4)
        # The with block closed the map; values read before stay valid (they are copies).
        self.assertTrue(m.closed)
        self.assertEqual(info.utm_zone, 33)
        self.assertEqual(info.path, straight_db)
        self.assertEqual(road.highway, "residential")
        with self.assertRaises(ValueError):
            m.assess(lat=50.0, lon=14.4)


@NEEDS_BUILD
class MapSetOverTwoMaps(unittest.TestCase):
    """roadcross.MapSet over the Prague map and the straight road (lat 50.0, lon 14.399..14.401,
    8 km south of Prague's map): each position is answered by the map that covers it, exactly
    as that Map alone answers, and the answer names the map (as the CLI's --db twice does)."""

    @classmethod
    def setUpClass(cls):
        cls.set = roadcross.MapSet([prague_db, straight_db])
        cls.prague = roadcross.Map(prague_db)

    @classmethod
    def tearDownClass(cls):
        cls.set.close()
        cls.prague.close()

    def test_each_position_from_its_map(self):
        self.assertEqual(len(self.set), 2)
        self.assertEqual([info.path for info in self.set.maps], [prague_db, straight_db])
        for lat, lon in PRAGUE_POSITIONS[:4]:
            with self.subTest(lat=lat, lon=lon):
                answer, source = self.set.assess(lat=lat, lon=lon)
                alone = self.prague.assess(lat=lat, lon=lon)
                self.assertEqual((source.index, source.path, source.map_id),
                                 (0, prague_db, self.prague.info.map_id))
                self.assertEqual(answer.segment_id, alone.segment_id)
                self.assertEqual(answer.distance_m, alone.distance_m)
                self.assertEqual(answer.reasons, alone.reasons)
                cli = cli_json("assess", "--db", prague_db, "--db", straight_db,
                               *lat_lon_args(lat, lon))
                self.assertEqual(cli["map"], {"path": prague_db, "map_id": source.map_id})
                self.assertEqual(cli["segment_id"], answer.segment_id)
        road, source = self.set.nearest(lat=50.0 + 5.0 / 111229.0, lon=14.4)
        self.assertEqual((source.index, source.path), (1, straight_db))
        self.assertAlmostEqual(road.distance_m, 5.0, delta=0.01)

    def test_utm_positions_need_their_zone(self):
        e, n = self.prague.to_utm(lat=50.0755, lon=14.4186)
        with self.assertRaises(roadcross.InvalidArgumentError) as raised:
            self.set.nearest(easting=e, northing=n)
        self.assertIn("zone", str(raised.exception))
        road, source = self.set.nearest(easting=e, northing=n, utm_zone="33N")
        self.assertEqual(source.index, 0)
        self.assertEqual(road.segment_id, self.prague.nearest(easting=e, northing=n).segment_id)
        with self.assertRaises(ValueError):
            self.set.nearest(easting=e, northing=n, utm_zone="99X")

    def test_coverage_in_map_info(self):
        info = self.set.maps[1]
        self.assertTrue(info.coverage_stored)
        min_lat, min_lon, max_lat, max_lon = info.extent_wgs84_deg
        # The road's ends, lat 50.0 at lon 14.399 and 14.401, within the box's 1e-5 deg margin.
        self.assertAlmostEqual(min_lon, 14.399, delta=2e-5)
        self.assertAlmostEqual(max_lon, 14.401, delta=2e-5)
        self.assertLess(min_lat, 50.0)
        self.assertGreater(max_lat, 50.0)

    def test_a_directory_with_a_file_that_is_not_a_map(self):
        with tempfile.TemporaryDirectory() as fleet:
            shutil.copy(straight_db, os.path.join(fleet, "straight.gpkg"))
            with open(os.path.join(fleet, "notes.txt"), "w") as f:
                f.write("not a map\n")
            with self.assertRaises(roadcross.NotARoadcrossMapError) as raised:
                roadcross.MapSet([fleet])
            self.assertIn(os.path.join(fleet, "notes.txt"), str(raised.exception))
            os.remove(os.path.join(fleet, "notes.txt"))
            with roadcross.MapSet([fleet]) as fleet_set:
                self.assertEqual(len(fleet_set), 1)
            self.assertTrue(fleet_set.closed)


@NEEDS_BUILD
class DocExamples(unittest.TestCase):
    """Each Python example in docs/embedding.md prints exactly the output shown after it."""

    def test_examples(self):
        source = os.path.join(os.path.dirname(__file__), "..", "..")
        with open(os.path.join(source, "docs", "embedding.md")) as f:
            blocks = re.findall(r"```(\w*)\n(.*?)```", f.read(), re.S)
        # The examples run from the repository root with out/prague.gpkg (run-default.sh).
        root = os.path.join(tmp.name, "doc-root")
        os.makedirs(os.path.join(root, "out"), exist_ok=True)
        if not os.path.exists(os.path.join(root, "out", "prague.gpkg")):
            os.symlink(prague_db, os.path.join(root, "out", "prague.gpkg"))
            shutil.copy(os.path.join(source, "README.md"), root)
        examples = [(body, blocks[i + 1][1]) for i, (lang, body) in enumerate(blocks)
                    if lang == "python"]
        self.assertGreaterEqual(len(examples), 4)
        for body, expected in examples:
            with self.subTest(example=body.splitlines()[0]):
                out = subprocess.run([sys.executable, "-c", body], cwd=root, capture_output=True,
                                     text=True)
                self.assertEqual(out.stderr, "")
                self.assertEqual(out.stdout, expected)


class Installed(unittest.TestCase):
    """cmake --install puts the module and its stub under the prefix, importable with
    PYTHONPATH."""

    def test_install_and_import(self):
        with tempfile.TemporaryDirectory() as prefix:
            subprocess.run([os.environ["CMAKE_COMMAND"], "--install",
                            os.environ["ROADCROSS_BINARY_DIR"], "--prefix", prefix,
                            "--component", "python"], check=True, capture_output=True)
            found = sorted(os.path.join(root, f) for root, _, files in os.walk(prefix)
                           for f in files)
            # The package's copyright file (share/doc/python3-roadcross/copyright), then the
            # module and its type stub (python/roadcross.pyi), side by side.
            copyright_files = [f for f in found if f.endswith("/copyright")]
            self.assertEqual([os.path.relpath(f, prefix) for f in copyright_files],
                             ["share/doc/python3-roadcross/copyright"], found)
            found = [f for f in found if f not in copyright_files]
            self.assertEqual(len(found), 2, found)
            site = os.path.dirname(found[0])
            self.assertEqual([os.path.dirname(f) for f in found], [site, site])
            self.assertRegex(os.path.basename(found[0]), r"^roadcross\..+\.so$")
            self.assertEqual(os.path.basename(found[1]), "roadcross.pyi")
            source = os.path.join(os.path.dirname(__file__), "..", "..", "python")
            with open(found[1]) as installed, open(os.path.join(source, "roadcross.pyi")) as f:
                self.assertEqual(installed.read(), f.read())
            self.assertRegex(site, r"/lib/python3\.\d+/(dist|site)-packages$")
            probe = ("import roadcross, sys; print(roadcross.__file__); "
                     "m = roadcross.Map(sys.argv[1]); a = m.assess(lat=50.0001, lon=14.4); "
                     "print(a.valid, repr(a.distance_m))") if straight_db else (
                     "import roadcross; print(roadcross.__file__)")
            env = dict(os.environ, PYTHONPATH=site)
            out = subprocess.run([sys.executable, "-c", probe, straight_db], env=env,
                                 capture_output=True, text=True, check=True).stdout.split("\n")
            self.assertTrue(out[0].startswith(site), out)
            if straight_db:
                with roadcross.Map(straight_db) as m:
                    a = m.assess(lat=50.0001, lon=14.4)
                self.assertEqual(out[1], f"{a.valid} {a.distance_m!r}")


if __name__ == "__main__":
    unittest.main()
