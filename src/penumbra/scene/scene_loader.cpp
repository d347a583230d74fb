#include "penumbra/scene/scene_loader.h"

#include <algorithm>
#include <map>

#include "penumbra/base/input_error.h"
#include "penumbra/scene/obj_mesh_reader.h"
#include "penumbra/scene/repeated_vertices.h"

namespace penumbra {

namespace {
std::string lowercaseExtension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  const auto slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext;
}
}  // namespace

Scene loadObjScene(const std::string& path) {
  ObjMesh mesh = readObjMesh(path);
  Scene scene;
  scene.sourcePath = path;
  SceneObject object;
  object.name = path.substr(path.find_last_of('/') + 1);
  std::map<std::string, int> materialIndex;
  for (ObjFace& face : mesh.faces) {
    const std::string where = path + ":" + std::to_string(face.line);
    if (face.materialName.empty()) throw InputError(where, "face has no material (usemtl)");
    auto it = materialIndex.find(face.materialName);
    if (it == materialIndex.end()) {
      const auto mtl =
          std::find_if(mesh.mtlMaterials.begin(), mesh.mtlMaterials.end(),
                       [&](const ObjMtlMaterial& m) { return m.name == face.materialName; });
      if (mtl == mesh.mtlMaterials.end())
        throw InputError(where, "unknown material '" + face.materialName + "'");
      it = materialIndex.emplace(face.materialName, int(scene.materials.size())).first;
      scene.materials.push_back({mtl->name, mtl->diffuse, mtl->emission, false});
    }
    object.polygons.push_back(std::move(face.vertices));
    object.polygonMaterial.push_back(it->second);
    object.polygonOrigin.push_back(where);
  }
  if (object.polygons.empty()) throw InputError(path, "the scene has no polygons");
  scene.objects.push_back(std::move(object));
  return scene;
}

Scene loadScene(const std::string& path) {
  const std::string ext = lowercaseExtension(path);
  Scene scene;
  if (ext == "json")
    scene = loadJsonScene(path);
  else if (ext == "obj")
    scene = loadObjScene(path);
  else if (ext == "gltf" || ext == "glb")
    scene = loadGltfScene(path);
  else
    throw InputError(path,
                     "unknown scene file type '." + ext + "' (expected .json, .obj, .gltf, .glb)");
  removeRepeatedVertices(scene);
  validateScene(scene);
  return scene;
}

}  // namespace penumbra
