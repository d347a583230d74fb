#!/usr/bin/env python3
"""Writes Penumbra's bundled test scenes (scenes/**/*.json, DESIGN.md section 4) reproducibly.

    python3 scripts/make-bundled-scenes.py [--check]

Every scene is built from closed convex solids (boxes and vertical prisms) so that the checks in
tests/scene/bundled_scenes_json_test.cpp hold by construction:
  * the room shell (the objects named "room" or "room-*") is closed, faces inward and has no
    T-junctions: it is one box, possibly cut into a few coplanar-free pieces whose edges match;
  * every other object is a union of closed convex solids with outward counter-clockwise faces;
    distinct solids never share a vertex (they may touch along faces: legs on floors, books on
    boards), because the tests recover the solids as vertex-connected components;
  * nothing interpenetrates at any keyframe or between keyframes (motion is translation only, so
    the swept volume is exact), nothing touches the light, the light faces into the room;
  * polygon counts are exact: a filler (books, plus one jar prism for the remainder modulo 6)
    tops each scene up to its target instead of subdividing walls.

The output depends only on this file (fixed seeds, fixed rounding), so re-running it reproduces
the committed scenes byte for byte; --check verifies that instead of writing.
"""

import math
import os
import random
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# ---------------------------------------------------------------------------------------------
# Small vector helpers (tuples of floats).


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def newell(poly):
    n = [0.0, 0.0, 0.0]
    for i, p in enumerate(poly):
        q = poly[(i + 1) % len(poly)]
        n[0] += (p[1] - q[1]) * (p[2] + q[2])
        n[1] += (p[2] - q[2]) * (p[0] + q[0])
        n[2] += (p[0] - q[0]) * (p[1] + q[1])
    return tuple(n)


def average(points):
    k = len(points)
    return (sum(p[0] for p in points) / k, sum(p[1] for p in points) / k,
            sum(p[2] for p in points) / k)


def oriented(poly, outward):
    """The loop, reversed if needed so that its right-hand normal points along `outward`."""
    return list(poly) if dot(newell(poly), outward) > 0 else list(reversed(poly))


# ---------------------------------------------------------------------------------------------
# Solids: lists of polygons (lists of (x, y, z)), closed, convex, faces counter-clockwise from
# outside.


def convex_solid(faces):
    """Orients every face of a convex solid outward (away from the vertex average)."""
    centre = average([p for f in faces for p in f])
    return [oriented(f, sub(average(f), centre)) for f in faces]


def prism(base_xz, y0, y1):
    """A vertical prism over a convex (x, z) loop, from height y0 to y1."""
    bottom = [(x, y0, z) for x, z in base_xz]
    top = [(x, y1, z) for x, z in base_xz]
    sides = []
    k = len(base_xz)
    for i in range(k):
        (xa, za), (xb, zb) = base_xz[i], base_xz[(i + 1) % k]
        sides.append([(xa, y0, za), (xb, y0, zb), (xb, y1, zb), (xa, y1, za)])
    return convex_solid([bottom, top] + sides)


def box(x0, y0, z0, x1, y1, z1):
    assert x0 < x1 and y0 < y1 and z0 < z1, (x0, y0, z0, x1, y1, z1)
    return prism([(x0, z0), (x1, z0), (x1, z1), (x0, z1)], y0, y1)


def ngon_prism(cx, cz, radius, sides, y0, y1, phase=0.0):
    """A regular `sides`-gon prism (round things: bins, jars, lamp shades, table tops)."""
    base = [(cx + radius * math.cos(phase + 2 * math.pi * i / sides),
             cz + radius * math.sin(phase + 2 * math.pi * i / sides)) for i in range(sides)]
    return prism(base, y0, y1)


def room_faces(x0, y0, z0, x1, y1, z1):
    """The six inward-facing faces of a room, by name."""
    centre = ((x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2)
    quads = {
        "floor": [(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)],
        "ceiling": [(x0, y1, z0), (x1, y1, z0), (x1, y1, z1), (x0, y1, z1)],
        "x0": [(x0, y0, z0), (x0, y1, z0), (x0, y1, z1), (x0, y0, z1)],
        "x1": [(x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1)],
        "z0": [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0)],
        "z1": [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)],
    }
    return {k: oriented(q, sub(centre, average(q))) for k, q in quads.items()}


def ceiling_light(cx, cz, size, ceiling_y, gap=0.01):
    """A square emitter `gap` below the ceiling, facing down into the room."""
    h = size / 2
    y = ceiling_y - gap
    quad = [(cx - h, y, cz - h), (cx + h, y, cz - h), (cx + h, y, cz + h), (cx - h, y, cz + h)]
    return oriented(quad, (0, -1, 0))


def rotate_y(p, degrees):
    """Rotation about +y by the right-hand rule (as the loader's axis-angle rotation)."""
    a = math.radians(degrees)
    c, s = math.cos(a), math.sin(a)
    return (c * p[0] + s * p[2], p[1], -s * p[0] + c * p[2])


# ---------------------------------------------------------------------------------------------
# Scene assembly and output.


class Scene:

    def __init__(self, name):
        self.name = name
        self.materials = {}
        self.objects = []
        self.camera = None
        self.frames = None

    def material(self, name, reflectance, emission=None, mirror=False):
        assert all(0 <= r < 1 for r in reflectance)
        self.materials[name] = (reflectance, emission, mirror)

    def add(self, name, material, solids, motion=None, transform=None):
        """solids: a list of solids (each a list of polygons) in object coordinates.
        motion: list of (frame, (tx, ty, tz)) keyframes. transform: (translate, y-degrees)."""
        assert material in self.materials, material
        assert all(o["name"] != name for o in self.objects), name
        self.objects.append({"name": name, "material": material, "solids": solids,
                             "motion": motion, "transform": transform})

    def polygon_count(self):
        return sum(len(s) for o in self.objects for s in o["solids"])

    # World-space solids of an object for a translation (used by the self-checks below).
    def world_solids(self, obj, translate=(0, 0, 0)):
        out = []
        for solid in obj["solids"]:
            faces = []
            for f in solid:
                pts = f
                if obj["transform"] is not None and obj["motion"] is None:
                    t, deg = obj["transform"]
                    pts = [add(rotate_y(p, deg), t) for p in pts]
                faces.append([add(p, translate) for p in pts])
            out.append(faces)
        return out

    def to_json(self):
        lines = ["{", '  "penumbra": 1,']
        if self.frames is not None:
            lines.append('  "frames": %d,' % self.frames)
        lines.append('  "materials": {')
        mats = []
        for name, (refl, emis, mirror) in self.materials.items():
            text = '    "%s": { "reflectance": %s' % (name, vec(refl))
            if emis is not None:
                text += ', "emission": %s' % vec(emis)
            if mirror:
                text += ', "mirror": true'
            mats.append(text + " }")
        lines.append(",\n".join(mats))
        lines.append("  },")
        lines.append('  "objects": [')
        objs = []
        for o in self.objects:
            head = '    { "name": "%s", "material": "%s",' % (o["name"], o["material"])
            parts = [head]
            if o["transform"] is not None:
                t, deg = o["transform"]
                parts.append('      "transform": { "translate": %s, "rotate": { "axis": [0, 1, 0], '
                             '"degrees": %s } },' % (vec(t), num(deg)))
            if o["motion"] is not None:
                keys = ['        { "frame": %d, "translate": %s }' % (f, vec(t))
                        for f, t in o["motion"]]
                parts.append('      "motion": [\n' + ",\n".join(keys) + "\n      ],")
            polys = ["        [" + ", ".join(vec(p) for p in poly) + "]"
                     for solid in o["solids"] for poly in solid]
            parts.append('      "polygons": [\n' + ",\n".join(polys) + "\n      ] }")
            objs.append("\n".join(parts))
        lines.append(",\n".join(objs))
        lines.append("  ],")
        c = self.camera
        lines.append('  "camera": { "eye": %s, "target": %s, "up": [0, 1, 0], "fov_y_degrees": %s,'
                     % (vec(c["eye"]), vec(c["target"]), num(c["fov"])))
        lines.append('              "width": %d, "height": %d }' % (c["width"], c["height"]))
        lines.append("}")
        return "\n".join(lines) + "\n"


def num(v):
    v = round(v, 6)
    if v == 0:
        v = 0.0  # no "-0"
    text = repr(v)
    return text[:-2] if text.endswith(".0") else text


def vec(v):
    return "[" + ", ".join(num(c) for c in v) + "]"


# ---------------------------------------------------------------------------------------------
# Self-checks (the C++ test is the authority; these catch layout mistakes while editing).


def aabb(points):
    xs, ys, zs = zip(*points)
    return (min(xs), min(ys), min(zs)), (max(xs), max(ys), max(zs))


def swept_interiors_meet(a, b, d):
    """Whether box a translated by s*d, s in [0, 1], ever shares interior with box b (exact)."""
    lo, hi = 0.0, 1.0
    eps = 1e-9
    for k in range(3):
        # Overlap on axis k: a.min + s d > b.min - a.len ... written as b.min - a.max < s d < b.max - a.min
        l, h = b[0][k] - a[1][k] + eps, b[1][k] - a[0][k] - eps
        if abs(d[k]) < 1e-15:
            if not (l < 0 < h):
                return False
            continue
        s0, s1 = l / d[k], h / d[k]
        if s0 > s1:
            s0, s1 = s1, s0
        lo, hi = max(lo, s0), min(hi, s1)
        if lo >= hi:
            return False
    return True


def check(scene, exact_count=None, aabb_pairs=True):
    count = scene.polygon_count()
    if exact_count is not None:
        assert count == exact_count, "%s: %d polygons, want %d" % (scene.name, count, exact_count)
    room = [o for o in scene.objects if o["name"] == "room" or o["name"].startswith("room-")]
    room_box = aabb([p for o in room for s in o["solids"] for f in s for p in f])
    movers = [o for o in scene.objects if o["motion"] is not None]
    statics = [o for o in scene.objects if o["motion"] is None and o not in room]
    for mover in movers:
        keys = mover["motion"]
        for (_, t0), (_, t1) in zip(keys, keys[1:] + keys[-1:]):
            d = sub(t1, t0)
            for ms in scene.world_solids(mover, t0):
                mb = aabb([p for f in ms for p in f])
                assert all(room_box[0][k] <= mb[0][k] and mb[1][k] <= room_box[1][k]
                           for k in range(3)), "%s leaves the room" % mover["name"]
                if not aabb_pairs:
                    continue
                for other in statics:
                    for os_ in scene.world_solids(other):
                        ob = aabb([p for f in os_ for p in f])
                        assert not swept_interiors_meet(mb, ob, d), \
                            "%s hits %s after %s" % (mover["name"], other["name"], t0)
    if aabb_pairs:
        solids = [(o["name"], aabb([p for f in s for p in f]))
                  for o in statics for s in scene.world_solids(o)]
        for i in range(len(solids)):
            for j in range(i + 1, len(solids)):
                assert not swept_interiors_meet(solids[i][1], solids[j][1], (0, 0, 0)), \
                    "%s overlaps %s: %s %s" % (solids[i][0], solids[j][0], solids[i][1],
                                               solids[j][1])
    return count


# ---------------------------------------------------------------------------------------------
# Furniture. Every builder returns a list of solids; no two solids share a vertex.

BOARD = 0.02  # shelf board / side thickness


def table(x0, z0, x1, z1, height, top=0.03, leg=0.05, inset=0.02):
    """Top plus four square legs inset from the corners (so no leg shares a top corner)."""
    solids = [box(x0, height - top, z0, x1, height, z1)]
    for lx in (x0 + inset, x1 - inset - leg):
        for lz in (z0 + inset, z1 - inset - leg):
            solids.append(box(lx, 0, lz, lx + leg, height - top, lz + leg))
    return solids


def chair(x0, z0, width=0.44, depth=0.44, seat_y=0.45, back="+z", posts=False, back_h=0.45):
    """A chair whose backrest is on side `back` ("+z", "-z", "+x", "-x") of the seat.
    Plain: seat, 4 legs, back panel (6 solids). posts=True: two posts and a rail (8 solids)."""
    x1, z1 = x0 + width, z0 + depth
    seat_t, leg = 0.04, 0.04
    solids = [box(x0, seat_y - seat_t, z0, x1, seat_y, z1)]
    for lx in (x0 + 0.01, x1 - 0.01 - leg):
        for lz in (z0 + 0.01, z1 - 0.01 - leg):
            solids.append(box(lx, 0, lz, lx + leg, seat_y - seat_t, lz + leg))
    top = seat_y + back_h

    # Back pieces in a frame where "u" runs along the back edge and "w" into the seat from it.
    def piece(u0, u1, w0, w1, y0, y1):
        if back in ("+z", "-z"):
            zs = (z1 - w1, z1 - w0) if back == "+z" else (z0 + w0, z0 + w1)
            return box(x0 + u0, y0, zs[0], x0 + u1, y1, zs[1])
        xs = (x1 - w1, x1 - w0) if back == "+x" else (x0 + w0, x0 + w1)
        return box(xs[0], y0, z0 + u0, xs[1], y1, z0 + u1)

    span = width if back in ("+z", "-z") else depth
    if not posts:
        solids.append(piece(0.01, span - 0.01, 0.005, 0.04, seat_y, top))
    else:
        solids.append(piece(0.01, 0.05, 0.005, 0.045, seat_y, top))
        solids.append(piece(span - 0.05, span - 0.01, 0.005, 0.045, seat_y, top))
        solids.append(piece(0.05, span - 0.05, 0.01, 0.04, top - 0.14, top - 0.02))
    return solids


def shelf_unit(x0, z0, x1, z1, height, boards, along, front):
    """Two sides and `boards` boards (bottom one raised off the floor). `along` is the long axis
    ("x" or "z"); `front` is +1/-1, the direction the open side faces on the short axis.
    Returns (solids, slots): slots are the free spaces above the boards for books."""
    solids, slots = [], []
    ys = [0.06 + i * (height - 0.06 - BOARD) / (boards - 1) for i in range(boards)]
    if along == "z":
        solids.append(box(x0, 0, z0, x1, height, z0 + BOARD))
        solids.append(box(x0, 0, z1 - BOARD, x1, height, z1))
        for y in ys:
            solids.append(box(x0 + 0.005, y, z0 + BOARD, x1 - 0.005, y + BOARD, z1 - BOARD))
        a0, a1 = z0 + BOARD, z1 - BOARD
        c_front = x1 if front > 0 else x0
    else:
        solids.append(box(x0, 0, z0, x0 + BOARD, height, z1))
        solids.append(box(x1 - BOARD, 0, z0, x1, height, z1))
        for y in ys:
            solids.append(box(x0 + BOARD, y, z0 + 0.005, x1 - BOARD, y + BOARD, z1 - 0.005))
        a0, a1 = x0 + BOARD, x1 - BOARD
        c_front = z1 if front > 0 else z0
    depth = (x1 - x0) if along == "z" else (z1 - z0)
    for lower, upper in zip(ys, ys[1:]):
        slots.append({"y": lower + BOARD, "along": along, "a0": a0 + 0.006, "a1": a1 - 0.006,
                      "front": c_front - front * 0.015, "back_dir": -front,
                      "depth": depth - 0.04, "max_h": upper - lower - BOARD - 0.02})
    return solids, slots


def books(rng, slots, polygons):
    """Exactly `polygons` polygons of books (6 each) standing in the slots, left to right; a
    remainder of 1..5 polygons becomes a jar prism with 6 + remainder faces."""
    n_books, rest = divmod(polygons, 6)
    jar_sides = None
    if rest:
        assert n_books >= 1
        n_books -= 1
        jar_sides = rest + 4  # an n-gon prism has n + 2 faces
    solids = []  # (solid, slot it stands in)
    free = [sl["a0"] for sl in slots]  # next free position along each slot
    turn = 0

    def place(thick, height, depth):
        """Books go to the slots in turn, so that every shelf gets some."""
        nonlocal turn
        for k in range(len(slots)):
            i = (turn + k) % len(slots)
            sl = slots[i]
            if free[i] + thick <= sl["a1"] and min(height, sl["max_h"]) > 0.1:
                break
        else:
            raise RuntimeError("not enough shelf space for the books")
        turn = i + 1
        height = min(height, sl["max_h"])
        a, b = free[i], free[i] + thick
        free[i] = b + rng.uniform(0.002, 0.006)
        c0 = sl["front"]
        c1 = c0 + sl["back_dir"] * depth
        c0, c1 = min(c0, c1), max(c0, c1)
        y0 = sl["y"]
        ext = (c0, y0, a, c1, y0 + height, b) if sl["along"] == "z" else (a, y0, c0, b, y0 + height, c1)
        return ext, sl

    for _ in range(n_books):
        thick = rng.uniform(0.018, 0.05)
        height = rng.uniform(0.17, 0.3)
        depth = rng.uniform(0.14, 0.22)
        ext, slot = place(thick, height, depth)
        solids.append((box(*ext), slot))
    if jar_sides:
        (x0, y0, z0, x1, y1, z1), slot = place(0.09, 0.14, 0.09)
        jar = ngon_prism((x0 + x1) / 2, (z0 + z1) / 2, 0.04, jar_sides, y0, y0 + 0.12)
        solids.append((jar, slot))
    return solids


def add_shelves(scene, parts, target, rng):
    """Adds the shelf units `parts` ({name: (solids, slots)}) filled with exactly the books that
    bring the scene to `target` polygons."""
    fixed = scene.polygon_count() + sum(len(solids) * 6 for solids, _ in parts.values())
    all_slots = [sl for _, slots in parts.values() for sl in slots]
    filler = books(rng, all_slots, target - fixed)
    for name, (solids, slots) in parts.items():
        mine = [b for b, sl in filler if any(sl is x for x in slots)]
        scene.add(name, "wood", solids + mine)


def cabinet(x0, z0, x1, z1, height, drawers, front):
    """A body with `drawers` drawer fronts and handles on its `front` side ("+z" or "-x" ...)."""
    solids = [box(x0, 0, z0, x1, height, z1)]
    gap = 0.015
    h = (height - 0.05 - gap * (drawers + 1)) / drawers
    for i in range(drawers):
        y0 = 0.05 + gap + i * (h + gap)
        y1 = y0 + h
        ym = (y0 + y1) / 2
        if front == "+z":
            solids.append(box(x0 + 0.02, y0, z1, x1 - 0.02, y1, z1 + 0.02))
            xm = (x0 + x1) / 2
            solids.append(box(xm - 0.06, ym - 0.01, z1 + 0.02, xm + 0.06, ym + 0.01, z1 + 0.04))
        elif front == "-x":
            solids.append(box(x0 - 0.02, y0, z0 + 0.02, x0, y1, z1 - 0.02))
            zm = (z0 + z1) / 2
            solids.append(box(x0 - 0.04, ym - 0.01, zm - 0.06, x0 - 0.02, ym + 0.01, zm + 0.06))
        else:
            raise ValueError(front)
    return solids


def desk_lamp(cx, cz, y):
    """Round base, square pole, round shade: 10 + 6 + 10 polygons."""
    return [ngon_prism(cx, cz, 0.07, 8, y, y + 0.02),
            box(cx - 0.01, y + 0.02, cz - 0.01, cx + 0.01, y + 0.37, cz + 0.01),
            ngon_prism(cx, cz, 0.09, 8, y + 0.37, y + 0.49, phase=math.pi / 8)]


def monitor(cx, z_back, y, detailed):
    """A screen facing +z standing on the desk at height y (with a stand when detailed)."""
    if not detailed:
        return [box(cx - 0.25, y, z_back, cx + 0.25, y + 0.32, z_back + 0.04)]
    return [box(cx - 0.1, y, z_back - 0.02, cx + 0.1, y + 0.015, z_back + 0.14),
            box(cx - 0.02, y + 0.015, z_back + 0.03, cx + 0.02, y + 0.2, z_back + 0.06),
            box(cx - 0.25, y + 0.05, z_back + 0.06, cx + 0.25, y + 0.37, z_back + 0.09)]


def sofa(x0, z0, x1, z1, back_side, cushions=0):
    """Base, back and two arms (and cushions) with the back against side "-x" of the footprint."""
    assert back_side == "-x"
    solids = [box(x0, 0, z0, x1, 0.42, z1),
              box(x0, 0.42, z0 + 0.005, x0 + 0.2, 0.85, z1 - 0.005),
              box(x0 + 0.2, 0.42, z0 + 0.01, x1 - 0.005, 0.62, z0 + 0.16),
              box(x0 + 0.2, 0.42, z1 - 0.16, x1 - 0.005, 0.62, z1 - 0.01)]
    if cushions:
        inner0, inner1 = z0 + 0.17, z1 - 0.17
        w = (inner1 - inner0 - 0.01 * (cushions - 1)) / cushions
        for i in range(cushions):
            a = inner0 + i * (w + 0.01)
            solids.append(box(x0 + 0.21, 0.42, a, x1 - 0.03, 0.52, a + w))
    return solids


# ---------------------------------------------------------------------------------------------
# The scenes.


def standard_materials(scene, emission):
    scene.material("white", [0.75, 0.75, 0.75])
    scene.material("floor", [0.45, 0.38, 0.3])
    scene.material("wood", [0.55, 0.4, 0.25])
    scene.material("grey", [0.35, 0.35, 0.38])
    scene.material("dark", [0.08, 0.08, 0.09])
    scene.material("red", [0.6, 0.12, 0.1])
    scene.material("blue", [0.12, 0.2, 0.55])
    scene.material("green", [0.18, 0.45, 0.15])
    scene.material("fabric", [0.5, 0.45, 0.35])
    scene.material("light", [0, 0, 0], emission)


def add_room(scene, x1, y1, z1):
    faces = room_faces(0, 0, 0, x1, y1, z1)
    scene.add("room-floor", "floor", [[faces["floor"]]])
    scene.add("room-walls", "white",
              [[faces["ceiling"], faces["x0"], faces["x1"], faces["z0"], faces["z1"]]])


# Radiant exitance of the room lights: about 2.5 W/m^2 of irradiance on a desk 2.2 m below a
# 0.36 m^2 panel, i.e. white surfaces of radiance ~0.6, a sensible unit exposure.
ROOM_LIGHT = [110, 105, 95]


def desk_scene(target, close=False):
    """Loscos & Drettakis 1997, Test 1 (and Test 2 with close=True): an office with a desk and a
    small box floating above it through 4 positions, detail growing with the polygon target."""
    name = "desk-%d%s" % (target, "-close" if close else "")
    rng = random.Random(target * 10 + close)
    s = Scene(name)
    standard_materials(s, ROOM_LIGHT)
    W, H, D = 5.0, 3.0, 4.0
    add_room(s, W, H, D)
    s.add("light", "light", [[ceiling_light(2.5, 1.5, 0.6, H)]])
    detailed = target >= 300
    rich = target >= 450

    # Desk against the back of the room, 0.5 m off the back wall; top at 0.75 m.
    desk = table(1.8, 0.5, 3.2, 1.25, 0.75)
    if detailed:  # a drawer pedestal under the right of the top
        desk += cabinet(2.70, 0.55, 3.10, 1.20 - 0.02, 0.72, 3, "+z")
    s.add("desk", "wood", desk)
    s.add("monitor", "dark", monitor(2.5, 0.6, 0.75, detailed))
    if detailed:
        s.add("keyboard", "grey", [box(2.3, 0.75, 0.85, 2.7, 0.77, 1.0)])
    if rich:
        s.add("desk-lamp", "grey", desk_lamp(3.0, 0.68, 0.75))
    s.add("chair", "red" if detailed else "grey", chair(2.28, 1.45, back="+z"))
    if rich:
        # A visitor's chair, turned 25 degrees: exercises the static "transform".
        s.add("visitor-chair", "blue", chair(-0.22, -0.22, back="+z"),
              transform=((1.25, 0, 1.75), 25))

    # Bookshelf on the left wall, cabinet right of the desk against the back wall.
    shelf, slots = shelf_unit(0.01, 0.4, 0.36, 1.4, 1.8, 4 if detailed else 3, "z", +1)
    parts = {"bookshelf": (shelf, slots)}
    if rich:
        parts["bookshelf-2"] = shelf_unit(4.64, 1.6, 4.99, 2.6, 2.0, 5, "z", -1)
    s.add("cabinet", "grey", cabinet(3.6, 0.01, 4.1, 0.5, 0.7, 3, "+z") if detailed
          else [box(3.6, 0, 0.3, 4.1, 0.7, 0.8)])
    if detailed:
        s.add("bin", "dark", [ngon_prism(1.5, 0.8, 0.13, 10, 0, 0.35)])
    if rich:
        s.add("picture", "blue", [box(0.9, 1.4, 0.0, 1.6, 1.9, 0.03)])

    # The floating box: 0.15 m, 0.4 m above the desk, crossing it in front of the monitor
    # (Test 1); or grazing the desk top, the monitor's front and top by 3 cm (Test 2).
    e = 0.15
    if not close:
        path = [(2.05, 1.15, 0.95), (2.35, 1.15, 1.0), (2.65, 1.15, 1.05), (2.95, 1.15, 1.0)]
    else:
        path = [(2.10 - e / 2, 0.78, 0.64 + 0.03 + e / 2), (2.5 + 0.03, 0.78, 0.64 + 0.03 + e / 2),
                (2.5 + 0.03, 1.07 + 0.03, 0.64 + 0.03 + e / 2), (2.5 + 0.03, 1.10, 0.62)]
    motion = [(i, (x, y, z)) for i, (x, y, z) in enumerate(path)]
    s.add("floating-box", "green" if detailed else "white",
          [box(-e / 2, 0, -e / 2, e / 2, e, e / 2)], motion=motion)
    s.frames = 4

    add_shelves(s, parts, target, rng)  # books fill the polygon budget exactly
    s.objects.sort(key=object_order)
    s.camera = {"eye": (3.75, 1.8, 3.1), "target": (2.4, 0.9, 0.95), "fov": 50,
                "width": 640, "height": 480}
    return s


def object_order(o):
    """Room first, then the light, then the rest in insertion order (stable sort)."""
    if o["name"].startswith("room"):
        return 0
    return 1 if o["name"] == "light" else 2


def chair_room():
    """A dining corner whose front chair is pushed back and away from the table over 5 frames."""
    s = Scene("chair-room")
    rng = random.Random(227)
    standard_materials(s, ROOM_LIGHT)
    W, H, D = 4.5, 2.7, 4.0
    add_room(s, W, H, D)
    s.add("light", "light", [[ceiling_light(2.25, 2.0, 0.6, H)]])
    s.add("table", "wood", table(1.5, 0.9, 2.7, 1.7, 0.75))
    s.add("chair-back", "wood", chair(1.88, 0.35, back="-z"))
    s.add("sofa", "fabric", sofa(0.01, 1.8, 0.85, 3.4, "-x"))
    s.add("sideboard", "grey", [box(4.0, 0, 0.4, 4.49, 0.8, 1.4),  # body and two doors
                                box(3.98, 0.05, 0.42, 4.0, 0.78, 0.89),
                                box(3.98, 0.05, 0.91, 4.0, 0.78, 1.38)])
    s.add("bin", "dark", [ngon_prism(3.2, 0.6, 0.14, 8, 0, 0.35)])
    shelf, slots = shelf_unit(2.9, 0.01, 4.1, 0.36, 1.9, 3, "x", +1)
    # The moving chair: starts tucked at the front of the table, then slides out and right.
    moving = chair(-0.22, -0.22, back="+z", posts=True)
    start = (2.1, 0, 2.07)
    offsets = [(0, 0, 0), (0.05, 0, 0.25), (0.35, 0, 0.5), (0.75, 0, 0.65), (1.2, 0, 0.7)]
    s.add("chair-moving", "red", moving,
          motion=[(i, add(start, o)) for i, o in enumerate(offsets)])
    s.frames = 5
    add_shelves(s, {"bookshelf": (shelf, slots)}, 227, rng)
    s.objects.sort(key=object_order)
    s.camera = {"eye": (4.2, 1.7, 3.8), "target": (2.3, 0.5, 1.7), "fov": 55,
                "width": 640, "height": 480}
    return s


def furnished_room():
    """A living/dining room of about 1,300 polygons with a stool sliding across the floor."""
    s = Scene("furnished-room")
    rng = random.Random(1300)
    standard_materials(s, ROOM_LIGHT)
    W, H, D = 7.0, 3.0, 6.0
    add_room(s, W, H, D)
    s.add("light", "light", [[ceiling_light(3.5, 3.0, 0.6, H)]])

    # Work corner at the back right.
    desk = table(4.6, 0.5, 6.0, 1.25, 0.75) + cabinet(5.5, 0.55, 5.9, 1.18, 0.72, 3, "+z")
    s.add("desk", "wood", desk)
    s.add("monitor", "dark", monitor(5.1, 0.6, 0.75, True))
    s.add("keyboard", "grey", [box(4.9, 0.75, 0.85, 5.3, 0.77, 1.0)])
    s.add("desk-lamp", "grey", desk_lamp(4.73, 0.7, 0.75))
    s.add("desk-chair", "red", chair(4.88, 1.45, back="+z", posts=True))
    s.add("filing-cabinet", "grey", cabinet(6.3, 0.01, 6.99, 0.6, 1.1, 4, "+z"))

    # Dining table with four chairs in the middle left.
    s.add("dining-table", "wood",
          [ngon_prism(2.2, 3.2, 0.6, 16, 0.72, 0.75),
           box(2.15, 0.03, 3.15, 2.25, 0.72, 3.25),
           ngon_prism(2.2, 3.2, 0.3, 8, 0, 0.03, phase=math.pi / 8)])
    s.add("dining-chair-n", "wood", chair(1.98, 2.15, back="-z", posts=True))
    s.add("dining-chair-s", "wood", chair(1.98, 3.81, back="+z", posts=True))
    s.add("dining-chair-w", "wood", chair(0.95, 2.98, back="-x", posts=True))
    s.add("dining-chair-e", "wood", chair(3.01, 2.98, back="+x", posts=True))

    # Sofa on the left wall with a coffee table carrying a stack of magazines.
    s.add("sofa", "fabric", sofa(0.01, 0.6, 0.9, 2.0, "-x", cushions=3))
    coffee = table(1.1, 0.9, 1.7, 1.7, 0.42, leg=0.04)
    for i in range(6):
        a = 0.01 * i
        coffee.append(box(1.2 + a, 0.42 + 0.012 * i, 1.0 + a / 2, 1.5 - a / 3,
                          0.42 + 0.012 * (i + 1), 1.35 - a / 2))
    s.add("coffee-table", "wood", coffee)
    s.add("plant-pot", "red", [ngon_prism(0.4, 4.6, 0.16, 10, 0, 0.4)])
    s.add("plant", "green", [box(0.3, 0.4, 4.5, 0.5, 1.1, 4.7)])
    s.add("sideboard", "grey", cabinet(6.5, 2.2, 6.99, 3.8, 0.85, 3, "-x"))
    s.add("bin", "dark", [ngon_prism(4.3, 1.0, 0.13, 10, 0, 0.35)])

    # Three bookshelves on the back wall (filled last), a fourth on the left wall at the front.
    parts = {}
    for i, x0 in enumerate((0.3, 1.35, 2.4)):
        parts["bookshelf-%d" % (i + 1)] = shelf_unit(x0, 0.01, x0 + 1.0, 0.36, 2.1, 6, "x", +1)
    parts["bookshelf-4"] = shelf_unit(0.01, 4.95, 0.36, 5.95, 2.1, 6, "z", +1)

    # The stool: round seat on four legs with foot rails, sliding across the open front floor.
    st = []
    st.append(ngon_prism(0, 0, 0.19, 12, 0.62, 0.66))
    for lx in (-0.12, 0.09):
        for lz in (-0.12, 0.09):
            st.append(box(lx, 0, lz, lx + 0.03, 0.62, lz + 0.03))
    st.append(box(-0.09, 0.25, -0.115, 0.09, 0.27, -0.095))
    st.append(box(-0.09, 0.25, 0.095, 0.09, 0.27, 0.115))
    st.append(box(-0.115, 0.32, -0.09, -0.095, 0.34, 0.09))
    st.append(box(0.095, 0.32, -0.09, 0.115, 0.34, 0.09))
    path = [(2.0, 0, 4.9), (2.8, 0, 4.6), (3.7, 0, 4.5), (4.5, 0, 4.1), (5.0, 0, 3.5)]
    s.add("stool", "blue", st, motion=list(enumerate(path)))
    s.frames = 5

    add_shelves(s, parts, 1300, rng)
    s.objects.sort(key=object_order)
    s.camera = {"eye": (6.6, 1.9, 5.6), "target": (3.2, 0.5, 3.0), "fov": 60,
                "width": 640, "height": 480}
    return s


def cornell_box(mirror=False):
    """The Cornell Box (Cornell University Program of Computer Graphics, published data), made
    an ideal 556 x 548.8 x 559.2 mm box (the measured walls are slightly skew), with the blocks
    as published (closed with bottom faces) and the short block sliding 6 cm toward the green
    wall over 4 frames. The real box is open toward the camera into a dark lab; to keep the room
    closed the opening continues as a black (reflectance 0) tunnel past the camera, which reflects
    nothing, exactly like the dark lab.

    With mirror=True the green wall is a planar mirror of reflectance 0.9 (the shadow-volume
    renderer draws the reflected room in it; the other engines see a diffuse grey wall)."""
    s = Scene("cornell-mirror" if mirror else "cornell-box")
    mm = 0.001
    s.material("white", [0.75, 0.75, 0.75])
    s.material("red", [0.63, 0.065, 0.05])
    if mirror:
        s.material("mirror", [0.9, 0.9, 0.9], mirror=True)
    else:
        s.material("green", [0.14, 0.45, 0.09])
    s.material("black", [0, 0, 0])
    # (17, 12, 4) is the usual radiance of the Cornell light; exitance of a Lambertian emitter is
    # pi times its radiance.
    s.material("light", [0.78, 0.78, 0.78], [round(math.pi * c, 4) for c in (17, 12, 4)])
    X, Y, Z = 556.0 * mm, 548.8 * mm, 559.2 * mm
    front = -0.85  # the tunnel ends 5 cm behind the camera
    box_faces = room_faces(0, 0, 0, X, Y, Z)
    tunnel = room_faces(0, 0, front, X, Y, 0)
    s.add("room-white", "white", [[box_faces["floor"], box_faces["ceiling"], box_faces["z1"]]])
    s.add("room-red", "red", [[box_faces["x1"]]])
    if mirror:
        s.add("room-mirror", "mirror", [[box_faces["x0"]]])
    else:
        s.add("room-green", "green", [[box_faces["x0"]]])
    s.add("room-black", "black", [[tunnel["floor"], tunnel["ceiling"], tunnel["x0"], tunnel["x1"],
                                   tunnel["z0"]]])
    light = [(343.0, 227.0), (343.0, 332.0), (213.0, 332.0), (213.0, 227.0)]
    ly = Y - 1.0 * mm
    s.add("light", "light", [[oriented([(x * mm, ly, z * mm) for x, z in light], (0, -1, 0))]])

    def block(top_xz, height):
        base = [(x * mm, z * mm) for x, z in top_xz]
        return prism(base, 0, height * mm)

    short = block([(130.0, 65.0), (82.0, 225.0), (240.0, 272.0), (290.0, 114.0)], 165.0)
    tall = block([(423.0, 247.0), (265.0, 296.0), (314.0, 456.0), (472.0, 406.0)], 330.0)
    s.add("short-block", "white", [short],
          motion=[(i, (-0.02 * i, 0, 0)) for i in range(4)])
    s.add("tall-block", "white", [tall])
    s.frames = 4
    fov = 2 * math.degrees(math.atan(12.5 / 35.0))  # 25 mm film, 35 mm focal length
    s.camera = {"eye": (278 * mm, 273 * mm, -800 * mm), "target": (278 * mm, 273 * mm, 0),
                "fov": fov, "width": 512, "height": 512}
    return s


def main():
    check_only = "--check" in sys.argv[1:]
    scenes = [
        ("cornell-box/cornell-box.json", cornell_box(), 23, False),
        ("cornell-box/cornell-mirror.json", cornell_box(mirror=True), 23, False),
        ("office-desk/desk-145.json", desk_scene(145), 145, True),
        ("office-desk/desk-307.json", desk_scene(307), 307, True),
        ("office-desk/desk-475.json", desk_scene(475), 475, True),
        ("office-desk/desk-145-close.json", desk_scene(145, close=True), 145, True),
        ("chair-room/chair-room.json", chair_room(), 227, True),
        ("chair-room/furnished-room.json", furnished_room(), 1300, True),
    ]
    stale = []
    for rel, scene, count, aabb_ok in scenes:
        n = check(scene, count, aabb_pairs=aabb_ok)
        path = os.path.join(ROOT, "scenes", rel)
        text = scene.to_json()
        if check_only:
            with open(path) as f:
                if f.read() != text:
                    stale.append(rel)
        else:
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with open(path, "w") as f:
                f.write(text)
        print("%-36s %5d polygons, %3d objects" % (rel, n, len(scene.objects)))
    if stale:
        print("out of date: " + ", ".join(stale), file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
