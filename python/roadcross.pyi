# Type stub of the roadcross extension module (python/roadcross_module.cpp), for IDEs and type
# checkers: pyright/Pylance and jedi read a .pyi beside the module; mypy reads it with
# MYPYPATH=<its directory>. Written by hand from the binding; tests/python/test_stub.py (ctest
# python.stub) checks it against the imported module: names, parameter names and kinds,
# defaults, types as pybind11 reports them, exception bases and docstrings. Change both together.
"""roadcross: where and how a pavement robot may cross a road.

m = roadcross.Map('map.gpkg'); a = m.assess(lat=50.0757, lon=14.4160)
Yaws are ENU (REP-103) radians in the map's UTM grid frame; distances in metres. Errors are
roadcross.Error subclasses carrying the runtime's message. See docs/embedding.md.
"""

import os
from typing import Iterator, Literal, Optional, Sequence, Union

__version__: str

# --- Errors: one class per runtime StatusCode, each also the built-in a caller would catch ---

class Error(Exception):
    """Base class of every error the roadcross runtime reports. `code` is the runtime's
    StatusCode name (e.g. 'file_not_found'); str(error) is the runtime's message."""

    code: str

class MapNotFoundError(Error, FileNotFoundError):
    """The map file does not exist or cannot be read (also a FileNotFoundError)."""

class NotARoadcrossMapError(Error, ValueError):
    """The file is not SQLite, not a GeoPackage, or not written by roadcross-build (also a
    ValueError)."""

class WrongVersionError(Error, ValueError):
    """A roadcross map of a schema version this runtime cannot read; the message says whether to
    update the runtime or rebuild the map (also a ValueError)."""

class CorruptMapError(Error, ValueError):
    """A roadcross map whose content breaks the contract (also a ValueError)."""

class CorruptSegmentError(CorruptMapError):
    """One segment of the map cannot be right (a non-finite or out-of-range value, an unknown
    reason code, an index box that does not hold it, flags contradicting its reasons): no verdict
    is given there. The message names the segment (also a CorruptMapError)."""

class InvalidArgumentError(Error, ValueError):
    """NaN or infinite input, latitude/longitude out of range, a position outside the map's UTM
    zone, or an option out of its range (also a ValueError)."""

class NoRoadError(Error, LookupError):
    """No road in the map near enough to answer (within max_distance_m), or no such segment
    (also a LookupError)."""

class InternalError(Error, RuntimeError):
    """An unexpected SQLite error (also a RuntimeError)."""

# --- Values ---

class PlanePoint:
    """A point in the map's UTM zone, metres. Unpacks as (easting_m, northing_m)."""

    def __init__(self, *, easting_m: float, northing_m: float) -> None: ...
    @property
    def easting_m(self) -> float:
        """UTM easting, metres"""
    @property
    def northing_m(self) -> float:
        """UTM northing, metres"""
    def __iter__(self) -> Iterator[float]: ...
    def __repr__(self) -> str: ...

class MapInfo:
    """What Map.info says about the open map."""

    @property
    def path(self) -> str:
        """the file as opened"""
    @property
    def schema_version(self) -> int:
        """the map file's schema version (an integer)"""
    @property
    def tool_version(self) -> str:
        """roadcross-build version that wrote it"""
    @property
    def map_id(self) -> Optional[str]:
        """the map's identity: SHA-256 of its content (64 hex digits), None for a map built before map ids"""
    @property
    def osm_timestamp(self) -> Optional[str]:
        """newest OSM object's timestamp, ISO 8601 UTC; None when the input had none"""
    @property
    def utm_zone(self) -> int:
        """UTM zone number, 1..60"""
    @property
    def utm_northern(self) -> bool:
        """True for the northern hemisphere"""
    @property
    def epsg(self) -> int:
        """EPSG code of the map's CRS (326zz or 327zz)"""
    @property
    def segment_count(self) -> int:
        """number of road segments in the map"""
    @property
    def extent_utm_m(self) -> tuple[float, float, float, float]:
        """(min_easting, min_northing, max_easting, max_northing) of all segments, UTM metres"""
    @property
    def extent_wgs84_deg(self) -> tuple[float, float, float, float]:
        """(min_lat, min_lon, max_lat, max_lon) of the segments' UTM extent, WGS84 degrees: the
        box a MapSet picks the map by"""
    @property
    def coverage_stored(self) -> bool:
        """True when the map stores its coverage; False for maps written before it (computed
        on open)"""
    @property
    def metadata(self) -> dict[str, str]:
        """every row of the map's metadata table (schema version, build parameters, inputs)"""
    def __repr__(self) -> str: ...

class NearestRoad:
    """The road centreline nearest to a position."""

    @property
    def segment_id(self) -> int:
        """id of the road segment (Map.assess_segment takes it)"""
    @property
    def osm_way_id(self) -> int:
        """id of the OSM way the segment comes from"""
    @property
    def highway(self) -> str:
        """OSM highway=* value"""
    @property
    def name(self) -> str:
        """the way's name; '' when it has none"""
    @property
    def query(self) -> PlanePoint:
        """the query position in the map's UTM zone"""
    @property
    def closest(self) -> PlanePoint:
        """nearest point on the centreline, UTM"""
    @property
    def distance_m(self) -> float:
        """distance from the query to the centreline, metres"""
    @property
    def segment_length_m(self) -> float:
        """metres"""
    def __repr__(self) -> str: ...

class RoadHeading:
    """The road's direction at the nearest point and the heading that crosses it. Yaws are ENU
    (REP-103: 0 = east, counter-clockwise), radians in (-pi, pi], UTM grid frame."""

    @property
    def road(self) -> NearestRoad:
        """the NearestRoad"""
    @property
    def road_heading_rad(self) -> float:
        """road direction (the OSM way's drawing direction), ENU grid yaw, radians"""
    @property
    def crossing_heading_rad(self) -> float:
        """perpendicular to the road, from the query's side across it, ENU grid yaw, radians"""
    @property
    def road_bearing_deg(self) -> float:
        """compass bearing of the road, degrees [0, 360), grid north"""
    @property
    def crossing_bearing_deg(self) -> float:
        """compass bearing across the road, degrees [0, 360), grid north"""
    @property
    def convergence_rad(self) -> float:
        """true_yaw = grid_yaw + convergence_rad, radians"""
    @property
    def on_centreline(self) -> bool:
        """the query is on the centreline: the side is unknown and the right-hand normal of the
        way direction is returned"""
    @property
    def distance_m(self) -> float:
        """distance to the centreline, metres"""
    def __repr__(self) -> str: ...

class Assessment:
    """Is this a place to cross, and why not. Cost terms are None where the map has none (e.g.
    no elevation data was given to roadcross-build)."""

    @property
    def road(self) -> NearestRoad:
        """the NearestRoad"""
    @property
    def valid(self) -> bool:
        """within valid_distance_m of a centreline"""
    @property
    def suitable(self) -> bool:
        """valid, score + context_score >= threshold, and not forbidden"""
    @property
    def valid_distance_m(self) -> float:
        """metres, as applied"""
    @property
    def threshold(self) -> float:
        """score threshold, as applied"""
    @property
    def score(self) -> Optional[int]:
        """the segment's crossing score, or None"""
    @property
    def context_score(self) -> Optional[int]:
        """bonus/penalty from the surroundings (designated crossings, ...), or None"""
    @property
    def rank(self) -> Optional[int]:
        """crossing rank, 0..14 (higher is worse), or None"""
    @property
    def class_cost(self) -> Optional[int]:
        """road class cost, 0..5 (primary 5 .. unclassified 1), or None"""
    @property
    def curvature_level(self) -> Optional[int]:
        """0..5 (5 = at a junction), or None"""
    @property
    def curvature_cost(self) -> Optional[int]:
        """0..14, windowed over +-100 m of road, or None"""
    @property
    def elevation_cost(self) -> Optional[int]:
        """0..9, or None"""
    @property
    def junction_distance_m(self) -> Optional[float]:
        """distance along the road to the nearest junction, metres, or None"""
    @property
    def radius_m(self) -> Optional[float]:
        """bend radius, metres, or None"""
    @property
    def crossing_distance_m(self) -> Optional[float]:
        """distance to the nearest designated crossing, metres, or None"""
    @property
    def maxspeed_kmh(self) -> Optional[float]:
        """km/h, or None"""
    @property
    def width_m(self) -> Optional[float]:
        """carriageway width, metres, or None"""
    @property
    def lanes(self) -> Optional[int]:
        """number of lanes, or None"""
    @property
    def landform(self) -> Optional[str]:
        """terrain class name, or None"""
    @property
    def sight_forward_m(self) -> Optional[float]:
        """sight distance along the way's direction, metres, or None"""
    @property
    def sight_backward_m(self) -> Optional[float]:
        """metres, or None"""
    @property
    def sight_min_m(self) -> Optional[float]:
        """metres, or None"""
    @property
    def required_sight_m(self) -> Optional[float]:
        """sight distance a crossing needs here, metres, or None"""
    @property
    def tunnel(self) -> bool:
        """True in a tunnel, building passage or covered=yes"""
    @property
    def kerb(self) -> Optional[str]:
        """kerb=* value of the highest kerb at a crossing within 5 m, or None"""
    @property
    def kerb_height_m(self) -> Optional[float]:
        """its height (kerb:height, else the value's usual height), metres, or None"""
    @property
    def max_kerb_height_m(self) -> float:
        """the robot's highest climbable kerb the judgement used, metres"""
    @property
    def crossing_island(self) -> Optional[bool]:
        """True: a refuge island (two-stage crossing), False: none, None: unknown"""
    @property
    def sidewalk_left(self) -> Optional[bool]:
        """pavement left of the OSM way's direction: True, False or None (unknown)"""
    @property
    def sidewalk_right(self) -> Optional[bool]:
        """the same on the right"""
    @property
    def robot_side(self) -> int:
        """+1 left of the way's direction, -1 right, 0 unknown (on the centreline)"""
    @property
    def pavement_far_side(self) -> Optional[bool]:
        """pavement on the far side: True, False (NO_PAVEMENT_FAR_SIDE) or None"""
    @property
    def override_note(self) -> str:
        """the operator's note when an override applies, else ''"""
    @property
    def reasons(self) -> list[str]:
        """reason codes (NEAR_JUNCTION, SHARP_BEND, BUSY_ROAD, TOO_FAR_FROM_ROAD, LOW_SCORE, ...);
        roadcross.describe_reason(code) gives a sentence"""
    @property
    def distance_m(self) -> float:
        """distance to the road centreline, metres"""
    @property
    def segment_id(self) -> int:
        """road.segment_id"""
    @property
    def osm_way_id(self) -> int:
        """road.osm_way_id"""
    @property
    def highway(self) -> str:
        """road.highway: OSM highway=* value"""
    @property
    def name(self) -> str:
        """road.name: '' when the way has none"""
    def __repr__(self) -> str: ...

class Candidate:
    """A place to cross instead, reached by walking along the road on the robot's side."""

    @property
    def point(self) -> PlanePoint:
        """where to stand, UTM"""
    @property
    def walking_distance_m(self) -> float:
        """metres"""
    @property
    def segment_id(self) -> int:
        """id of the road segment at that place"""
    @property
    def suitable(self) -> bool:
        """suitable by the same rules as Assessment.suitable"""
    @property
    def score(self) -> int:
        """score + context_score"""
    @property
    def designated_crossing(self) -> bool:
        """a designated crossing within 5 m"""
    @property
    def crossing_heading_rad(self) -> float:
        """ENU grid yaw across the road from that side, radians"""
    @property
    def reasons(self) -> list[str]:
        """reason codes at that place, as in Assessment.reasons"""
    def __repr__(self) -> str: ...

class BetterPlaces:
    """Candidates, best first (suitable, then designated crossings, then score, then walking
    distance). Iterable; len() is the number of candidates."""

    @property
    def candidates(self) -> list[Candidate]:
        """list of Candidate"""
    @property
    def reason(self) -> str:
        """why the list is empty, else ''"""
    def __len__(self) -> int: ...
    def __iter__(self) -> Iterator[Candidate]: ...
    def __getitem__(self, index: int, /) -> Candidate: ...
    def __repr__(self) -> str: ...

class CrossingPlan:
    """A crossing: from start straight across to target (UTM metres)."""

    def __init__(
        self,
        *,
        start: PlanePoint,
        target: PlanePoint,
        heading_rad: float,
        road_width_m: float = 0.0,
    ) -> None: ...
    @property
    def start(self) -> PlanePoint:
        """where the crossing starts, UTM metres"""
    @property
    def target(self) -> PlanePoint:
        """where it ends beyond the far kerb, UTM metres"""
    @property
    def heading_rad(self) -> float:
        """ENU grid yaw from start to target, radians"""
    @property
    def road_width_m(self) -> float:
        """metres"""
    def __repr__(self) -> str: ...

class CrossingProgress:
    """Where the robot is on its plan."""

    @property
    def progress(self) -> float:
        """0 at start .. 1 at target"""
    @property
    def lateral_deviation_m(self) -> float:
        """signed, metres: > 0 left of the line start -> target"""
    @property
    def heading_error_rad(self) -> float:
        """pose yaw minus plan heading, radians (-pi, pi]"""
    @property
    def state(self) -> Literal['ON_TRACK', 'DRIFTING', 'LEAVING_CORRIDOR', 'DONE']:
        """'ON_TRACK', 'DRIFTING', 'LEAVING_CORRIDOR' or 'DONE'"""
    def __repr__(self) -> str: ...

class GapCrossing:
    """The crossing as the gap decision sees it (UTM metres)."""

    def __init__(
        self,
        *,
        start: PlanePoint,
        centre: PlanePoint,
        heading_rad: float,
        road_width_m: float = 6.0,
        lanes: int = 2,
        maxspeed_kmh: float = 50.0,
        convergence_rad: float = 0.0,
        junction_distance_m: Optional[float] = None,
        sight_forward_m: Optional[float] = None,
        sight_backward_m: Optional[float] = None,
        refuge_island: bool = False,
        stage: int = 1,
    ) -> None: ...
    @property
    def start(self) -> PlanePoint:
        """where the robot waits"""
    @property
    def centre(self) -> PlanePoint:
        """the centreline on the crossing line"""
    @property
    def heading_rad(self) -> float:
        """ENU grid yaw across, radians"""
    @property
    def road_width_m(self) -> float:
        """carriageway width, metres"""
    @property
    def lanes(self) -> int:
        """>= 1"""
    @property
    def maxspeed_kmh(self) -> float:
        """km/h"""
    @property
    def convergence_rad(self) -> float:
        """radians"""
    @property
    def junction_distance_m(self) -> Optional[float]:
        """metres along the road to the nearest junction, or None"""
    @property
    def sight_forward_m(self) -> Optional[float]:
        """road visible in the OSM way's direction (the DB's sight), metres, or None"""
    @property
    def sight_backward_m(self) -> Optional[float]:
        """road visible against the way's direction, metres, or None"""
    @property
    def refuge_island(self) -> bool:
        """True: two stages, each over half the lanes, with a wait on the island"""
    @property
    def stage(self) -> int:
        """with an island: 1 = kerb to island (near lanes), 2 = island to far kerb"""
    def __repr__(self) -> str: ...

class Vehicle:
    """One tracked vehicle. Position and velocity in the map's UTM grid (easting=, northing=) or
    in the robot's ENU frame (east_m=, north_m=: true east/north offsets from the crossing
    start)."""

    def __init__(
        self,
        *,
        easting: Optional[float] = None,
        northing: Optional[float] = None,
        east_m: Optional[float] = None,
        north_m: Optional[float] = None,
        vx_mps: float,
        vy_mps: float,
        length_m: float = 4.5,
        speed_uncertainty_mps: Optional[float] = None,
        time_s: float = 0.0,
    ) -> None:
        """vx_mps, vy_mps: velocity, m/s (same frame as the position); length_m: > 0, metres;
        speed_uncertainty_mps: +- m/s (None: GapOptions' fraction of the speed); time_s: when it
        was observed, seconds on the clock of gap_decision's now_s"""
    @property
    def frame(self) -> Literal['utm', 'robot_enu']:
        """'utm' or 'robot_enu'"""
    @property
    def x_m(self) -> float:
        """easting (utm) or east offset (robot_enu), m"""
    @property
    def y_m(self) -> float:
        """northing (utm) or north offset (robot_enu), m"""
    @property
    def vx_mps(self) -> float:
        """velocity east (frame as x_m), m/s"""
    @property
    def vy_mps(self) -> float:
        """velocity north (frame as y_m), m/s"""
    @property
    def length_m(self) -> float:
        """vehicle length, metres, > 0"""
    @property
    def speed_uncertainty_mps(self) -> Optional[float]:
        """+- m/s, or None: GapOptions' fraction of the speed"""
    @property
    def time_s(self) -> float:
        """when it was observed, seconds on the clock of now_s"""
    def __repr__(self) -> str: ...

class GapDecision:
    """GO or WAIT, and why."""

    @property
    def verdict(self) -> Literal['GO', 'WAIT']:
        """'GO' or 'WAIT'"""
    @property
    def go(self) -> bool:
        """True when the robot may start now"""
    @property
    def reason(
        self,
    ) -> Literal[
        'CLEAR', 'VEHICLE_CONFLICT', 'BLOCKED', 'INSUFFICIENT_SIGHT', 'STALE_TRACK', 'GAP_TOO_SHORT'
    ]:
        """'CLEAR', 'VEHICLE_CONFLICT', 'BLOCKED', 'INSUFFICIENT_SIGHT', 'STALE_TRACK' or
        'GAP_TOO_SHORT'"""
    @property
    def limiting_vehicle(self) -> int:
        """index into the vehicles; -1: none, or the unseen vehicle"""
    @property
    def margin_s(self) -> Optional[float]:
        """smallest predicted PET if starting now, seconds, or None"""
    @property
    def earliest_start_s(self) -> Optional[float]:
        """earliest GO time on the now_s clock, seconds, or None (never)"""
    @property
    def stage(self) -> int:
        """0: one-stage crossing; 1 or 2: the stage of a two-stage crossing decided"""
    @property
    def crossing_time_s(self) -> float:
        """seconds (of the stage)"""
    @property
    def required_sight_m(self) -> float:
        """metres each way"""
    @property
    def visible_road_m(self) -> float:
        """road seen each way: sensor range cut by the sight distances, metres"""
    @property
    def critical_gap_s(self) -> float:
        """HCM t_c, seconds (HCM only)"""
    @property
    def vehicles_counted(self) -> int:
        """vehicles that will still reach the crossing, count"""
    @property
    def stale_tracks(self) -> int:
        """tracks older than max_track_age_s, count"""
    @property
    def beyond_sensor_range(self) -> int:
        """tracks farther than sensor_range_m (still counted), count"""
    def __repr__(self) -> str: ...

# --- The map ---

class Map:
    """A roadcross map (GeoPackage written by roadcross-build), opened read-only.

    Map(path) raises MapNotFoundError (a FileNotFoundError), NotARoadcrossMapError or
    WrongVersionError (ValueErrors). One Map is one SQLite connection: use one Map per thread.
    Replace a map file by renaming a new file over it, then open a new Map; never rewrite it in
    place while a Map has it open. Usable as a context manager (closes on exit)."""

    def __init__(
        self, path: Union[str, bytes, os.PathLike[str], os.PathLike[bytes]]
    ) -> None:
        """path: the map file (str or os.PathLike)"""
    @property
    def info(self) -> MapInfo:
        """MapInfo: UTM zone, extent, segment count, metadata"""
    @property
    def closed(self) -> bool:
        """True after close() or the end of the with block"""
    def close(self) -> None:
        """Close the map now; later queries raise ValueError."""
    def __enter__(self) -> Map: ...
    def __exit__(
        self, exc_type: object, exc_value: object, traceback: object, /
    ) -> Literal[False]: ...
    def to_utm(
        self,
        *,
        lat: Optional[float] = None,
        lon: Optional[float] = None,
        easting: Optional[float] = None,
        northing: Optional[float] = None,
    ) -> PlanePoint:
        """The position in the map's UTM zone (PlanePoint, metres).
        Position (keyword-only): lat, lon: WGS84 latitude and longitude, degrees; or easting,
        northing: UTM metres in the map's zone (Map.info.utm_zone)."""
    def nearest(
        self,
        *,
        lat: Optional[float] = None,
        lon: Optional[float] = None,
        easting: Optional[float] = None,
        northing: Optional[float] = None,
        max_distance_m: float = 1000.0,
    ) -> NearestRoad:
        """The nearest road centreline (NearestRoad).
        Position (keyword-only): lat, lon: WGS84 latitude and longitude, degrees; or easting,
        northing: UTM metres in the map's zone (Map.info.utm_zone).
        max_distance_m: search radius, metres, > 0; NoRoadError when no road is that near."""
    def assess(
        self,
        *,
        lat: Optional[float] = None,
        lon: Optional[float] = None,
        easting: Optional[float] = None,
        northing: Optional[float] = None,
        valid_distance_m: Optional[float] = None,
        threshold: Optional[float] = None,
        max_distance_m: float = 1000.0,
        max_kerb_height_m: Optional[float] = None,
    ) -> Assessment:
        """Is this a suitable place to cross (Assessment).
        Position (keyword-only): lat, lon: WGS84 latitude and longitude, degrees; or easting,
        northing: UTM metres in the map's zone (Map.info.utm_zone).
        valid_distance_m: valid within this distance of a centreline, metres (None: the map's,
        10 m by default); threshold: suitable when score + context_score >= this (None: the
        map's); max_distance_m: how far to look for a road, metres, > 0; max_kerb_height_m: the
        highest kerb the robot climbs, metres, >= 0 (None: the map profile's; a known higher
        kerb is KERB_TOO_HIGH, an unknown one never forbids)."""
    def assess_segment(
        self,
        segment_id: int,
        *,
        valid_distance_m: Optional[float] = None,
        threshold: Optional[float] = None,
        max_kerb_height_m: Optional[float] = None,
    ) -> Assessment:
        """The assessment on the centreline of one segment (distance 0); NoRoadError when there
        is no such segment. Thresholds as in assess."""
    def better_place(
        self,
        *,
        lat: Optional[float] = None,
        lon: Optional[float] = None,
        easting: Optional[float] = None,
        northing: Optional[float] = None,
        search_radius_m: float = 100.0,
        max_candidates: int = 5,
        valid_distance_m: Optional[float] = None,
        threshold: Optional[float] = None,
        max_kerb_height_m: Optional[float] = None,
    ) -> BetterPlaces:
        """Better places to cross nearby, reached by walking along the road on the robot's side
        (BetterPlaces).
        Position (keyword-only): lat, lon: WGS84 latitude and longitude, degrees; or easting,
        northing: UTM metres in the map's zone (Map.info.utm_zone).
        search_radius_m: walking distance, metres, > 0; max_candidates: at most this many;
        thresholds as in assess."""
    def road_heading(
        self,
        *,
        lat: Optional[float] = None,
        lon: Optional[float] = None,
        easting: Optional[float] = None,
        northing: Optional[float] = None,
        max_distance_m: float = 1000.0,
    ) -> RoadHeading:
        """The road's direction and the crossing heading (RoadHeading; ENU grid yaws, radians).
        Position (keyword-only): lat, lon: WGS84 latitude and longitude, degrees; or easting,
        northing: UTM metres in the map's zone (Map.info.utm_zone).
        max_distance_m: search radius, metres, > 0."""
    def plan_crossing(
        self,
        *,
        lat: Optional[float] = None,
        lon: Optional[float] = None,
        easting: Optional[float] = None,
        northing: Optional[float] = None,
        default_width_m: float = 6.0,
        kerb_margin_m: float = 0.5,
    ) -> CrossingPlan:
        """A CrossingPlan from this position straight across the road, to half the road width
        (the map's width_m, else default_width_m, metres) plus kerb_margin_m (metres) beyond the
        centreline. For roadcross.monitor.
        Position (keyword-only): lat, lon: WGS84 latitude and longitude, degrees; or easting,
        northing: UTM metres in the map's zone (Map.info.utm_zone)."""
    def gap_crossing(
        self,
        *,
        lat: Optional[float] = None,
        lon: Optional[float] = None,
        easting: Optional[float] = None,
        northing: Optional[float] = None,
        default_width_m: float = 6.0,
        default_lane_width_m: float = 3.25,
        default_maxspeed_kmh: float = 50.0,
    ) -> GapCrossing:
        """The GapCrossing at this position (start, heading, lanes, width, maxspeed from the
        map; the defaults where it has none: width metres, lane width metres, km/h). For
        roadcross.gap_decision.
        Position (keyword-only): lat, lon: WGS84 latitude and longitude, degrees; or easting,
        northing: UTM metres in the map's zone (Map.info.utm_zone)."""
    def __repr__(self) -> str: ...

class MapSource:
    """Which map of a MapSet answered."""

    @property
    def index(self) -> int:
        """position of the map in the set, from 0"""
    @property
    def path(self) -> str:
        """the map's file, as opened"""
    @property
    def map_id(self) -> Optional[str]:
        """the map's identifier (metadata map_id), None when it has none"""
    def __repr__(self) -> str: ...

class MapSet:
    """Several roadcross maps answered as one (a fleet's area in several files or UTM zones).

    MapSet(paths): each path a map file or a directory of maps (every file in it must be a
    map). Raises like Map(path), naming the file at fault. One MapSet per thread. Usable as a
    context manager (closes on exit)."""

    def __init__(
        self, paths: Sequence[Union[str, bytes, os.PathLike[str], os.PathLike[bytes]]]
    ) -> None:
        """paths: map files and directories of maps (str or os.PathLike each)"""
    def __len__(self) -> int: ...
    @property
    def maps(self) -> list[MapInfo]:
        """MapInfo of every map, in the set's order (a directory's maps by name)"""
    @property
    def closed(self) -> bool:
        """True after close() or the end of the with block"""
    def close(self) -> None:
        """Close every map now; later queries raise ValueError."""
    def __enter__(self) -> MapSet: ...
    def __exit__(
        self, exc_type: object, exc_value: object, traceback: object, /
    ) -> Literal[False]: ...
    def nearest(
        self,
        *,
        lat: Optional[float] = None,
        lon: Optional[float] = None,
        easting: Optional[float] = None,
        northing: Optional[float] = None,
        utm_zone: Optional[str] = None,
        max_distance_m: float = 1000.0,
    ) -> tuple[NearestRoad, MapSource]:
        """Map.nearest over the set: (NearestRoad, MapSource).
        Position (keyword-only): lat, lon: WGS84 latitude and longitude, degrees; or easting,
        northing: UTM metres with utm_zone, the zone as '33N' or '34S' (required: a set's maps
        may lie in several zones). Returns (answer, MapSource): the answer of the map whose road
        is nearest among the maps that cover the position, and which map that is.
        max_distance_m: search radius, metres, > 0; NoRoadError when no map has a road that
        near."""
    def assess(
        self,
        *,
        lat: Optional[float] = None,
        lon: Optional[float] = None,
        easting: Optional[float] = None,
        northing: Optional[float] = None,
        utm_zone: Optional[str] = None,
        valid_distance_m: Optional[float] = None,
        threshold: Optional[float] = None,
        max_distance_m: float = 1000.0,
        max_kerb_height_m: Optional[float] = None,
    ) -> tuple[Assessment, MapSource]:
        """Map.assess over the set: (Assessment, MapSource).
        Position (keyword-only): lat, lon: WGS84 latitude and longitude, degrees; or easting,
        northing: UTM metres with utm_zone, the zone as '33N' or '34S' (required: a set's maps
        may lie in several zones). Returns (answer, MapSource): the answer of the map whose road
        is nearest among the maps that cover the position, and which map that is.
        Thresholds and max_distance_m as in Map.assess."""
    def better_place(
        self,
        *,
        lat: Optional[float] = None,
        lon: Optional[float] = None,
        easting: Optional[float] = None,
        northing: Optional[float] = None,
        utm_zone: Optional[str] = None,
        search_radius_m: float = 100.0,
        max_candidates: int = 5,
        valid_distance_m: Optional[float] = None,
        threshold: Optional[float] = None,
        max_kerb_height_m: Optional[float] = None,
    ) -> tuple[BetterPlaces, MapSource]:
        """Map.better_place over the set: (BetterPlaces, MapSource).
        Position (keyword-only): lat, lon: WGS84 latitude and longitude, degrees; or easting,
        northing: UTM metres with utm_zone, the zone as '33N' or '34S' (required: a set's maps
        may lie in several zones). Returns (answer, MapSource): the answer of the map whose road
        is nearest among the maps that cover the position, and which map that is.
        Options as in Map.better_place."""
    def road_heading(
        self,
        *,
        lat: Optional[float] = None,
        lon: Optional[float] = None,
        easting: Optional[float] = None,
        northing: Optional[float] = None,
        utm_zone: Optional[str] = None,
        max_distance_m: float = 1000.0,
    ) -> tuple[RoadHeading, MapSource]:
        """Map.road_heading over the set: (RoadHeading, MapSource).
        Position (keyword-only): lat, lon: WGS84 latitude and longitude, degrees; or easting,
        northing: UTM metres with utm_zone, the zone as '33N' or '34S' (required: a set's maps
        may lie in several zones). Returns (answer, MapSource): the answer of the map whose road
        is nearest among the maps that cover the position, and which map that is.
        max_distance_m: search radius, metres, > 0."""
    def __repr__(self) -> str: ...

# --- Pure computations (no map access) ---

def monitor(
    plan: CrossingPlan,
    *,
    easting: float,
    northing: float,
    yaw_rad: float,
    drift_m: float = 0.5,
    corridor_half_width_m: float = 1.5,
    heading_tolerance_rad: float = 0.35,
    done_margin_m: float = 0.2,
) -> CrossingProgress:
    """Progress of the robot on a CrossingPlan (CrossingProgress). Pure computation, no map
    access.
    easting, northing: the robot's UTM position, metres; yaw_rad: its ENU grid yaw, radians (any
    value). drift_m: DRIFTING beyond this lateral deviation, metres; corridor_half_width_m:
    LEAVING_CORRIDOR beyond this, metres; heading_tolerance_rad: DRIFTING beyond this heading
    error, radians; done_margin_m: DONE within this of the target, metres."""

def gap_decision(
    crossing: GapCrossing,
    vehicles: Sequence[Vehicle],
    *,
    now_s: float,
    speed_mps: float = 1.2,
    startup_s: float = 1.0,
    radius_m: float = 0.4,
    min_pet_s: float = 1.2,
    safety_buffer_m: float = 0.5,
    speed_uncertainty_fraction: float = 0.1,
    stopped_speed_mps: float = 0.1,
    max_track_age_s: float = 0.5,
    sensor_range_m: float = 200.0,
    unseen_speed_factor: float = 1.2,
    turning_speed_kmh: float = 25.0,
) -> GapDecision:
    """May the robot start crossing now (GapDecision)? GO when every vehicle's predicted
    post-encroachment time is at least min_pet_s, no track is stale and the road is seen far
    enough (docs/runtime.md, Gap acceptance).
    crossing: a GapCrossing (Map.gap_crossing); vehicles: a list of Vehicle; now_s: the current
    time, seconds, same clock as Vehicle.time_s. The robot: speed_mps (crossing speed, m/s, > 0),
    startup_s (seconds, >= 0), radius_m (half footprint, metres). Options: min_pet_s (seconds),
    safety_buffer_m (metres), speed_uncertainty_fraction (>= 0), stopped_speed_mps (m/s),
    max_track_age_s (seconds), sensor_range_m (metres, > 0), unseen_speed_factor (x maxspeed),
    turning_speed_kmh (km/h). InvalidArgumentError for NaN, a timestamp after now_s, or
    out-of-range values."""

def hcm_gap_decision(
    crossing: GapCrossing,
    vehicles: Sequence[Vehicle],
    *,
    now_s: float,
    speed_mps: float = 1.2,
    startup_s: float = 1.0,
    radius_m: float = 0.4,
    min_pet_s: float = 1.2,
    safety_buffer_m: float = 0.5,
    speed_uncertainty_fraction: float = 0.1,
    stopped_speed_mps: float = 0.1,
    max_track_age_s: float = 0.5,
    sensor_range_m: float = 200.0,
    unseen_speed_factor: float = 1.2,
    turning_speed_kmh: float = 25.0,
    start_clearance_s: float = 3.0,
) -> GapDecision:
    """The HCM reference policy (GapDecision): GO when no vehicle is in the crossing and the next
    one arrives no sooner than the critical gap t_c = width / speed_mps + start_clearance_s
    (seconds).
    crossing: a GapCrossing (Map.gap_crossing); vehicles: a list of Vehicle; now_s: the current
    time, seconds, same clock as Vehicle.time_s. The robot: speed_mps (crossing speed, m/s, > 0),
    startup_s (seconds, >= 0), radius_m (half footprint, metres). Options: min_pet_s (seconds),
    safety_buffer_m (metres), speed_uncertainty_fraction (>= 0), stopped_speed_mps (m/s),
    max_track_age_s (seconds), sensor_range_m (metres, > 0), unseen_speed_factor (x maxspeed),
    turning_speed_kmh (km/h). InvalidArgumentError for NaN, a timestamp after now_s, or
    out-of-range values."""

def sight_distance_m(
    assessment: Assessment, *, sensor_range_m: float = 200.0, clearance_m: float = 3.0
) -> float:
    """How far along the road the robot can see at an assessed place, metres: the sensor range
    (metres), cut at a bend by an obstruction clearance_m (metres) inside the curve."""

def describe_reason(code: str) -> str:
    """A sentence for a reason code (e.g. 'SHARP_BEND'), for people."""
