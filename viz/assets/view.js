// roadcross view: the map's segments coloured by the runtime's suitability, their terms on
// hover/click, and a coordinate search that gives assess's answer.
//
// The search runs assess's rule on the per-segment judgement that roadcross computed with the
// runtime (properties suitable and assess_reasons, for a position on the centreline): it finds
// the nearest segment, and then, as Map::assess does, valid = distance <= valid_distance_m,
// suitable = valid && the segment's suitable, TOO_FAR_FROM_ROAD first when not valid. Distances
// are measured in a local equirectangular frame around the query (within 0.1 % of UTM metres
// over a city); at a junction, where two segments are equally near, the segment may differ
// from the runtime's pick.
(function () {
  'use strict';
  const data = window.ROADCROSS_DATA;
  const meta = data.meta;
  const EARTH_RADIUS_M = 6371008.8;
  const DEG = Math.PI / 180;

  const map = L.map('map', { zoomSnap: 0.25 });
  map.attributionControl.setPrefix('Leaflet');
  map.attributionControl.addAttribution(meta.attribution);

  // The terrain under the network, when the DB holds it (faint, as in roadcross render).
  if (meta.hillshade) {
    L.imageOverlay(meta.hillshade.file, meta.hillshade.bounds, { opacity: 0.45 }).addTo(map);
  }

  function colorOf(props) {
    return props.suitable ? meta.colors.suitable : meta.colors.unsuitable;
  }
  function styleOf(feature) {
    return { color: colorOf(feature.properties), weight: 4, opacity: 1, lineCap: 'round' };
  }
  function escapeHtml(text) {
    return String(text).replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' }[c]));
  }
  function reasonsOf(props) {
    return props.assess_reasons ? props.assess_reasons.split(',') : [];
  }
  function reasonList(codes) {
    if (!codes.length) return '';
    return '<ul class="reasons">' + codes.map((c) =>
      '<li><b>' + escapeHtml(c) + '</b>: ' + escapeHtml(meta.reasons[c] || 'see docs/cost-model.md') + '</li>').join('') + '</ul>';
  }

  const TERMS = ['name', 'highway', 'fid', 'osm_way_id', 'suitable', 'score', 'context_score', 'rank',
    'class_cost', 'curvature_level', 'curvature_cost', 'radius_m', 'junction_distance_m',
    'elevation_cost', 'landform', 'elevation_m', 'slope_deg', 'grade_percent', 'maxspeed_kmh',
    'lanes', 'width_m', 'crossing_distance_m', 'tunnel', 'bridge', 'length_m', 'override_note'];
  function termsTable(props) {
    const rows = TERMS.filter((k) => props[k] !== undefined && props[k] !== null && props[k] !== '')
      .map((k) => {
        let v = props[k];
        if (typeof v === 'number' && !Number.isInteger(v)) v = v.toFixed(1);
        return '<tr><td>' + k + '</td><td>' + escapeHtml(v) + '</td></tr>';
      });
    const total = (props.score ?? 0) + (props.context_score ?? 0);
    rows.splice(7, 0, '<tr><td>score + context</td><td>' + total + ' (threshold ' + meta.threshold + ')</td></tr>');
    return '<table class="terms">' + rows.join('') + '</table>' + reasonList(reasonsOf(props));
  }

  const info = document.getElementById('info');
  const layerOf = new Map();
  let pinned = null;
  function showInfo(props) {
    info.innerHTML = '<p class="verdict">' + (props.suitable ? 'Suitable' : 'Not suitable') +
      ' on the centreline</p>' + termsTable(props);
  }

  const segments = L.geoJSON(data.segments, {
    style: styleOf,
    onEachFeature: (feature, layer) => {
      layerOf.set(feature, layer);
      layer.on('mouseover', () => { layer.setStyle({ weight: 8 }); if (!pinned) showInfo(feature.properties); });
      layer.on('mouseout', () => { if (layer !== found) segments.resetStyle(layer); });
      layer.on('click', () => { pinned = feature; showInfo(feature.properties); });
      layer.bindPopup(() => '<b>' + escapeHtml(feature.properties.name || feature.properties.highway) +
        '</b>' + termsTable(feature.properties));
    },
  }).addTo(map);

  L.geoJSON(data.crossings, {
    filter: (f) => f.properties.designated,
    pointToLayer: (f, latlng) => L.circleMarker(latlng, {
      radius: 4, color: '#000', weight: 1.5, fillColor: '#fff', fillOpacity: 1,
    }).bindTooltip('designated crossing (' + escapeHtml(f.properties.crossing_type) + ')'),
  }).addTo(map);

  if (segments.getLayers().length) map.fitBounds(segments.getBounds(), { padding: [10, 10] });
  else map.setView([0, 0], 2);
  L.control.scale({ imperial: false }).addTo(map);

  document.getElementById('subtitle').textContent = meta.db + ' \u2014 ' +
    data.segments.features.length + ' segments; suitable when score + context \u2265 ' + meta.threshold;
  document.getElementById('legend').innerHTML =
    '<div><span class="swatch" style="background:' + meta.colors.suitable + '"></span>suitable</div>' +
    '<div><span class="swatch" style="background:' + meta.colors.unsuitable + '"></span>not suitable</div>' +
    '<div><span class="dot"></span>designated crossing</div>' +
    (meta.hillshade ? '<div class="hint">over a hillshade of the terrain</div>' : '');

  // Distance from p to the polyline, both [lon, lat], metres, in a frame centred on p.
  function distanceToLine(p, coords) {
    const kx = Math.cos(p[1] * DEG) * EARTH_RADIUS_M * DEG;
    const ky = EARTH_RADIUS_M * DEG;
    let best = Infinity;
    for (let i = 0; i + 1 < coords.length; i++) {
      const ax = (coords[i][0] - p[0]) * kx, ay = (coords[i][1] - p[1]) * ky;
      const bx = (coords[i + 1][0] - p[0]) * kx, by = (coords[i + 1][1] - p[1]) * ky;
      const dx = bx - ax, dy = by - ay;
      const len2 = dx * dx + dy * dy;
      const t = len2 > 0 ? Math.max(0, Math.min(1, -(ax * dx + ay * dy) / len2)) : 0;
      best = Math.min(best, Math.hypot(ax + t * dx, ay + t * dy));
    }
    return best;
  }

  function assess(lat, lon) {
    let nearest = null, distance = Infinity;
    for (const f of data.segments.features) {
      const d = distanceToLine([lon, lat], f.geometry.coordinates);
      if (d < distance) { distance = d; nearest = f; }
    }
    if (!nearest || distance > meta.max_distance_m) {
      return { error: 'no road within ' + meta.max_distance_m + ' m of ' + lat + ', ' + lon };
    }
    const props = nearest.properties;
    const valid = distance <= meta.valid_distance_m;
    const reasons = (valid ? [] : ['TOO_FAR_FROM_ROAD']).concat(reasonsOf(props));
    return {
      valid: valid, suitable: valid && props.suitable, segment_id: props.fid,
      highway: props.highway, name: props.name || '', distance_m: distance,
      score: props.score, context_score: props.context_score, threshold: meta.threshold,
      reasons: reasons, feature: nearest,
    };
  }

  const resultBox = document.getElementById('result');
  const resultJson = document.getElementById('result-json');
  let marker = null;
  let found = null;  // the segment layer of the last search, drawn wide
  function search(text) {
    const m = text.trim().match(/^(-?\d+(?:\.\d+)?)\s*[,\s]\s*(-?\d+(?:\.\d+)?)$/);
    if (!m) {
      resultBox.innerHTML = '<p class="error">Type a latitude and a longitude, e.g. 50.0757, 14.4160</p>';
      return;
    }
    const lat = parseFloat(m[1]), lon = parseFloat(m[2]);
    const a = assess(lat, lon);
    const { feature, ...answer } = a;
    resultJson.textContent = JSON.stringify(answer);
    if (marker) marker.remove();
    marker = L.marker([lat, lon], { icon: L.divIcon({ className: '', html: '<b style="font-size:18px">\u2716</b>', iconSize: [18, 18] }) }).addTo(map);
    if (a.error) { resultBox.innerHTML = '<p class="error">' + escapeHtml(a.error) + '</p>'; return; }
    resultBox.innerHTML = '<p class="verdict">' + (a.suitable ? 'Suitable place to cross' : 'Not suitable') +
      '</p><p>' + escapeHtml(a.name || a.highway) + ' (segment ' + a.segment_id + '), ' +
      a.distance_m.toFixed(1) + ' m from the centreline</p>' + reasonList(a.reasons);
    pinned = feature;
    showInfo(feature.properties);
    if (found) segments.resetStyle(found);
    found = layerOf.get(feature);
    found.setStyle({ weight: 9 });
    found.bringToFront();
    map.setView([lat, lon], Math.max(map.getZoom(), 18));
  }

  document.getElementById('search').addEventListener('submit', (event) => {
    event.preventDefault();
    const text = document.getElementById('query').value;
    window.location.hash = text.replace(/\s+/g, '');
    search(text);
  });
  // A link or a test can ask for a place: index.html#50.0757,14.4160
  if (window.location.hash.length > 1) {
    const text = decodeURIComponent(window.location.hash.slice(1));
    document.getElementById('query').value = text;
    search(text);
  }
})();
