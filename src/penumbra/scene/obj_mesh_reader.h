#pragma once
// Reads a Wavefront OBJ file (with its MTL) into polygons, keeping faces as polygons (no
// triangulation) and the source line of every face so errors can name it.
// Parsing is tinyobjloader's (double precision); a pre-scan of our own checks what tinyobjloader
// would silently accept or drop: non-finite coordinates, faces of fewer than 3 vertices, vertex
// indices out of range; a pre-scan of the MTL files finds the line of each material's `Kd`.

#include <string>
#include <vector>

#include "penumbra/base/rgb.h"
#include "penumbra/geometry/polygon.h"

namespace penumbra {

struct ObjFace {
  Polygon3 vertices;
  std::string materialName;  // from `usemtl`; empty when the face names none
  int line = 0;              // 1-based line of the `f` statement
};

struct ObjMtlMaterial {
  std::string name;
  Rgb diffuse;   // Kd
  Rgb emission;  // Ke
  // "file.mtl:line" of its last `Kd` statement (the one that counts), or of its `newmtl` when it
  // has no Kd, so that a range error names the line to fix; the OBJ's path when unknown.
  std::string location;
};

struct ObjMesh {
  std::string path;
  std::vector<ObjFace> faces;
  std::vector<ObjMtlMaterial> mtlMaterials;
};

// Throws InputError ("file:line: problem") on unreadable or malformed input.
ObjMesh readObjMesh(const std::string& path);

}  // namespace penumbra
