#!/usr/bin/env python3
"""Writes scenes/glass.obj, the glass of scenes/glass.json: a closed, outward-
oriented triangle mesh of an open-top cup (a solid of revolution, so the fluid
sits in its cavity). Deterministic; run from anywhere:

    python3 scenes/make_glass.py

Dimensions in metres: outer radius 0.08, inner radius 0.065 (walls 0.015
thick), height 0.2, base 0.02 thick; 32 segments around. The cup stands on
y = 0 centred on the y axis.
"""
import math
import os

R_OUT, R_IN, HEIGHT, BASE, SEGMENTS = 0.08, 0.065, 0.2, 0.02, 32

# The profile (radius, height) from the centre of the underside, up the outside,
# over the rim, down the inside to the centre of the inner floor. Its ends are
# on the axis (poles); the rings between are revolved.
RINGS = [(R_OUT, 0.0), (R_OUT, HEIGHT), (R_IN, HEIGHT), (R_IN, BASE)]
POLES = [(0.0, 0.0), (0.0, BASE)]


def mesh():
    verts = [(0.0, POLES[0][1], 0.0)]
    for r, y in RINGS:
        for k in range(SEGMENTS):
            a = 2.0 * math.pi * k / SEGMENTS
            verts.append((r * math.cos(a), y, r * math.sin(a)))
    verts.append((0.0, POLES[1][1], 0.0))
    first, last = 0, len(verts) - 1

    def ring(j, k):  # vertex index of ring j, segment k (wrapping)
        return 1 + j * SEGMENTS + k % SEGMENTS

    tris = []
    for k in range(SEGMENTS):
        tris.append((first, ring(0, k + 1), ring(0, k)))
        for j in range(len(RINGS) - 1):
            a0, a1, b0, b1 = ring(j, k), ring(j, k + 1), ring(j + 1, k), ring(j + 1, k + 1)
            tris.append((a0, a1, b1))
            tris.append((a0, b1, b0))
        tris.append((ring(len(RINGS) - 1, k), ring(len(RINGS) - 1, k + 1), last))
    return verts, tris


def signed_volume(verts, tris):
    v = 0.0
    for a, b, c in tris:
        (ax, ay, az), (bx, by, bz), (cx, cy, cz) = verts[a], verts[b], verts[c]
        v += (ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)) / 6.0
    return v


def main():
    verts, tris = mesh()
    if signed_volume(verts, tris) < 0:  # make the normals point out of the solid
        tris = [(a, c, b) for a, b, c in tris]
    assert signed_volume(verts, tris) > 0
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "glass.obj")
    with open(path, "w") as f:
        f.write("# Open-top glass for scenes/glass.json, written by scenes/make_glass.py.\n")
        f.write("# Closed and outward-oriented; metres; outer radius %g, inner %g, height %g, base %g.\n"
                % (R_OUT, R_IN, HEIGHT, BASE))
        for x, y, z in verts:
            f.write("v %.6f %.6f %.6f\n" % (x, y, z))
        for a, b, c in tris:
            f.write("f %d %d %d\n" % (a + 1, b + 1, c + 1))
    print("%s: %d vertices, %d triangles, volume %.6g m^3" % (path, len(verts), len(tris), signed_volume(verts, tris)))


if __name__ == "__main__":
    main()
