#!/usr/bin/env python3
"""Procedural closed meshes for the translucent-object experiments (`make subsurface`), since the
repository ships none: written as OBJ with shared vertices (closed, consistently oriented, outward
counter-clockwise faces), deterministic.

  bumpy-sphere  a cube-sphere of radius R with smooth radial bumps: 6 n^2 quads, 12 n^2 triangles
                (n = 150: 270,000 triangles)
  torus-knot    a (2, 3) torus knot tube: segments x sides x 2 triangles (1000 x 128: 256,000)

Usage: scripts/make_meshes.py bumpy-sphere OUT.obj [--n 150] [--radius 20]
       scripts/make_meshes.py torus-knot OUT.obj [--segments 1000] [--sides 128] [--radius 12]
Lengths are in the unit of the material's coefficients (Jensen et al. 2001's are per mm).
"""
import argparse
import math


def normalised(v):
    n = math.sqrt(sum(c * c for c in v))
    return [c / n for c in v]


def bumps(d):
    """A smooth, deterministic relief on the unit sphere in [-1, 1]."""
    x, y, z = d
    return (math.sin(5 * x + 1.3) * math.sin(4 * y + 0.7) * math.sin(6 * z + 2.1)
            + 0.5 * math.sin(11 * x - 3 * z) * math.cos(9 * y + 2 * x)) / 1.5


def bumpy_sphere(n, radius):
    """The six faces of a cube, each an n x n grid, projected on the sphere and displaced radially."""
    index = {}
    vertices, faces = [], []

    def vertex(p):
        key = tuple(round(c, 9) for c in p)  # cube-edge points shared by two faces
        if key not in index:
            d = normalised(p)
            r = radius * (1 + 0.06 * bumps(d))
            index[key] = len(vertices) + 1
            vertices.append([r * c for c in d])
        return index[key]

    # (axis, sign): the face's normal; u, v span it so that u x v points outward.
    for axis in range(3):
        for sign in (1, -1):
            u_axis, v_axis = (axis + 1) % 3, (axis + 2) % 3
            if sign < 0:
                u_axis, v_axis = v_axis, u_axis
            grid = []
            for i in range(n + 1):
                row = []
                for j in range(n + 1):
                    p = [0.0, 0.0, 0.0]
                    p[axis] = sign
                    p[u_axis] = -1 + 2 * i / n
                    p[v_axis] = -1 + 2 * j / n
                    row.append(vertex(p))
                grid.append(row)
            for i in range(n):
                for j in range(n):
                    a, b, c, d = grid[i][j], grid[i + 1][j], grid[i + 1][j + 1], grid[i][j + 1]
                    faces += [(a, b, c), (a, c, d)]
    return vertices, faces


def torus_knot(segments, sides, radius):
    """A tube of radius 0.28 R around the (2, 3) torus knot of size R, with a rotation-minimising frame."""
    def curve(t):
        r = radius * (0.6 + 0.3 * math.cos(3 * t))
        return [r * math.cos(2 * t), r * math.sin(2 * t), radius * 0.3 * math.sin(3 * t)]

    centres = [curve(2 * math.pi * k / segments) for k in range(segments)]
    tangents = [normalised([centres[(k + 1) % segments][a] - centres[k - 1][a] for a in range(3)]) for k in range(segments)]
    vertices, faces = [], []
    tube = 0.28 * radius * 0.45
    for k in range(segments):
        t = tangents[k]
        helper = [0, 0, 1] if abs(t[2]) < 0.9 else [1, 0, 0]
        n = normalised([t[1] * helper[2] - t[2] * helper[1], t[2] * helper[0] - t[0] * helper[2],
                        t[0] * helper[1] - t[1] * helper[0]])
        b = [t[1] * n[2] - t[2] * n[1], t[2] * n[0] - t[0] * n[2], t[0] * n[1] - t[1] * n[0]]
        for s in range(sides):
            phi = 2 * math.pi * s / sides
            vertices.append([centres[k][a] + tube * (math.cos(phi) * n[a] + math.sin(phi) * b[a]) for a in range(3)])
    for k in range(segments):
        for s in range(sides):
            a = k * sides + s + 1
            b = k * sides + (s + 1) % sides + 1
            c = ((k + 1) % segments) * sides + (s + 1) % sides + 1
            d = ((k + 1) % segments) * sides + s + 1
            faces += [(a, d, c), (a, c, b)]
    return vertices, faces


def write_obj(path, vertices, faces):
    with open(path, "w") as f:
        f.write("".join(f"v {x:.9g} {y:.9g} {z:.9g}\n" for x, y, z in vertices))
        f.write("".join(f"f {a} {b} {c}\n" for a, b, c in faces))


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("kind", choices=["bumpy-sphere", "torus-knot"])
    p.add_argument("out")
    p.add_argument("--n", type=int, default=150)
    p.add_argument("--radius", type=float, default=None)
    p.add_argument("--segments", type=int, default=1000)
    p.add_argument("--sides", type=int, default=128)
    args = p.parse_args()
    if args.kind == "bumpy-sphere":
        vertices, faces = bumpy_sphere(args.n, args.radius or 20.0)
    else:
        vertices, faces = torus_knot(args.segments, args.sides, args.radius or 12.0)
    write_obj(args.out, vertices, faces)
    print(f"{args.out}: {len(vertices)} vertices, {len(faces)} triangles")


main()
