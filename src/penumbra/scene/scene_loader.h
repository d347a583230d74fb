#pragma once
// Loading scenes from files (DESIGN.md §4). Every loader validates what it reads and throws
// InputError naming the file and the line (OBJ) or JSON path and the problem; nothing is loaded
// partially. Dispatch is by extension: .json, .obj, .gltf, .glb.

#include <string>

#include "penumbra/scene/scene.h"

namespace penumbra {

// Loads any supported scene file, then runs validateScene.
Scene loadScene(const std::string& path);

// Penumbra's JSON scene format (may reference OBJ files relative to the JSON file).
Scene loadJsonScene(const std::string& path);
// A bare Wavefront OBJ (with its MTL) as a static scene of one object per OBJ object/group.
Scene loadObjScene(const std::string& path);
// glTF animations are sampled at integer frames f = 0, 1, ... at t = f / kGltfFramesPerSecond
// seconds (film rate; docs/gltf.md).
inline constexpr int kGltfFramesPerSecond = 24;
// glTF 2.0 (.gltf or .glb): meshes, node transforms, emissive materials as lights, node
// animations as keyframed motion (docs/gltf.md gives the mapping).
Scene loadGltfScene(const std::string& path);

// Checks every polygon (finite, >= 3 distinct vertices, non-zero area, planar, simple), every
// material (finite, non-negative, reflectance in [0, 1]) and motion (finite, invertible transforms).
// Throws InputError located by the polygon's origin (file:line or JSON path).
void validateScene(const Scene& scene);

}  // namespace penumbra
