#!/usr/bin/env python3
"""Writes animated-box.gltf: a closed 4 x 3 x 4 m room (red left wall, green right wall), an
emissive 1 x 1 m ceiling lamp facing down, and a 0.6 m box hovering 0.1 m above the floor that
slides 1.6 m along +x while turning 45 degrees about +y during one second. Every quad is two
triangles, counter-clockwise seen from its front. Run it again after editing; the output is
committed so that the tests do not need Python."""

import base64
import json
import math
import os
import struct


def quad_from_frame(center, u, v):
    """Corners of the quad center +- u +- v, counter-clockwise around u x v."""
    c, (ux, uy, uz), (vx, vy, vz) = center, u, v
    return [
        (c[0] - ux - vx, c[1] - uy - vy, c[2] - uz - vz),
        (c[0] + ux - vx, c[1] + uy - vy, c[2] + uz - vz),
        (c[0] + ux + vx, c[1] + uy + vy, c[2] + uz + vz),
        (c[0] - ux + vx, c[1] - uy + vy, c[2] - uz + vz),
    ]


# Room walls face inwards (front = inside): (center, u, v) with u x v = inward normal.
WHITE_WALLS = [
    ((2, 0, 2), (0, 0, 2), (2, 0, 0)),      # floor, normal +y
    ((2, 3, 2), (2, 0, 0), (0, 0, 2)),      # ceiling, normal -y
    ((2, 1.5, 0), (2, 0, 0), (0, 1.5, 0)),  # back wall z = 0, normal +z
    ((2, 1.5, 4), (0, 1.5, 0), (2, 0, 0)),  # front wall z = 4, normal -z
]
RED_WALLS = [((0, 1.5, 2), (0, 1.5, 0), (0, 0, 2))]    # x = 0, normal +x
GREEN_WALLS = [((4, 1.5, 2), (0, 0, 2), (0, 1.5, 0))]  # x = 4, normal -x
LAMP = [((2, 2.99, 2), (0.5, 0, 0), (0, 0, 0.5))]      # normal -y, 1 cm below the ceiling
H = 0.3
BOX = [  # outward normals +x, -x, +y, -y, +z, -z
    ((H, 0, 0), (0, H, 0), (0, 0, H)),
    ((-H, 0, 0), (0, 0, H), (0, H, 0)),
    ((0, H, 0), (0, 0, H), (H, 0, 0)),
    ((0, -H, 0), (H, 0, 0), (0, 0, H)),
    ((0, 0, H), (H, 0, 0), (0, H, 0)),
    ((0, 0, -H), (0, H, 0), (H, 0, 0)),
]

binary = bytearray()
buffer_views, accessors = [], []


def add_view(data):
    while len(binary) % 4:
        binary.append(0)
    buffer_views.append({"buffer": 0, "byteOffset": len(binary), "byteLength": len(data)})
    binary.extend(data)
    return len(buffer_views) - 1


def add_accessor(values, component_type, fmt, type_name, count, **extra):
    view = add_view(struct.pack("<%d%s" % (len(values), fmt), *values))
    accessors.append(dict(bufferView=view, componentType=component_type, count=count,
                          type=type_name, **extra))
    return len(accessors) - 1


def primitive(quads, material):
    positions, indices = [], []
    for q in quads:
        corners = quad_from_frame(*q)
        base = len(positions)
        positions.extend(corners)
        indices.extend([base, base + 1, base + 2, base, base + 2, base + 3])
    flat = [x for p in positions for x in p]
    lo = [min(p[i] for p in positions) for i in range(3)]
    hi = [max(p[i] for p in positions) for i in range(3)]
    pos = add_accessor(flat, 5126, "f", "VEC3", len(positions), min=lo, max=hi)
    idx = add_accessor(indices, 5123, "H", "SCALAR", len(indices))
    return {"attributes": {"POSITION": pos}, "indices": idx, "material": material}


def y_rotation(degrees):
    half = math.radians(degrees) / 2
    return [0, math.sin(half), 0, math.cos(half)]


meshes = [
    {"name": "room", "primitives": [primitive(WHITE_WALLS, 0), primitive(RED_WALLS, 1),
                                    primitive(GREEN_WALLS, 2)]},
    {"name": "lamp", "primitives": [primitive(LAMP, 3)]},
    {"name": "box", "primitives": [primitive(BOX, 4)]},
]
times = add_accessor([0.0, 1.0], 5126, "f", "SCALAR", 2, min=[0.0], max=[1.0])
translations = add_accessor([1.2, 0.4, 2.0, 2.8, 0.4, 2.0], 5126, "f", "VEC3", 2)
rotations = add_accessor(y_rotation(0) + y_rotation(45), 5126, "f", "VEC4", 2)

gltf = {
    "asset": {"version": "2.0", "generator": "penumbra scenes/gltf/make_animated_box.py"},
    "extensionsUsed": ["KHR_materials_emissive_strength"],
    "scene": 0,
    "scenes": [{"name": "animated box", "nodes": [0, 1, 2, 3]}],
    "nodes": [
        {"name": "room", "mesh": 0},
        {"name": "lamp", "mesh": 1},
        {"name": "box", "mesh": 2, "translation": [1.2, 0.4, 2.0]},
        {"name": "camera", "camera": 0, "translation": [2, 1.5, 3.8]},
    ],
    "cameras": [{"type": "perspective",
                 "perspective": {"yfov": math.radians(60), "aspectRatio": 4 / 3,
                                 "znear": 0.05}}],
    "materials": [
        {"name": "white", "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.7, 0.7, 1]}},
        {"name": "red", "pbrMetallicRoughness": {"baseColorFactor": [0.6, 0.1, 0.1, 1]}},
        {"name": "green", "pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.6, 0.1, 1]}},
        {"name": "lamp", "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1]},
         "emissiveFactor": [1, 1, 1],
         "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 10}}},
        {"name": "box", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1]}},
    ],
    "meshes": meshes,
    "animations": [{
        "name": "slide",
        "samplers": [{"input": times, "output": translations, "interpolation": "LINEAR"},
                     {"input": times, "output": rotations, "interpolation": "LINEAR"}],
        "channels": [{"sampler": 0, "target": {"node": 2, "path": "translation"}},
                     {"sampler": 1, "target": {"node": 2, "path": "rotation"}}],
    }],
    "accessors": accessors,
    "bufferViews": buffer_views,
    "buffers": [{"byteLength": len(binary),
                 "uri": "data:application/octet-stream;base64," +
                        base64.b64encode(bytes(binary)).decode("ascii")}],
}

out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "animated-box.gltf")
with open(out, "w") as f:
    json.dump(gltf, f, indent=1)
    f.write("\n")
print("wrote", out)
