// roadcross view: the map's segments on one canvas, coloured by the runtime's verdict or by the
// reason that decides it; a segment's terms on hover and click; for a searched or clicked place
// the runtime's three answers, computed here by the runtime's own rules from data.js:
//
// - assess: the nearest segment (a box grown from 16 m, as Map::assess searches), valid within
//   valid_distance_m, and the segment's verdict that roadcross computed with the runtime
//   (schema::judge_segment), plus NO_PAVEMENT_FAR_SIDE for the side the place is on;
// - road_heading: the road's direction at the nearest point (the mean of the two edges at a
//   vertex, and of the continuing segment at a segment's end) and the perpendicular across it;
// - better_place: the walk along the road graph from the place (Dijkstra over the segments
//   within the search radius, straight on or turning towards the robot's own side at a
//   junction), the candidates judged and ordered as Map::better_place does.
//
// Positions are UTM metres in the map's zone, as in the runtime, rounded to 0.01 m in data.js;
// a typed latitude/longitude is projected with the Krüger series (Karney 2011, to n^6), within
// a micrometre of GeographicLib. tests/cli/view_test.sh compares the answers with the CLI's.
(function () {
  'use strict';
  const data = window.ROADCROSS_DATA;
  const meta = data.meta;
  const strings = data.strings;
  const S = data.segments;
  const PI = Math.PI;
  const DEG = PI / 180;

  // ---------------------------------------------------------------------------------------
  // Angles, as geo/ defines them: ENU yaw in (-pi, pi], compass bearing in [0, 360).
  function normalizeRad(a) {
    let r = a - 2 * PI * Math.round(a / (2 * PI));
    if (r <= -PI) r += 2 * PI;
    if (r > PI) r -= 2 * PI;
    return r;
  }
  function angleDifferenceRad(to, from) { return normalizeRad(normalizeRad(to) - normalizeRad(from)); }
  function bearingDeg(yawRad) {
    let b = (90 - yawRad / DEG) % 360;
    if (b < 0) b += 360;
    if (b >= 360) b -= 360;
    return b;
  }

  // ---------------------------------------------------------------------------------------
  // WGS84 <-> UTM, transverse Mercator by Krüger's series in n (Karney 2011, eqs. 35-36).
  const utm = (function () {
    const a = 6378137, f = 1 / 298.257223563, k0 = 0.9996;
    const n = f / (2 - f), n2 = n * n, n3 = n2 * n, n4 = n3 * n, n5 = n4 * n, n6 = n5 * n;
    const e = Math.sqrt(f * (2 - f));
    const A = a / (1 + n) * (1 + n2 / 4 + n4 / 64 + n6 / 256);
    const alpha = [
      n / 2 - 2 * n2 / 3 + 5 * n3 / 16 + 41 * n4 / 180 - 127 * n5 / 288 + 7891 * n6 / 37800,
      13 * n2 / 48 - 3 * n3 / 5 + 557 * n4 / 1440 + 281 * n5 / 630 - 1983433 * n6 / 1935360,
      61 * n3 / 240 - 103 * n4 / 140 + 15061 * n5 / 26880 + 167603 * n6 / 181440,
      49561 * n4 / 161280 - 179 * n5 / 168 + 6601661 * n6 / 7257600,
      34729 * n5 / 80640 - 3418889 * n6 / 1995840,
      212378941 * n6 / 319334400];
    const beta = [
      n / 2 - 2 * n2 / 3 + 37 * n3 / 96 - n4 / 360 - 81 * n5 / 512 + 96199 * n6 / 604800,
      n2 / 48 + n3 / 15 - 437 * n4 / 1440 + 46 * n5 / 105 - 1118711 * n6 / 3870720,
      17 * n3 / 480 - 37 * n4 / 840 - 209 * n5 / 4480 + 5569 * n6 / 90720,
      4397 * n4 / 161280 - 11 * n5 / 504 - 830251 * n6 / 7257600,
      4583 * n5 / 161280 - 108847 * n6 / 3991680,
      20648693 * n6 / 638668800];
    const delta = [
      2 * n - 2 * n2 / 3 - 2 * n3 + 116 * n4 / 45 + 26 * n5 / 45 - 2854 * n6 / 675,
      7 * n2 / 3 - 8 * n3 / 5 - 227 * n4 / 45 + 2704 * n5 / 315 + 2323 * n6 / 945,
      56 * n3 / 15 - 136 * n4 / 35 - 1262 * n5 / 105 + 73814 * n6 / 2835,
      4279 * n4 / 630 - 332 * n5 / 35 - 399572 * n6 / 14175,
      4174 * n5 / 315 - 144838 * n6 / 6237,
      601676 * n6 / 22275];
    const lon0 = (meta.utm_zone * 6 - 183) * DEG;
    const falseNorthing = meta.utm_northern ? 0 : 10000000;
    function forward(latDeg, lonDeg) {
      const phi = latDeg * DEG, lam = normalizeRad(lonDeg * DEG - lon0);
      const s = Math.sin(phi);
      const t = Math.sinh(Math.atanh(s) - e * Math.atanh(e * s));
      const xi = Math.atan2(t, Math.cos(lam));
      const eta = Math.atanh(Math.sin(lam) / Math.sqrt(1 + t * t));
      let x = eta, y = xi;
      for (let j = 1; j <= 6; j++) {
        x += alpha[j - 1] * Math.cos(2 * j * xi) * Math.sinh(2 * j * eta);
        y += alpha[j - 1] * Math.sin(2 * j * xi) * Math.cosh(2 * j * eta);
      }
      return [500000 + k0 * A * x, falseNorthing + k0 * A * y];
    }
    function inverse(eastingM, northingM) {
      const xi = (northingM - falseNorthing) / (k0 * A), eta = (eastingM - 500000) / (k0 * A);
      let xp = xi, ep = eta;
      for (let j = 1; j <= 6; j++) {
        xp -= beta[j - 1] * Math.sin(2 * j * xi) * Math.cosh(2 * j * eta);
        ep -= beta[j - 1] * Math.cos(2 * j * xi) * Math.sinh(2 * j * eta);
      }
      const chi = Math.asin(Math.sin(xp) / Math.cosh(ep));
      let phi = chi;
      for (let j = 1; j <= 6; j++) phi += delta[j - 1] * Math.sin(2 * j * chi);
      return [phi / DEG, (lon0 + Math.atan2(Math.sinh(ep), Math.cos(xp))) / DEG];
    }
    // Grid north's angle from true north (the sphere's formula: within 0.01 degrees, enough to
    // turn an arrow; answers give grid yaws as the runtime does).
    function convergenceRad(latDeg, lonDeg) {
      return Math.atan(Math.tan(normalizeRad(lonDeg * DEG - lon0)) * Math.sin(latDeg * DEG));
    }
    return { forward, inverse, convergenceRad };
  })();

  // ---------------------------------------------------------------------------------------
  // The segments: UTM metres (X, Y), Web Mercator pixels at zoom 0 (PX, PY), boxes of both.
  const count = S.fid.length;
  const first = new Uint32Array(count + 1);
  for (let i = 0; i < count; i++) first[i + 1] = first[i] + S.count[i];
  const points = first[count];
  const X = new Float64Array(points), Y = new Float64Array(points);
  const PX = new Float64Array(points), PY = new Float64Array(points);
  const box = new Float64Array(4 * count);     // UTM min x, min y, max x, max y
  const pixelBox = new Float64Array(4 * count);  // zoom-0 pixels, the same
  const MERCATOR_R = 6378137;
  function mercatorPixel(latDeg, lonDeg) {
    const x = lonDeg * DEG, y = Math.log(Math.tan(PI / 4 + latDeg * DEG / 2));
    return [256 * (0.5 + x / (2 * PI)), 256 * (0.5 - y / (2 * PI))];
  }
  {
    const [ox, oy] = meta.origin_cm;
    let k = 0;
    for (let i = 0; i < count; i++) {
      let x = ox, y = oy;
      let b0 = Infinity, b1 = Infinity, b2 = -Infinity, b3 = -Infinity;
      let p0 = Infinity, p1 = Infinity, p2 = -Infinity, p3 = -Infinity;
      for (let j = first[i]; j < first[i + 1]; j++, k += 2) {
        x += S.xy_cm[k];
        y += S.xy_cm[k + 1];
        X[j] = x / 100;
        Y[j] = y / 100;
        const [lat, lon] = utm.inverse(X[j], Y[j]);
        [PX[j], PY[j]] = mercatorPixel(lat, lon);
        b0 = Math.min(b0, X[j]); b1 = Math.min(b1, Y[j]); b2 = Math.max(b2, X[j]); b3 = Math.max(b3, Y[j]);
        p0 = Math.min(p0, PX[j]); p1 = Math.min(p1, PY[j]); p2 = Math.max(p2, PX[j]); p3 = Math.max(p3, PY[j]);
      }
      box.set([b0, b1, b2, b3], 4 * i);
      pixelBox.set([p0, p1, p2, p3], 4 * i);
    }
  }
  const lengthM = (i) => S.length_cm[i] / 100;
  const codesOf = (index) => (strings[index] ? strings[index].split(',') : []);
  const decidingReason = (i) => strings[S.decide[i]];

  // A grid of the segments' boxes, for "which segments meet this square".
  const CELL_M = 64;
  const grid = new Map();
  const cellKey = (cx, cy) => cx * 1048576 + cy;
  for (let i = 0; i < count; i++) {
    for (let cx = Math.floor(box[4 * i] / CELL_M); cx <= Math.floor(box[4 * i + 2] / CELL_M); cx++) {
      for (let cy = Math.floor(box[4 * i + 1] / CELL_M); cy <= Math.floor(box[4 * i + 3] / CELL_M); cy++) {
        const key = cellKey(cx, cy);
        if (!grid.has(key)) grid.set(key, []);
        grid.get(key).push(i);
      }
    }
  }
  // Segments whose box meets [x0, x1] x [y0, y1], in fid order.
  function segmentsMeeting(x0, y0, x1, y1) {
    const found = new Set();
    const cx0 = Math.floor(x0 / CELL_M), cx1 = Math.floor(x1 / CELL_M);
    const cy0 = Math.floor(y0 / CELL_M), cy1 = Math.floor(y1 / CELL_M);
    if ((cx1 - cx0 + 1) * (cy1 - cy0 + 1) > 4 * grid.size) {
      for (let i = 0; i < count; i++) found.add(i);
    } else {
      for (let cx = cx0; cx <= cx1; cx++) {
        for (let cy = cy0; cy <= cy1; cy++) for (const i of grid.get(cellKey(cx, cy)) || []) found.add(i);
      }
    }
    return [...found].filter((i) => box[4 * i + 2] >= x0 && box[4 * i] <= x1 &&
      box[4 * i + 3] >= y0 && box[4 * i + 1] <= y1).sort((a, b) => a - b);
  }

  // ---------------------------------------------------------------------------------------
  // The runtime's polyline rules (runtime/src/polyline.cpp).
  function project(i, x, y) {
    let best = { d: Infinity, cx: X[first[i]], cy: Y[first[i]], edge: 0, t: 0 };
    for (let j = first[i]; j + 1 < first[i + 1]; j++) {
      const dx = X[j + 1] - X[j], dy = Y[j + 1] - Y[j];
      const l2 = dx * dx + dy * dy;
      let t = 0;
      if (l2 > 0) t = Math.max(0, Math.min(1, ((x - X[j]) * dx + (y - Y[j]) * dy) / l2));
      const cx = X[j] + t * dx, cy = Y[j] + t * dy;
      const d = Math.hypot(x - cx, y - cy);
      if (d < best.d) best = { d, cx, cy, edge: j - first[i], t };
    }
    return best;
  }
  function edgeYaw(i, edge) {
    const j = first[i] + edge;
    return normalizeRad(Math.atan2(Y[j + 1] - Y[j], X[j + 1] - X[j]));
  }
  function polylineDirection(i, at) {
    const lastEdge = S.count[i] - 2;
    let before = at.edge, after = at.edge;
    if (at.t <= 0 && at.edge > 0) before = at.edge - 1;
    if (at.t >= 1 && at.edge < lastEdge) after = at.edge + 1;
    const yawBefore = edgeYaw(i, before);
    if (before === after) return yawBefore;
    return normalizeRad(yawBefore + 0.5 * angleDifferenceRad(edgeYaw(i, after), yawBefore));
  }
  // Segments by graph node.
  let nodeCount = 0;
  for (let i = 0; i < count; i++) nodeCount = Math.max(nodeCount, S.from[i] + 1, S.to[i] + 1);
  const atNode = Array.from({ length: nodeCount }, () => []);
  for (let i = 0; i < count; i++) { atNode[S.from[i]].push(i); atNode[S.to[i]].push(i); }
  // The road's direction at a projection (Map::Impl::direction_at): at a segment's end where
  // exactly one other segment continues, the mean of the two.
  function directionAt(i, at) {
    const own = polylineDirection(i, at);
    const atStart = at.edge === 0 && at.t <= 0, atEnd = at.edge + 2 === S.count[i] && at.t >= 1;
    if ((!atStart && !atEnd) || S.from[i] === S.to[i]) return own;
    const node = atStart ? S.from[i] : S.to[i];
    let ends = 0, leaving = 0;
    for (const o of atNode[node]) {
      if (o === i) continue;
      const f = first[o], l = first[o + 1] - 1;
      if (S.from[o] === node) { ends++; leaving = normalizeRad(Math.atan2(Y[f + 1] - Y[f], X[f + 1] - X[f])); }
      if (S.to[o] === node) { ends++; leaving = normalizeRad(Math.atan2(Y[l - 1] - Y[l], X[l - 1] - X[l])); }
    }
    if (ends !== 1) return own;
    const before = atEnd ? own : normalizeRad(leaving + PI);
    const after = atEnd ? leaving : own;
    return normalizeRad(before + 0.5 * angleDifferenceRad(after, before));
  }

  // ---------------------------------------------------------------------------------------
  // The runtime's answers.
  function nearest(x, y, maxDistanceM) {
    let best = null;
    for (let r = Math.min(16, maxDistanceM); ; r = Math.min(2 * r, maxDistanceM)) {
      for (const i of segmentsMeeting(x - r, y - r, x + r, y + r)) {
        const at = project(i, x, y);
        if (!best || at.d < best.at.d) best = { i, at };
      }
      if ((best && best.at.d <= r) || r >= maxDistanceM) break;
    }
    return best && best.at.d <= maxDistanceM ? best : null;
  }
  function sideOf(near, x, y) {
    if (near.at.d < 1e-3 || S.count[near.i] < 2) return 0;
    const yaw = polylineDirection(near.i, near.at);
    const cross = Math.cos(yaw) * (y - near.at.cy) - Math.sin(yaw) * (x - near.at.cx);
    return cross >= 0 ? 1 : -1;
  }
  const metresOrNull = (dm) => (dm === null ? null : dm / 10);

  function assess(x, y) {
    const near = nearest(x, y, meta.max_distance_m);
    if (!near) return { error: 'no road within ' + meta.max_distance_m + ' m of E ' + x.toFixed(1) + ' N ' + y.toFixed(1) };
    const i = near.i;
    const valid = near.at.d <= meta.valid_distance_m;
    const side = sideOf(near, x, y);
    const reasons = codesOf(S.reasons[i]);
    const far = side > 0 ? S.sidewalk_right[i] : side < 0 ? S.sidewalk_left[i] : null;
    const stranded = far === 0;
    if (stranded) reasons.splice(reasons.length - S.codes_after_pavement[i], 0, 'NO_PAVEMENT_FAR_SIDE');
    if (!valid) reasons.unshift('TOO_FAR_FROM_ROAD');
    return {
      valid, suitable: valid && S.suitable[i] === 1 && !stranded, segment_id: S.fid[i],
      highway: strings[S.highway[i]], name: strings[S.name[i]], distance_m: near.at.d,
      closest_utm_m: [near.at.cx, near.at.cy], score: S.score[i], context_score: S.context[i],
      threshold: meta.threshold, rank: S.rank[i],
      sight_forward_m: metresOrNull(S.sight_forward_dm[i]), sight_backward_m: metresOrNull(S.sight_backward_dm[i]),
      required_sight_m: metresOrNull(S.required_sight_dm[i]), robot_side: side, reasons,
      index: i,
    };
  }

  function roadHeading(x, y) {
    const near = nearest(x, y, meta.max_distance_m);
    if (!near) return null;
    const road = directionAt(near.i, near.at);
    const side = Math.cos(road) * (y - near.at.cy) - Math.sin(road) * (x - near.at.cx);
    const onCentreline = near.at.d < 1e-3;
    const crossing = normalizeRad(road + (side >= 0 || onCentreline ? -PI / 2 : PI / 2));
    return {
      segment_id: S.fid[near.i], road_heading_rad: road, road_bearing_deg: bearingDeg(road),
      crossing_heading_rad: crossing, crossing_bearing_deg: bearingDeg(crossing), on_centreline: onCentreline,
    };
  }

  // The point `fraction` along segment i and the direction there.
  function pointAndDirection(i, fraction) {
    let total = 0;
    for (let j = first[i] + 1; j < first[i + 1]; j++) total += Math.hypot(X[j] - X[j - 1], Y[j] - Y[j - 1]);
    let target = fraction * total;
    for (let j = first[i] + 1; j < first[i + 1]; j++) {
      const dx = X[j] - X[j - 1], dy = Y[j] - Y[j - 1], edge = Math.hypot(dx, dy);
      if (target <= edge || j + 1 === first[i + 1]) {
        const t = edge > 0 ? Math.max(0, Math.min(1, target / edge)) : 0;
        return [X[j - 1] + t * dx, Y[j - 1] + t * dy, Math.atan2(dy, dx)];
      }
      target -= edge;
    }
    return [X[first[i]], Y[first[i]], 0];
  }
  function departureYaw(i, forward) {
    const f = first[i], l = first[i + 1] - 1;
    return forward ? Math.atan2(Y[f + 1] - Y[f], X[f + 1] - X[f]) : Math.atan2(Y[l - 1] - Y[l], X[l - 1] - X[l]);
  }
  const arrivalYaw = (i, forward) => normalizeRad(departureYaw(i, !forward) + PI);

  // Map::better_place (runtime/src/better_place.cpp), step by step.
  function betterPlace(x, y, searchRadiusM, maxCandidates) {
    const here = assess(x, y);
    if (here.error) return { error: here.error };
    const local = segmentsMeeting(x - searchRadiusM - 20, y - searchRadiusM - 20, x + searchRadiusM + 20, y + searchRadiusM + 20);
    const start = here.index;
    const nodeSegments = new Map();
    for (const i of local) {
      for (const node of [S.from[i], S.to[i]]) {
        if (!nodeSegments.has(node)) nodeSegments.set(node, []);
        nodeSegments.get(node).push(i);
      }
    }
    const on = project(start, x, y);
    const yaw = polylineDirection(start, on);
    const sideOfStart = Math.cos(yaw) * (y - on.cy) - Math.sin(yaw) * (x - on.cx) >= 0 ? 1 : -1;
    const offsetM = Math.min(Math.max(here.distance_m, 1), meta.valid_distance_m);
    let along = 0;
    const f = first[start];
    for (let j = 0; j < on.edge; j++) along += Math.hypot(X[f + j + 1] - X[f + j], Y[f + j + 1] - Y[f + j]);
    along += on.t * Math.hypot(X[f + on.edge + 1] - X[f + on.edge], Y[f + on.edge + 1] - Y[f + on.edge]);

    const length = lengthM(start);
    const reached = new Map([[start, { d: Math.abs(along - 0.5 * length), forward: true }]]);
    const nodeDistance = new Map([[S.from[start], along], [S.to[start], length - along]]);
    const queue = [[along, S.from[start]], [length - along, S.to[start]]];
    const sideAtNode = new Map([[S.from[start], -sideOfStart], [S.to[start], sideOfStart]]);
    const sideOfSegment = new Map([[start, sideOfStart]]);
    const arrived = new Map([[S.from[start], [start, arrivalYaw(start, false)]], [S.to[start], [start, arrivalYaw(start, true)]]]);
    while (queue.length) {
      let m = 0;
      for (let q = 1; q < queue.length; q++) if (queue[q][0] < queue[m][0]) m = q;
      const [d, node] = queue.splice(m, 1)[0];
      if (d > nodeDistance.get(node) || d > searchRadiusM) continue;
      const [cameBy, heading] = arrived.get(node);
      let onward = (nodeSegments.get(node) || []).filter((i) => i !== cameBy);
      if (onward.length > 1) {
        const turn = (i) => angleDifferenceRad(departureYaw(i, S.from[i] === node), heading);
        let straightest = onward[0];
        for (const i of onward) if (Math.abs(turn(i)) < Math.abs(turn(straightest))) straightest = i;
        const ownSide = sideAtNode.get(node);
        onward = onward.filter((i) => i === straightest || ownSide * turn(i) > 0.3);
      }
      for (const i of onward) {
        if (i === start) continue;
        const forward = S.from[i] === node;
        const mid = d + 0.5 * lengthM(i);
        const r = reached.get(i);
        if (!r || mid < r.d) {
          reached.set(i, { d: mid, forward });
          sideOfSegment.set(i, forward ? sideAtNode.get(node) : -sideAtNode.get(node));
        }
        const next = forward ? S.to[i] : S.from[i];
        const nextD = d + lengthM(i);
        if (!nodeDistance.has(next) || nextD < nodeDistance.get(next)) {
          nodeDistance.set(next, nextD);
          sideAtNode.set(next, sideAtNode.get(node));
          arrived.set(next, [i, arrivalYaw(i, forward)]);
          queue.push([nextD, next]);
        }
      }
    }
    let candidates = [];
    for (const [i, r] of reached) {
      if (r.d > searchRadiusM || !S.offered[i]) continue;
      const [mx, my, direction] = pointAndDirection(i, 0.5);
      const side = sideOfSegment.get(i);
      const judged = decidingReason(i) === '' || decidingReason(i) === 'KERB_TOO_HIGH';
      const kerbTooHigh = S.kerb_too_high[i] === 1;
      const far = side > 0 ? S.sidewalk_right[i] : S.sidewalk_left[i];
      const stranded = far === 0;
      const reasons = codesOf(S.stored_reasons[i]);
      if (kerbTooHigh) reasons.push('KERB_TOO_HIGH');
      if (stranded) reasons.push('NO_PAVEMENT_FAR_SIDE');
      candidates.push({
        point_utm_m: [mx - side * offsetM * Math.sin(direction), my + side * offsetM * Math.cos(direction)],
        walking_distance_m: r.d, segment_id: S.fid[i], suitable: judged && !kerbTooHigh && !stranded,
        score_plus_context: (S.score[i] || 0) + (S.context[i] || 0), designated_crossing: S.designated[i] === 1,
        crossing_heading_rad: normalizeRad(direction - side * PI / 2), reasons,
      });
    }
    candidates.sort((a, b) => {
      if (a.suitable !== b.suitable) return a.suitable ? -1 : 1;
      if (a.designated_crossing !== b.designated_crossing) return a.designated_crossing ? -1 : 1;
      if (a.score_plus_context !== b.score_plus_context) return b.score_plus_context - a.score_plus_context;
      if (a.walking_distance_m !== b.walking_distance_m) return a.walking_distance_m - b.walking_distance_m;
      return a.segment_id - b.segment_id;
    });
    candidates = candidates.slice(0, maxCandidates);
    let reason = '';
    if (!candidates.length || !candidates[0].suitable) {
      candidates = candidates.filter((c) => c.suitable);
      reason = 'no suitable place within ' + Math.trunc(searchRadiusM) + ' m of walking along the road';
    }
    return { candidates, reason };
  }

  // ---------------------------------------------------------------------------------------
  // Drawing: one canvas over the map, redrawn when the view changes.
  const map = L.map('map', { zoomSnap: 0.25, zoomAnimation: false });
  map.attributionControl.setPrefix('Leaflet');
  map.attributionControl.addAttribution(meta.attribution);
  if (meta.hillshade) {
    L.imageOverlay(meta.hillshade.file, meta.hillshade.bounds, { opacity: 0.45 }).addTo(map);
  }
  let colorBy = 'suitable';
  function colorOf(i) {
    if (colorBy === 'reason') {
      const code = decidingReason(i);
      return code ? meta.reason_colors[code] || '#bbbbbb' : meta.colors.suitable;
    }
    return S.suitable[i] ? meta.colors.suitable : meta.colors.unsuitable;
  }
  const crossingXY = [];
  for (let k = 0; k < data.crossings.xy_cm.length; k += 2) {
    const [lat, lon] = utm.inverse((meta.origin_cm[0] + data.crossings.xy_cm[k]) / 100,
      (meta.origin_cm[1] + data.crossings.xy_cm[k + 1]) / 100);
    crossingXY.push(mercatorPixel(lat, lon));
  }

  const NetworkLayer = L.Layer.extend({
    onAdd(m) {
      this._canvas = L.DomUtil.create('canvas', 'roadcross-network leaflet-zoom-hide');
      m.getPanes().overlayPane.appendChild(this._canvas);
      m.on('moveend zoomend resize viewreset', this.redraw, this);
      this.redraw();
    },
    onRemove(m) {
      m.off('moveend zoomend resize viewreset', this.redraw, this);
      this._canvas.remove();
    },
    redraw() {
      const size = map.getSize(), pad = 0.3;
      const topLeft = map.containerPointToLayerPoint([-pad * size.x, -pad * size.y]);
      const width = Math.round(size.x * (1 + 2 * pad)), height = Math.round(size.y * (1 + 2 * pad));
      const ratio = window.devicePixelRatio || 1;
      const canvas = this._canvas;
      L.DomUtil.setPosition(canvas, topLeft);
      canvas.width = width * ratio;
      canvas.height = height * ratio;
      canvas.style.width = width + 'px';
      canvas.style.height = height + 'px';
      const ctx = canvas.getContext('2d');
      ctx.setTransform(ratio, 0, 0, ratio, 0, 0);
      const scale = Math.pow(2, map.getZoom());  // zoom-0 pixels to pixels
      const origin = map.getPixelBounds().min.subtract([pad * size.x, pad * size.y]);
      const ox = origin.x, oy = origin.y;
      const x0 = ox / scale, y0 = oy / scale, x1 = (ox + width) / scale, y1 = (oy + height) / scale;
      const lineWidth = Math.max(1.5, Math.min(5, map.getZoom() - 12));
      const byColor = new Map();
      for (let i = 0; i < count; i++) {
        if (pixelBox[4 * i + 2] < x0 || pixelBox[4 * i] > x1 || pixelBox[4 * i + 3] < y0 || pixelBox[4 * i + 1] > y1) continue;
        const color = colorOf(i);
        if (!byColor.has(color)) byColor.set(color, []);
        byColor.get(color).push(i);
      }
      const trace = (list) => {
        ctx.beginPath();
        for (const i of list) {
          ctx.moveTo(PX[first[i]] * scale - ox, PY[first[i]] * scale - oy);
          for (let j = first[i] + 1; j < first[i + 1]; j++) ctx.lineTo(PX[j] * scale - ox, PY[j] * scale - oy);
        }
      };
      ctx.lineCap = 'round';
      ctx.lineJoin = 'round';
      for (const [color, list] of byColor) {
        trace(list);
        ctx.strokeStyle = color;
        ctx.lineWidth = lineWidth;
        ctx.stroke();
      }
      ctx.lineWidth = 1.5;
      ctx.strokeStyle = '#000';
      ctx.fillStyle = '#fff';
      const radius = Math.max(2, Math.min(4, map.getZoom() - 13));
      for (const [cx, cy] of crossingXY) {
        const px = cx * scale - ox, py = cy * scale - oy;
        if (px < 0 || py < 0 || px > width || py > height) continue;
        ctx.beginPath();
        ctx.arc(px, py, radius, 0, 2 * PI);
        ctx.fill();
        ctx.stroke();
      }
      this.drawn = byColor.size;
    },
  });
  const network = new NetworkLayer().addTo(map);

  const latLngsOf = (i) => {
    const out = [];
    for (let j = first[i]; j < first[i + 1]; j++) out.push(utm.inverse(X[j], Y[j]));
    return out;
  };
  const ext = [Infinity, Infinity, -Infinity, -Infinity];
  for (let i = 0; i < count; i++) {
    ext[0] = Math.min(ext[0], box[4 * i]); ext[1] = Math.min(ext[1], box[4 * i + 1]);
    ext[2] = Math.max(ext[2], box[4 * i + 2]); ext[3] = Math.max(ext[3], box[4 * i + 3]);
  }
  if (count) map.fitBounds([utm.inverse(ext[0], ext[1]), utm.inverse(ext[2], ext[3])], { padding: [10, 10] });
  else map.setView([0, 0], 2);
  L.control.scale({ imperial: false }).addTo(map);

  // ---------------------------------------------------------------------------------------
  // The panel.
  function escapeHtml(text) {
    return String(text).replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' }[c]));
  }
  function reasonList(codes) {
    if (!codes.length) return '';
    return '<ul class="reasons">' + codes.map((c) =>
      '<li><b>' + escapeHtml(c) + '</b>: ' + escapeHtml(meta.reasons[c] || 'see docs/cost-model.md') + '</li>').join('') + '</ul>';
  }
  const metres = (v) => (v === null || v === undefined ? '\u2013' : v.toFixed(1) + ' m');
  function termsTable(i) {
    const rows = [
      ['name', strings[S.name[i]]], ['highway', strings[S.highway[i]]], ['segment', S.fid[i]],
      ['score + context', ((S.score[i] || 0) + (S.context[i] || 0)) + ' (threshold ' + meta.threshold + ')'],
      ['score', S.score[i]], ['context score', S.context[i]], ['rank', S.rank[i]],
      ['junction distance', metres(metresOrNull(S.junction_dm[i]))], ['bend radius', metres(metresOrNull(S.radius_dm[i]))],
      ['length', metres(lengthM(i))],
    ].filter(([, v]) => v !== null && v !== undefined && v !== '');
    return '<table class="terms">' + rows.map(([k, v]) => '<tr><td>' + k + '</td><td>' + escapeHtml(v) + '</td></tr>').join('') + '</table>';
  }
  // The sight distances behind LIMITED_VISIBILITY: each way along the road against the need.
  function sightTable(i) {
    const forward = metresOrNull(S.sight_forward_dm[i]), backward = metresOrNull(S.sight_backward_dm[i]);
    const required = metresOrNull(S.required_sight_dm[i]);
    if (forward === null && backward === null) return '<p class="hint">No sight distances here (a tunnel, or an older map).</p>';
    const row = (label, v) => '<tr><td>' + label + '</td><td>' + metres(v) + '</td><td>' +
      (v !== null && required !== null ? (v >= required ? '\u2713 enough' : '\u2717 ' + (required - v).toFixed(1) + ' m short') : '') + '</td></tr>';
    return '<table class="terms sight"><tr><th colspan="3">Sight along the road</th></tr>' +
      row('forward (way direction)', forward) + row('backward', backward) +
      '<tr><td>required</td><td>' + metres(required) + '</td><td></td></tr></table>';
  }
  const info = document.getElementById('info');
  function showSegment(i) {
    info.innerHTML = '<p class="verdict">' + (S.suitable[i] ? 'Suitable' : 'Not suitable') + ' on the centreline' +
      (decidingReason(i) ? ' (' + escapeHtml(decidingReason(i)) + ')' : '') + '</p>' + termsTable(i) +
      sightTable(i) + reasonList(codesOf(S.reasons[i]));
  }

  document.getElementById('subtitle').textContent = meta.db + ' \u2014 ' + count +
    ' segments; suitable when score + context \u2265 ' + meta.threshold;
  function drawLegend() {
    const swatch = (color, label) => '<div><span class="swatch" style="background:' + color + '"></span>' + label + '</div>';
    let html = '';
    if (colorBy === 'reason') {
      html += swatch(meta.colors.suitable, 'suitable');
      const present = new Set();
      for (let i = 0; i < count; i++) present.add(decidingReason(i));
      for (const [code, color] of Object.entries(meta.reason_colors)) if (present.has(code)) html += swatch(color, code);
    } else {
      html += swatch(meta.colors.suitable, 'suitable') + swatch(meta.colors.unsuitable, 'not suitable');
    }
    html += '<div><span class="dot"></span>designated crossing</div>';
    if (meta.hillshade) html += '<div class="hint">over a hillshade of the terrain</div>';
    document.getElementById('legend').innerHTML = html;
  }
  drawLegend();
  document.getElementById('color-by').addEventListener('change', (event) => {
    colorBy = event.target.value;
    drawLegend();
    network.redraw();
  });

  // Hover and click: the segment under the pointer (within 8 px).
  let highlight = null, pinned = false;
  function nearestOnScreen(latlng) {
    const [x, y] = utm.forward(latlng.lat, latlng.lng);
    const metresPerPixel = 40075016.686 * Math.cos(latlng.lat * DEG) / (256 * Math.pow(2, map.getZoom()));
    return nearest(x, y, Math.max(1, 8 * metresPerPixel));
  }
  function highlightSegment(i) {
    if (highlight) highlight.remove();
    highlight = L.polyline(latLngsOf(i), { color: '#000', weight: 9, opacity: 0.35, interactive: false }).addTo(map);
  }
  map.on('mousemove', (event) => {
    if (pinned) return;
    const near = nearestOnScreen(event.latlng);
    if (!near) return;
    highlightSegment(near.i);
    showSegment(near.i);
  });
  map.on('click', (event) => {
    const text = event.latlng.lat.toFixed(6) + ',' + event.latlng.lng.toFixed(6);
    document.getElementById('query').value = text;
    window.location.hash = text;
    search(text);
  });

  // The searched place: assess, heading and better places, drawn and listed.
  const resultBox = document.getElementById('result');
  const resultJson = document.getElementById('result-json');
  const answerLayer = L.layerGroup().addTo(map);
  function arrow(x, y, yawRad, lengthM, color) {
    // A grid yaw becomes a direction on the (north-up) map through the convergence.
    const [lat, lon] = utm.inverse(x, y);
    const trueYaw = yawRad + utm.convergenceRad(lat, lon);
    const tip = utm.inverse(x + lengthM * Math.cos(yawRad), y + lengthM * Math.sin(yawRad));
    const left = utm.inverse(x + 0.7 * lengthM * Math.cos(yawRad + 0.25), y + 0.7 * lengthM * Math.sin(yawRad + 0.25));
    const right = utm.inverse(x + 0.7 * lengthM * Math.cos(yawRad - 0.25), y + 0.7 * lengthM * Math.sin(yawRad - 0.25));
    L.polyline([[lat, lon], tip], { color, weight: 3, interactive: false }).addTo(answerLayer);
    L.polyline([left, tip, right], { color, weight: 3, interactive: false }).addTo(answerLayer);
    return trueYaw;
  }
  function search(text) {
    const m = text.trim().match(/^(-?\d+(?:\.\d+)?)\s*[,\s]\s*(-?\d+(?:\.\d+)?)(?:\s*[,\s]\s*(\d+(?:\.\d+)?))?$/);
    if (!m) {
      resultBox.innerHTML = '<p class="error">Type a latitude and a longitude, e.g. 50.0757, 14.4160</p>';
      return;
    }
    const lat = parseFloat(m[1]), lon = parseFloat(m[2]);
    const radius = m[3] ? parseFloat(m[3]) : meta.search_radius_m;
    const [x, y] = utm.forward(lat, lon);
    const a = assess(x, y);
    const heading = a.error ? null : roadHeading(x, y);
    const better = a.error ? null : betterPlace(x, y, radius, meta.max_candidates);
    const { index, ...answer } = a;
    resultJson.textContent = JSON.stringify({ query_utm_m: [x, y], assess: answer, heading, better });
    answerLayer.clearLayers();
    L.marker([lat, lon], { icon: L.divIcon({ className: '', html: '<b style="font-size:18px">\u2716</b>', iconSize: [18, 18] }) }).addTo(answerLayer);
    if (a.error) { resultBox.innerHTML = '<p class="error">' + escapeHtml(a.error) + '</p>'; return; }
    pinned = true;
    highlightSegment(index);
    showSegment(index);
    const trueYaw = arrow(x, y, heading.crossing_heading_rad, 12, '#222');
    let html = '<p class="verdict">' + (a.suitable ? 'Suitable place to cross' : 'Not suitable') +
      '</p><p>' + escapeHtml(a.name || a.highway) + ' (segment ' + a.segment_id + '), ' +
      a.distance_m.toFixed(1) + ' m from the centreline</p>' + reasonList(a.reasons) + sightTable(index) +
      '<p><b>Heading</b>: cross towards ' + heading.crossing_bearing_deg.toFixed(1) + '\u00b0 (grid; ' +
      bearingDeg(trueYaw).toFixed(1) + '\u00b0 true), the road runs ' + heading.road_bearing_deg.toFixed(1) + '\u00b0</p>';
    html += '<p><b>Better places</b> within ' + radius + ' m of walking:</p>';
    if (!better.candidates.length) html += '<p class="hint">' + escapeHtml(better.reason) + '</p>';
    html += '<ol class="better">' + better.candidates.map((c) =>
      '<li>' + c.walking_distance_m.toFixed(0) + ' m away, segment ' + c.segment_id + ', score ' + c.score_plus_context +
      (c.designated_crossing ? ', designated crossing' : '') + '</li>').join('') + '</ol>';
    resultBox.innerHTML = html;
    better.candidates.forEach((c, k) => {
      const [clat, clon] = utm.inverse(c.point_utm_m[0], c.point_utm_m[1]);
      L.marker([clat, clon], { icon: L.divIcon({ className: 'candidate', html: String(k + 1), iconSize: [18, 18] }) })
        .bindTooltip('better place ' + (k + 1) + ': ' + c.walking_distance_m.toFixed(0) + ' m of walking').addTo(answerLayer);
      arrow(c.point_utm_m[0], c.point_utm_m[1], c.crossing_heading_rad, 10, '#0072b2');
    });
    // The place and its better places in view, as close as street level.
    const shown = [[lat, lon]].concat(better.candidates.map((c) => utm.inverse(c.point_utm_m[0], c.point_utm_m[1])));
    map.fitBounds(L.latLngBounds(shown).pad(0.15), { maxZoom: 18 });
  }

  document.getElementById('search').addEventListener('submit', (event) => {
    event.preventDefault();
    const text = document.getElementById('query').value;
    window.location.hash = text.replace(/\s+/g, '');
    search(text);
  });
  document.getElementById('unpin').addEventListener('click', () => { pinned = false; });
  // A link or a test can ask for a place: index.html#50.0757,14.4160 (and a radius: ,300).
  if (window.location.hash.length > 1) {
    const text = decodeURIComponent(window.location.hash.slice(1));
    document.getElementById('query').value = text;
    search(text);
  }
  // For benchmarks and tests: the time from navigation start until everything is drawn.
  document.body.dataset.readyMs = performance.now().toFixed(0);
})();
