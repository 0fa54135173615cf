#!/usr/bin/env python3
"""Draws docs/sight.svg, the picture of the sight distance method in docs/cost-model.md: (a) plan
view of the L-shaped road with a building in the corner (the known-answer test), (b) profile of
the road over the Gaussian hill. Plain SVG, no dependencies: python3 scripts/make-sight-figure.py
"""
import math
import pathlib

OUT = pathlib.Path(__file__).resolve().parent.parent / "docs" / "sight.svg"


def hill(x, y=0.0):
    return 300.0 + 50.0 * math.exp(-(x * x + y * y) / (2 * 100.0 * 100.0))


def hill_sight(x0, sensor=0.6, obj=1.1):
    """First hidden vehicle position over the hill (5 cm steps), as the test computes it."""
    ez = hill(x0, 3) + sensor
    d = 0.05
    while d <= 300:
        tz = hill(x0 + d) + obj
        for k in range(1, 400):
            t = k / 400
            if hill(x0 + t * d, 3 * (1 - t)) >= ez + t * (tz - ez):
                return d - 0.05
        d += 0.05
    return 300.0


def plan():
    # Offsets in metres -> SVG: scale 2 px/m, origin (the corner) at (330, 250).
    s, ox, oy = 2.0, 330.0, 250.0
    P = lambda x, y: (ox + s * x, oy - s * y)
    out = ['<g font-family="sans-serif" font-size="12">',
           '<text x="20" y="24" font-weight="bold">(a) plan: building in the corner</text>']
    road = " ".join("%.1f,%.1f" % P(x, y) for x, y in [(-150, 0), (0, 0), (0, 100)])
    out.append('<polyline points="%s" fill="none" stroke="#bbb" stroke-width="%.0f"/>' % (road, 6 * s))
    out.append('<polyline points="%s" fill="none" stroke="#666" stroke-dasharray="4 3"/>' % road)
    bx, by = P(-100, 100)
    out.append('<rect x="%.1f" y="%.1f" width="%.1f" height="%.1f" fill="#c96" stroke="#733"/>'
               % (bx, by, 90 * s, 90 * s))
    out.append('<text x="%.1f" y="%.1f">building, 9 m</text>' % P(-85, 55))
    e, t_seen, t_hid = P(-30, 3), P(0, 13.5), P(0, 30)
    out.append('<line x1="%.1f" y1="%.1f" x2="%.1f" y2="%.1f" stroke="green" stroke-width="1.5"/>'
               % (*e, *t_seen))
    out.append('<line x1="%.1f" y1="%.1f" x2="%.1f" y2="%.1f" stroke="red" stroke-dasharray="5 3"/>'
               % (*e, *t_hid))
    out.append('<circle cx="%.1f" cy="%.1f" r="4" fill="blue"/>' % e)
    out.append('<text x="%.1f" y="%.1f">robot at the kerb, 30 m before the corner</text>' % P(-140, -15))
    for (x, y), c in [((0, 13.5), "green"), ((0, 30), "red")]:
        out.append('<rect x="%.1f" y="%.1f" width="8" height="12" fill="%s"/>' % (P(x, y)[0] - 4, P(x, y)[1] - 6, c))
    out.append('<text x="%.1f" y="%.1f">last visible: 30 + 13.5 = 43.5 m along the road</text>' % P(5, 12))
    out.append('<text x="%.1f" y="%.1f">hidden</text>' % P(5, 30))
    out.append('</g>')
    return out


def profile():
    # x from -250 to 150 m -> 20..580 px; z 295..360 m -> 560..300 px.
    X = lambda x: 20 + (x + 250) * 560 / 400
    Z = lambda z: 560 - (z - 295) * 260 / 65
    x0 = -190.0
    d = hill_sight(x0)
    out = ['<g font-family="sans-serif" font-size="12">',
           '<text x="20" y="300" font-weight="bold">(b) profile: crest of a Gaussian hill '
           '(heights x4)</text>']
    ground = " ".join("%.1f,%.1f" % (X(x), Z(hill(x))) for x in range(-250, 151, 5))
    out.append('<polyline points="%s 580,560 20,560" fill="#dcb" stroke="#754"/>' % ground)
    ez = hill(x0, 3) + 0.6
    tx = x0 + d
    tz = hill(tx) + 1.1
    far = x0 + 300
    # The grazing line, continued beyond the last visible vehicle.
    k = (tz - ez) / (tx - x0)
    out.append('<line x1="%.1f" y1="%.1f" x2="%.1f" y2="%.1f" stroke="green" stroke-width="1.5"/>'
               % (X(x0), Z(ez), X(far), Z(ez + k * (far - x0))))
    out.append('<circle cx="%.1f" cy="%.1f" r="4" fill="blue"/>' % (X(x0), Z(ez)))
    out.append('<rect x="%.1f" y="%.1f" width="8" height="8" fill="green"/>' % (X(tx) - 4, Z(tz) - 4))
    out.append('<text x="%.1f" y="%.1f">robot (sensor 0.6 m)</text>' % (X(x0) - 10, Z(ez) + 22))
    out.append('<text x="%.1f" y="%.1f">last visible vehicle (1.1 m): %.1f m along the road</text>'
               % (X(tx) - 60, Z(tz) - 40, d))
    out.append('<text x="%.1f" y="%.1f">beyond: hidden by the crest</text>' % (X(60), Z(hill(60)) + 30))
    out.append('</g>')
    return out


def main():
    parts = ['<svg xmlns="http://www.w3.org/2000/svg" width="600" height="580" '
             'viewBox="0 0 600 580">', '<rect width="600" height="580" fill="white"/>']
    parts += plan() + profile() + ['</svg>']
    OUT.write_text("\n".join(parts) + "\n")
    print("wrote", OUT)


if __name__ == "__main__":
    main()
