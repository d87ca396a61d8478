#!/usr/bin/env python3
"""Writes the OBJ meshes of an axisymmetric granular column and its gate.

    python3 benches/scripts/cylinder_obj.py RADIUS HEIGHT OUT_PREFIX [--segments N]

OUT_PREFIX-column.obj is the closed cylinder x^2 + y^2 <= RADIUS^2, 0 <= z <= HEIGHT (outward
normals), the soil block; OUT_PREFIX-gate.obj is the open tube around it, 1.2 HEIGHT tall with
inward normals (facing the soil), the wall that holds the column during the geostatic stage
and is released. The polygon is circumscribed about the circle (its edges touch it at their
midpoints) so the lattice sites inside the circle are inside the tube too.
"""
import argparse
import math


def ring(radius, z, segments):
    # Circumscribed: vertices at radius / cos(pi / n).
    r = radius / math.cos(math.pi / segments)
    return [(r * math.cos(2 * math.pi * k / segments), r * math.sin(2 * math.pi * k / segments), z)
            for k in range(segments)]


def write(path, vertices, faces, comment):
    with open(path, "w") as out:
        out.write(f"# {comment}\n")
        for x, y, z in vertices:
            out.write(f"v {x:.9f} {y:.9f} {z:.9f}\n")
        for a, b, c in faces:
            out.write(f"f {a + 1} {b + 1} {c + 1}\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("radius", type=float)
    parser.add_argument("height", type=float)
    parser.add_argument("prefix")
    parser.add_argument("--segments", type=int, default=96)
    args = parser.parse_args()
    n, r, h = args.segments, args.radius, args.height

    # The column: bottom ring, top ring and the two cap centres; outward normals
    # (counter-clockwise seen from outside).
    vertices = ring(r, 0.0, n) + ring(r, h, n) + [(0.0, 0.0, 0.0), (0.0, 0.0, h)]
    bottom, top = 2 * n, 2 * n + 1
    faces = []
    for k in range(n):
        a, b = k, (k + 1) % n
        faces += [(a, b, n + b), (a, n + b, n + a)]
        faces.append((bottom, b, a))
        faces.append((top, n + a, n + b))
    write(f"{args.prefix}-column.obj", vertices, faces,
          f"granular column: cylinder r = {r} m, h = {h} m, {n} segments, outward normals")

    # The gate: an open tube, inward normals.
    tall = 1.2 * h
    vertices = ring(r, 0.0, n) + ring(r, tall, n)
    faces = []
    for k in range(n):
        a, b = k, (k + 1) % n
        faces += [(a, n + b, b), (a, n + a, n + b)]
    write(f"{args.prefix}-gate.obj", vertices, faces,
          f"gate of the granular column: open tube r = {r} m, {tall} m tall, inward normals")


if __name__ == "__main__":
    main()
