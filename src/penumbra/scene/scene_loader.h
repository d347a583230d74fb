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
// The largest coordinate any pose of a scene may reach (and a probe point or the camera may
// have), in the scene's units: a million kilometres in metres. Beyond it the engines cannot
// keep their guarantees (the ray caster works in floats around the scene's centre, the exact
// reference clips in 64-bit integers scaled to each light, tolerances are relative to the
// scene's size), and magnitudes like 1e150 crashed them; such input is refused naming the object
// or line instead.
inline constexpr double kMaxCoordinate = 1e9;
inline constexpr int kGltfFramesPerSecond = 24;
// glTF 2.0 (.gltf or .glb): meshes, node transforms, emissive materials as lights, node
// animations as keyframed motion (docs/gltf.md gives the mapping).
Scene loadGltfScene(const std::string& path);

// Checks every polygon (finite, >= 3 distinct vertices, non-zero area, planar, simple), every
// material (finite, non-negative, reflectance in [0, 1]) and motion (finite, invertible
// transforms). Throws InputError located by the polygon's origin (file:line or JSON path).
void validateScene(const Scene& scene);

}  // namespace penumbra
