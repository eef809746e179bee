#!/usr/bin/env python3
"""Writes the project's own glTF 2.0 models into scenes/models/ (CC0, made here): a small
sailing boat with a mast, a pier on piles, a buoy, and a ship. Standard library only; the output
is deterministic, so running it again leaves the committed files unchanged.

Each model is metres, +y up (glTF's convention), its waterline at y = 0 where it floats or
stands in the sea, its bow towards +x. Run from the repository root: python3 scripts/make_models.py
"""

import json
import math
import struct
from pathlib import Path

OUT = Path(__file__).resolve().parent.parent / "scenes" / "models"


class Builder:
    """Triangles grouped by material, written as one glTF with one .bin buffer."""

    def __init__(self):
        self.materials = []  # (name, rgba, metallic, roughness)
        self.parts = {}  # material index -> (positions, normals, indices)

    def material(self, name, rgba, metallic, roughness):
        self.materials.append((name, rgba, metallic, roughness))
        return len(self.materials) - 1

    def _part(self, m):
        return self.parts.setdefault(m, ([], [], []))

    def triangle(self, m, a, b, c):
        """A flat triangle, counter-clockwise seen from its front."""
        pos, nor, idx = self._part(m)
        n = normalize(cross(sub(b, a), sub(c, a)))
        base = len(pos)
        pos.extend([a, b, c])
        nor.extend([n, n, n])
        idx.extend([base, base + 1, base + 2])

    def quad(self, m, a, b, c, d):
        self.triangle(m, a, b, c)
        self.triangle(m, a, c, d)

    def grid(self, m, rows, close_u=False):
        """A smooth surface through rows[i][j] (i along v, j along u), normals averaged from the
        faces around each vertex; `close_u` joins the last column to the first."""
        pos, nor, idx = self._part(m)
        nv, nu = len(rows), len(rows[0])
        cols = nu if close_u else nu - 1
        acc = [[(0.0, 0.0, 0.0) for _ in range(nu)] for _ in range(nv)]
        faces = []
        for i in range(nv - 1):
            for j in range(cols):
                k = (j + 1) % nu
                quad = [(i, j), (i, k), (i + 1, k), (i + 1, j)]
                p = [rows[a][b] for a, b in quad]
                n = cross(sub(p[2], p[0]), sub(p[3], p[1]))
                for a, b in quad:
                    acc[a][b] = add(acc[a][b], n)
                faces.append(quad)
        base = len(pos)
        for i in range(nv):
            for j in range(nu):
                pos.append(rows[i][j])
                nor.append(normalize(acc[i][j]))
        at = lambda q: base + q[0] * nu + q[1]
        for quad in faces:
            a, b, c, d = (at(q) for q in quad)
            idx.extend([a, b, c, a, c, d])

    def box(self, m, lo, hi):
        x0, y0, z0 = lo
        x1, y1, z1 = hi
        v = lambda x, y, z: (x, y, z)
        self.quad(m, v(x1, y0, z0), v(x1, y1, z0), v(x1, y1, z1), v(x1, y0, z1))  # +x
        self.quad(m, v(x0, y0, z1), v(x0, y1, z1), v(x0, y1, z0), v(x0, y0, z0))  # -x
        self.quad(m, v(x0, y1, z0), v(x0, y1, z1), v(x1, y1, z1), v(x1, y1, z0))  # +y
        self.quad(m, v(x0, y0, z1), v(x0, y0, z0), v(x1, y0, z0), v(x1, y0, z1))  # -y
        self.quad(m, v(x0, y0, z1), v(x1, y0, z1), v(x1, y1, z1), v(x0, y1, z1))  # +z
        self.quad(m, v(x1, y0, z0), v(x0, y0, z0), v(x0, y1, z0), v(x1, y1, z0))  # -z

    def cylinder(self, m, base, top, r0, r1, sides=16, caps=True):
        """A (truncated) cone from `base` (radius r0) to `top` (radius r1), smooth sides."""
        axis = normalize(sub(top, base))
        u = normalize(cross(axis, (0.0, 0.0, 1.0) if abs(axis[2]) < 0.9 else (1.0, 0.0, 0.0)))
        w = cross(axis, u)
        ring = lambda c, r: [add(c, add(scale(u, r * math.cos(t)), scale(w, r * math.sin(t)))) for t in angles(sides)]
        lower, upper = ring(base, r0), ring(top, r1)
        self.grid(m, [lower, upper], close_u=True)
        if caps:
            for k in range(sides):
                n = (k + 1) % sides
                if r0 > 0:
                    self.triangle(m, base, lower[n], lower[k])
                if r1 > 0:
                    self.triangle(m, top, upper[k], upper[n])

    def write(self, name):
        bin_ = bytearray()
        views, accessors, primitives = [], [], []

        def view(data, target):
            while len(bin_) % 4:
                bin_.append(0)
            views.append({"buffer": 0, "byteOffset": len(bin_), "byteLength": len(data), "target": target})
            bin_.extend(data)
            return len(views) - 1

        for m in sorted(self.parts):
            pos, nor, idx = self.parts[m]
            lo = [min(p[k] for p in pos) for k in range(3)]
            hi = [max(p[k] for p in pos) for k in range(3)]
            p_view = view(b"".join(struct.pack("<3f", *p) for p in pos), 34962)
            accessors.append({"bufferView": p_view, "componentType": 5126, "count": len(pos), "type": "VEC3",
                              "min": lo, "max": hi})
            n_view = view(b"".join(struct.pack("<3f", *n) for n in nor), 34962)
            accessors.append({"bufferView": n_view, "componentType": 5126, "count": len(nor), "type": "VEC3"})
            i_view = view(b"".join(struct.pack("<I", i) for i in idx), 34963)
            accessors.append({"bufferView": i_view, "componentType": 5125, "count": len(idx), "type": "SCALAR"})
            a = len(accessors)
            primitives.append({"attributes": {"POSITION": a - 3, "NORMAL": a - 2}, "indices": a - 1, "material": m})
        document = {
            "asset": {"version": "2.0", "generator": "scripts/make_models.py (ocean)", "copyright": "CC0"},
            "scene": 0,
            "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0, "name": name}],
            "meshes": [{"name": name, "primitives": primitives}],
            "materials": [
                {"name": n, "pbrMetallicRoughness": {"baseColorFactor": list(rgba), "metallicFactor": metal,
                                                     "roughnessFactor": rough}}
                for n, rgba, metal, rough in self.materials
            ],
            "buffers": [{"uri": f"{name}.bin", "byteLength": len(bin_)}],
            "bufferViews": views,
            "accessors": accessors,
        }
        OUT.mkdir(parents=True, exist_ok=True)
        (OUT / f"{name}.bin").write_bytes(bytes(bin_))
        (OUT / f"{name}.gltf").write_text(json.dumps(document, indent=1) + "\n")
        triangles = sum(len(p[2]) for p in self.parts.values()) // 3
        print(f"{name}: {triangles} triangles, {len(bin_)} bytes")


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def scale(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def normalize(a):
    n = math.sqrt(a[0] ** 2 + a[1] ** 2 + a[2] ** 2)
    return (a[0] / n, a[1] / n, a[2] / n) if n > 0 else (0.0, 1.0, 0.0)


def angles(n):
    return [2.0 * math.pi * k / n for k in range(n)]


def hull(b, m, length, beam, depth, freeboard, stations=16, points=9, bluff=0.25):
    """A hull from its stations: each a U from the keel (depth below the waterline) up to the
    sheer line (freeboard above it), narrowing to the bow (+x) and less to the stern."""
    rows = []
    for i in range(stations + 1):
        s = i / stations  # 0 stern, 1 bow
        x = (s - 0.5) * length
        half = 0.5 * beam * (math.sin(math.pi * min(1.0, s * (1.0 - bluff) + bluff)) ** 0.6)
        half = max(half, 0.02 * beam)
        keel = depth * (math.sin(math.pi * min(1.0, 0.15 + 0.85 * s)) ** 0.5)
        row = []
        for j in range(points):
            a = math.pi * j / (points - 1)  # port sheer, keel, starboard sheer
            y = freeboard if j in (0, points - 1) else -keel * math.sin(a) + freeboard * (1 - math.sin(a)) ** 3
            z = half * math.cos(a)
            row.append((x, y, z))
        rows.append(row)
    b.grid(m, rows)
    # The transom closes the stern, a sliver the bow: fans facing aft and forward.
    for row, facing in ((rows[0], -1.0), (rows[-1], 1.0)):
        centre = scale(row[0], 0.0)
        for p in row:
            centre = add(centre, scale(p, 1.0 / len(row)))
        for j in range(points - 1):
            a, c = row[j], row[j + 1]
            if cross(sub(c, a), sub(centre, a))[0] * facing > 0:
                b.triangle(m, a, c, centre)
            else:
                b.triangle(m, c, a, centre)
    # The deck closes the sheer line.
    for i in range(stations):
        p, q = rows[i], rows[i + 1]
        b.quad(m, p[0], q[0], q[-1], p[-1])


def boat():
    b = Builder()
    paint = b.material("hull paint", (0.85, 0.86, 0.88, 1.0), 0.0, 0.35)
    wood = b.material("teak deck", (0.36, 0.22, 0.12, 1.0), 0.0, 0.7)
    metal = b.material("aluminium", (0.91, 0.92, 0.92, 1.0), 1.0, 0.3)
    hull(b, paint, length=6.0, beam=2.2, depth=0.9, freeboard=0.7)
    b.box(wood, (-1.2, 0.7, -0.6), (0.6, 1.25, 0.6))  # cabin
    b.cylinder(metal, (0.4, 0.7, 0.0), (0.4, 9.0, 0.0), 0.07, 0.05, sides=12)  # mast
    b.cylinder(metal, (0.4, 1.7, 0.0), (-2.4, 1.7, 0.0), 0.05, 0.05, sides=10)  # boom
    b.write("boat")


def pier():
    b = Builder()
    boards = b.material("weathered planks", (0.42, 0.36, 0.29, 1.0), 0.0, 0.85)
    piles = b.material("tarred piles", (0.10, 0.08, 0.07, 1.0), 0.0, 0.6)
    b.box(boards, (0.0, 1.8, -1.5), (30.0, 2.0, 1.5))
    for k in range(11):
        x = 0.3 + 2.94 * k
        for z in (-1.3, 1.3):
            b.cylinder(piles, (x, -5.0, z), (x, 1.8, z), 0.15, 0.15, sides=12)
            b.cylinder(piles, (x, 2.0, z), (x, 3.0, z), 0.06, 0.06, sides=8)  # railing posts
    for z in (-1.3, 1.3):
        b.box(boards, (0.2, 2.9, z - 0.05), (29.8, 3.0, z + 0.05))  # rails
    b.write("pier")


def buoy():
    b = Builder()
    red = b.material("red paint", (0.70, 0.06, 0.05, 1.0), 0.0, 0.45)
    white = b.material("white paint", (0.85, 0.85, 0.82, 1.0), 0.0, 0.45)
    steel = b.material("steel", (0.56, 0.57, 0.58, 1.0), 1.0, 0.4)
    b.cylinder(red, (0.0, -0.6, 0.0), (0.0, 0.3, 0.0), 0.5, 0.5, sides=24)
    b.cylinder(white, (0.0, 0.3, 0.0), (0.0, 0.6, 0.0), 0.5, 0.42, sides=24)
    b.cylinder(red, (0.0, 0.6, 0.0), (0.0, 1.5, 0.0), 0.3, 0.0, sides=24)
    b.cylinder(steel, (0.0, 1.5, 0.0), (0.0, 1.8, 0.0), 0.03, 0.03, sides=8)
    b.write("buoy")


def ship():
    b = Builder()
    hull_paint = b.material("hull paint", (0.08, 0.10, 0.14, 1.0), 0.0, 0.4)
    white = b.material("superstructure", (0.86, 0.86, 0.84, 1.0), 0.0, 0.5)
    funnel = b.material("funnel", (0.75, 0.35, 0.08, 1.0), 0.0, 0.4)
    hull(b, hull_paint, length=120.0, beam=18.0, depth=7.0, freeboard=6.0, stations=24, points=11, bluff=0.45)
    b.box(white, (-55.0, 6.0, -7.0), (-35.0, 16.0, 7.0))
    b.box(white, (-52.0, 16.0, -5.0), (-40.0, 20.0, 5.0))
    b.cylinder(funnel, (-45.0, 20.0, 0.0), (-46.0, 27.0, 0.0), 2.0, 1.8, sides=16)
    for k in range(6):
        x = -25.0 + 12.0 * k
        b.box(funnel if k % 2 else white, (x, 6.0, -6.0), (x + 10.0, 8.5, 6.0))  # containers
    b.write("ship")


if __name__ == "__main__":
    boat()
    pier()
    buoy()
    ship()
