#!/usr/bin/env python3
"""Writes the generated glTF seeds of fuzz/corpus/gltf_scene/ (the others are copied from scenes/).

Small documents, each reaching a different part of the glTF loader: data URIs, the binary container,
an external buffer (after the target's %%BIN%% separator), strips and fans, sparse and quantized
accessors, matrix nodes in a hierarchy, a camera, and animations of every interpolation.
Run from the repository root: python3 fuzz/make_gltf_seeds.py
"""

import base64
import json
import struct
from pathlib import Path

OUT = Path(__file__).resolve().parent / "corpus" / "gltf_scene"
FLOAT, USHORT, SHORT = 5126, 5123, 5122


class Doc:
    def __init__(self):
        self.bin = bytearray()
        self.doc = {"asset": {"version": "2.0"}, "bufferViews": [], "accessors": []}

    def view(self, data):
        while len(self.bin) % 4:
            self.bin.append(0)
        self.doc["bufferViews"].append({"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)})
        self.bin += data
        return len(self.doc["bufferViews"]) - 1

    def accessor(self, fmt, values, component, type_, count, **extra):
        accessor = {"bufferView": self.view(struct.pack("<" + fmt * len(values), *values)),
                    "componentType": component, "count": count, "type": type_}
        accessor.update(extra)
        self.doc["accessors"].append(accessor)
        return len(self.doc["accessors"]) - 1

    def floats(self, values, type_):
        width = {"SCALAR": 1, "VEC3": 3, "VEC4": 4}[type_]
        extra = {}
        if type_ == "VEC3":
            extra = {"min": [min(values[i::3]) for i in range(3)], "max": [max(values[i::3]) for i in range(3)]}
        return self.accessor("f", values, FLOAT, type_, len(values) // width, **extra)

    def indices(self, values):
        return self.accessor("H", values, USHORT, "SCALAR", len(values))

    def mesh(self, positions, indices=None, material=None, mode=4):
        primitive = {"attributes": {"POSITION": positions}, "mode": mode}
        if indices is not None:
            primitive["indices"] = indices
        if material is not None:
            primitive["material"] = material
        self.doc.setdefault("meshes", []).append({"primitives": [primitive]})
        return len(self.doc["meshes"]) - 1

    def node(self, **node):
        self.doc.setdefault("nodes", []).append(node)
        return len(self.doc["nodes"]) - 1

    def quad(self, material=None, z=0.0):
        positions = self.floats([0, 0, z, 1, 0, z, 1, 1, z, 0, 1, z], "VEC3")
        return self.mesh(positions, self.indices([0, 1, 2, 0, 2, 3]), material)

    def lit_quad_scene(self):
        self.doc["materials"] = [
            {"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1]}},
            {"emissiveFactor": [1, 1, 1], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 5}}},
        ]
        self.doc["extensionsUsed"] = ["KHR_materials_emissive_strength"]
        floor = self.node(name="floor", mesh=self.quad(0))
        lamp = self.node(name="lamp", mesh=self.quad(1), translation=[0.25, 0.25, 2], scale=[0.5, 0.5, -1])
        self.doc["scenes"] = [{"nodes": [floor, lamp]}]
        self.doc["scene"] = 0

    def json_with(self, uri):
        doc = dict(self.doc)
        buffer = {"byteLength": len(self.bin)}
        if uri is not None:
            buffer["uri"] = uri
        doc["buffers"] = [buffer]
        return json.dumps(doc, separators=(",", ":")).encode()

    def gltf(self):
        return self.json_with("data:application/octet-stream;base64," + base64.b64encode(self.bin).decode())

    def gltf_external(self):
        return self.json_with("buffer.bin") + b"\n%%BIN%%\n" + bytes(self.bin)

    def glb(self):
        text = self.json_with(None)
        text += b" " * (-len(text) % 4)
        binary = bytes(self.bin) + b"\0" * (-len(self.bin) % 4)
        chunks = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(binary), 0x004E4942) + binary
        return struct.pack("<III", 0x46546C67, 2, 12 + len(chunks)) + chunks


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    d = Doc()
    d.lit_quad_scene()
    (OUT / "lit-quad.gltf").write_bytes(d.gltf())
    (OUT / "lit-quad.glb").write_bytes(d.glb())
    (OUT / "lit-quad-external.gltf").write_bytes(d.gltf_external())

    # Strips, fans and lines; a matrix node above a TRS child; a camera.
    d = Doc()
    strip = d.mesh(d.floats([0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 2, 0], "VEC3"), mode=5)
    fan = d.mesh(d.floats([0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1], "VEC3"), d.indices([0, 1, 2, 2, 3]), mode=6)
    lines = d.mesh(d.floats([0, 0, 0, 1, 1, 1], "VEC3"), mode=1)
    child = d.node(mesh=fan, rotation=[0, 0, 0.38268343, 0.92387953], scale=[2, 1, 1])
    d.node(mesh=strip, matrix=[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.5, 0, 0, 1], children=[child])
    d.node(mesh=lines)
    d.doc["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "aspectRatio": 1.5}}]
    d.node(camera=0, translation=[0, 0, 5])
    (OUT / "strips-fans-hierarchy.gltf").write_bytes(d.gltf())

    # Sparse and quantized accessors.
    d = Doc()
    d.doc["extensionsUsed"] = d.doc["extensionsRequired"] = ["KHR_mesh_quantization"]
    quantized = d.accessor("h", [0, 0, 0, 32767, 0, 0, 0, 32767, 0], SHORT, "VEC3", 3, normalized=True)
    sparse = d.floats([0, 0, 2, 1, 0, 2, 0, 1, 2], "VEC3")
    d.doc["accessors"][sparse]["sparse"] = {
        "count": 1,
        "indices": {"bufferView": d.view(struct.pack("<H", 2)), "componentType": USHORT},
        "values": {"bufferView": d.view(struct.pack("<3f", 1, 1, 2))},
    }
    d.node(mesh=d.mesh(quantized))
    d.node(mesh=d.mesh(sparse))
    (OUT / "sparse-quantized.gltf").write_bytes(d.gltf())

    # Animations: LINEAR translation, STEP scale, CUBICSPLINE rotation, a weights channel.
    d = Doc()
    d.lit_quad_scene()
    box = d.node(name="mover", mesh=d.quad(0, 0.5), children=[])
    d.doc["scenes"][0]["nodes"].append(box)
    times = d.floats([0, 0.5, 1], "SCALAR")
    samplers = [
        {"input": times, "output": d.floats([0, 0, 0, 0.5, 0, 0, 1, 0, 0], "VEC3"), "interpolation": "LINEAR"},
        {"input": times, "output": d.floats([1, 1, 1, 2, 1, 1, 1, 1, 1], "VEC3"), "interpolation": "STEP"},
        {"input": times, "interpolation": "CUBICSPLINE",
         "output": d.floats([0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0] * 3, "VEC4")},
    ]
    d.doc["animations"] = [{"samplers": samplers, "channels": [
        {"sampler": 0, "target": {"node": box, "path": "translation"}},
        {"sampler": 1, "target": {"node": box, "path": "scale"}},
        {"sampler": 2, "target": {"node": box, "path": "rotation"}},
        {"sampler": 0, "target": {"node": box, "path": "weights"}},
    ]}]
    (OUT / "animations.gltf").write_bytes(d.gltf())


if __name__ == "__main__":
    main()
