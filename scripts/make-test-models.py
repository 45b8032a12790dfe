#!/usr/bin/env python3
"""Writes the low-poly test models of tests/gpu/test_fidelity.cpp into tests/models/ (OBJ, outward windings):

  spider.obj      a body (a low-poly ellipsoid) and eight long thin legs, each a square tube through hip, knee
                  and foot: every leg face is a long, skinny triangle, with no vertex along its length
  hemisphere.obj  an open surface: half a UV sphere, open at its rim
  parts.obj       three separate closed parts: a box, a UV sphere and a torus

Deterministic (no randomness): running it again gives the same bytes. Usage: scripts/make-test-models.py
"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "tests", "models")


class Mesh:
    def __init__(self):
        self.v = []
        self.f = []

    def vertex(self, p):
        self.v.append(tuple(p))
        return len(self.v) - 1

    def face(self, *idx):
        self.f.append(idx)

    def write(self, path, comment):
        with open(path, "w") as out:
            out.write("# " + comment + "\n# Written by scripts/make-test-models.py\n")
            for p in self.v:
                out.write("v %.6f %.6f %.6f\n" % p)
            for f in self.f:
                out.write("f " + " ".join(str(i + 1) for i in f) + "\n")


def add(a, b):
    return tuple(x + y for x, y in zip(a, b))


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def scale(a, s):
    return tuple(x * s for x in a)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def normalize(a):
    n = math.sqrt(sum(x * x for x in a))
    return scale(a, 1 / n)


def uv_sphere(mesh, centre, radii, segments, rings, upper_only=False):
    """A UV sphere (or its upper half, open at the equator), outward."""
    last = rings // 2 if upper_only else rings
    top = mesh.vertex(add(centre, (0, radii[1], 0)))
    grid = []
    for r in range(1, last + 1 if upper_only else rings):
        theta = math.pi * r / rings
        row = []
        for s in range(segments):
            phi = 2 * math.pi * s / segments
            p = (radii[0] * math.sin(theta) * math.cos(phi), radii[1] * math.cos(theta),
                 radii[2] * math.sin(theta) * math.sin(phi))
            row.append(mesh.vertex(add(centre, p)))
        grid.append(row)
    for s in range(segments):
        t = (s + 1) % segments
        mesh.face(top, grid[0][t], grid[0][s])
    for r in range(len(grid) - 1):
        for s in range(segments):
            t = (s + 1) % segments
            mesh.face(grid[r][s], grid[r][t], grid[r + 1][t], grid[r + 1][s])
    if not upper_only:
        bottom = mesh.vertex(add(centre, (0, -radii[1], 0)))
        for s in range(segments):
            t = (s + 1) % segments
            mesh.face(bottom, grid[-1][s], grid[-1][t])


def tube(mesh, path, width):
    """A square tube of side `width` along the polyline `path`, open at its first end (inside the body), capped
    at the last; every side a quad (two long thin triangles) from one joint to the next."""
    rings = []
    for i, p in enumerate(path):
        ahead = normalize(sub(path[min(i + 1, len(path) - 1)], path[max(i - 1, 0)]))
        side = normalize(cross(ahead, (0, 1, 0)))
        up = cross(side, ahead)
        h = width / 2
        rings.append([mesh.vertex(add(p, add(scale(side, a * h), scale(up, b * h))))
                      for a, b in ((1, 1), (-1, 1), (-1, -1), (1, -1))])
    for r in range(len(rings) - 1):
        for k in range(4):
            j = (k + 1) % 4
            mesh.face(rings[r][k], rings[r + 1][k], rings[r + 1][j], rings[r][j])
    end = rings[-1]
    mesh.face(end[3], end[2], end[1], end[0])


def spider():
    m = Mesh()
    body = (0.36, 0.22, 0.28)
    uv_sphere(m, (0, 0, 0), body, 10, 6)
    for side in (1, -1):
        for k in range(4):
            a = math.radians(-50 + k * 33)  # spread from front to back
            out = (side * math.cos(a), 0, math.sin(a))
            # The hip just inside the body's surface (open end hidden there), the knee up and out, the foot down.
            hip = (out[0] * body[0] * 0.9, 0.02, out[2] * body[2] * 0.9)
            knee = add(scale(out, 0.75), (0, 0.35, 0))
            foot = add(scale(out, 1.45), (0, -0.45, 0))
            tube(m, [hip, knee, foot], 0.04)
    return m


def hemisphere():
    m = Mesh()
    uv_sphere(m, (0, 0, 0), (1, 1, 1), 16, 8, upper_only=True)
    return m


def parts():
    m = Mesh()
    # A box.
    c = [m.vertex((x * 0.8 - 1.6, y * 0.5 - 0.25, z * 0.6 - 0.3)) for x in (0, 1) for y in (0, 1) for z in (0, 1)]
    for q in ((0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)):
        m.face(*(c[i] for i in q))
    uv_sphere(m, (0, 0, 0), (0.4, 0.4, 0.4), 12, 8)
    # A torus about y, outward.
    R, r, nu, nv = 0.45, 0.15, 16, 8
    ring = [[m.vertex((1.4 + (R + r * math.cos(2 * math.pi * j / nv)) * math.cos(2 * math.pi * i / nu),
                       r * math.sin(2 * math.pi * j / nv),
                       (R + r * math.cos(2 * math.pi * j / nv)) * math.sin(2 * math.pi * i / nu)))
             for j in range(nv)] for i in range(nu)]
    for i in range(nu):
        for j in range(nv):
            a, b = (i + 1) % nu, (j + 1) % nv
            m.face(ring[i][j], ring[i][b], ring[a][b], ring[a][j])
    return m


if __name__ == "__main__":
    os.makedirs(OUT, exist_ok=True)
    spider().write(os.path.join(OUT, "spider.obj"), "A low-poly spider: a body and eight thin legs of long, skinny triangles")
    hemisphere().write(os.path.join(OUT, "hemisphere.obj"), "An open surface: half a UV sphere")
    parts().write(os.path.join(OUT, "parts.obj"), "Three separate parts: a box, a sphere and a torus")
