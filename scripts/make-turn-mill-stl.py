#!/usr/bin/env python3
"""Writes the STL parts of machines/turn-mill.toml into machines/turn-mill/.

Each part is a closed solid, triangles counter-clockwise seen from outside, in its component's own
frame (mm; docs/turn-mill.md, "The kinematic machine"). Run from the repository root:

    python3 scripts/make-turn-mill-stl.py

The output is deterministic and committed beside this script.
"""

import math
import os
import struct

OUT = os.path.join("machines", "turn-mill")


def box(x0, x1, y0, y1, z0, z1):
    v = [(x, y, z) for z in (z0, z1) for y in (y0, y1) for x in (x0, x1)]
    t = [
        (0, 2, 3), (0, 3, 1),  # z0
        (4, 5, 7), (4, 7, 6),  # z1
        (0, 1, 5), (0, 5, 4),  # y0
        (2, 6, 7), (2, 7, 3),  # y1
        (0, 4, 6), (0, 6, 2),  # x0
        (1, 3, 7), (1, 7, 5),  # x1
    ]
    return [tuple(v[i] for i in tri) for tri in t]


def prism(cx, cy, r, n, z0, z1, phase):
    """A regular n-gon prism about the line (cx, cy) parallel to z, vertices at radius r."""
    ring = [
        (round(cx + r * math.cos(phase + 2 * math.pi * k / n), 6) + 0.0, round(cy + r * math.sin(phase + 2 * math.pi * k / n), 6) + 0.0)
        for k in range(n)
    ]
    tris = []
    for k in range(n):
        (ax, ay), (bx, by) = ring[k], ring[(k + 1) % n]
        # Caps: the -z one seen from -z is clockwise in (x, y).
        tris.append(((cx, cy, z0), (bx, by, z0), (ax, ay, z0)))
        tris.append(((cx, cy, z1), (ax, ay, z1), (bx, by, z1)))
        tris.append(((ax, ay, z0), (bx, by, z0), (bx, by, z1)))
        tris.append(((ax, ay, z0), (bx, by, z1), (ax, ay, z1)))
    return tris


def normal(t):
    (ax, ay, az), (bx, by, bz), (cx, cy, cz) = t
    u = (bx - ax, by - ay, bz - az)
    v = (cx - ax, cy - ay, cz - az)
    n = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
    length = math.sqrt(sum(c * c for c in n)) or 1.0
    return tuple(c / length for c in n)


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


def write_binary(name, tris):
    with open(os.path.join(OUT, name), "wb") as f:
        # A header that starts with "solid", as many exporters write: readers must not be fooled.
        f.write(("solid " + name + " (binary)").encode().ljust(80, b" "))
        f.write(struct.pack("<I", len(tris)))
        for t in tris:
            f.write(struct.pack("<3f", *normal(t)))
            for p in t:
                f.write(struct.pack("<3f", *p))
            f.write(b"\0\0")


def write_ascii(name, tris):
    def g(x):
        return "%.9g" % f32(x)

    with open(os.path.join(OUT, name), "w", newline="\n") as f:
        f.write("solid %s\n" % name)
        for t in tris:
            f.write("  facet normal %s %s %s\n    outer loop\n" % tuple(g(c) for c in normal(t)))
            for p in t:
                f.write("      vertex %s %s %s\n" % tuple(g(c) for c in p))
            f.write("    endloop\n  endfacet\n")
        f.write("endsolid %s\n" % name)


def main():
    os.makedirs(OUT, exist_ok=True)
    # Main headstock: the housing behind the chuck (the chuck's back face is at z = -100).
    write_binary("headstock.stl", box(-260, 260, -260, 260, -420, -100))
    # Turret drum: 12 faces, one per station, 280 mm across its corners, 70 mm thick, its axis
    # 140 mm from the reference point in +x; a corner points at the spindle (the reference point).
    write_ascii("turret.stl", prism(140, 0, 140, 12, -35, 35, math.pi))
    # Live tool holder: the driven block that carries a live drill's collet (drill along +z of
    # the holder's frame, the collet face at z = 0).
    write_binary("live-holder.stl", box(-25, 25, -25, 25, 0, 60))
    # Sub-spindle housing: behind the sub chuck, whose back face is at z = 830 at B = 0.
    write_binary("sub-headstock.stl", box(-200, 100, -200, 200, 830, 1100))


if __name__ == "__main__":
    main()
