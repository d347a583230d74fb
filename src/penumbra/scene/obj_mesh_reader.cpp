#include "penumbra/scene/obj_mesh_reader.h"

#include <tiny_obj_loader.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "penumbra/base/input_error.h"
#include "penumbra/base/input_file.h"

namespace penumbra {

namespace {

std::string at(const std::string& path, int line) {
  return path + ":" + std::to_string(line);
}

// Parses a finite double occupying the whole token.
bool parseFiniteDouble(const std::string& token, double& value) {
  if (token.empty()) return false;
  char* end = nullptr;
  errno = 0;
  value = std::strtod(token.c_str(), &end);
  return end == token.c_str() + token.size() && errno != ERANGE && std::isfinite(value);
}

// The blank-separated fields of an OBJ statement as tinyobjloader separates them: at spaces and
// tabs only (its IS_SPACE), the line's final CR (CR LF files) dropped. Splitting at every isspace()
// character (form feed, vertical tab) made `v\f0 1 0` a vertex here and an unknown statement
// there, and a face's negative index then reached a vertex tinyobjloader did not have
// (std::out_of_range escaped).
std::vector<std::string> objFields(std::string statement) {
  if (!statement.empty() && statement.back() == '\r') statement.pop_back();
  std::vector<std::string> fields;
  size_t start = statement.find_first_not_of(" \t");
  while (start != std::string::npos) {
    const size_t end = statement.find_first_of(" \t", start);
    fields.push_back(statement.substr(start, end - start));
    start = statement.find_first_not_of(" \t", end);
  }
  return fields;
}

struct FaceStatement {
  int line;
  std::string materialName;  // the `usemtl` in force
};

struct Prescan {
  std::vector<FaceStatement> faces;
  std::vector<Vec3> vertices;  // parsed with strtod: correctly rounded, unlike tinyobjloader's
  std::vector<std::vector<std::string>> mtllibs;  // the file names of each `mtllib` statement
  std::vector<std::string> lines;  // the file's lines, vertex and face statements uncommented
  bool hasTrailingComments = false;
};

// A copy of the OBJ's lines in a temporary file, removed when this goes.
class TemporaryObj {
 public:
  explicit TemporaryObj(const std::vector<std::string>& lines) {
    static std::atomic<unsigned> counter{0};
    path_ = (std::filesystem::temp_directory_path() /
             ("penumbra-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + ".obj"))
                .string();
    std::ofstream out(path_);
    for (const std::string& line : lines) out << line << '\n';
    if (!out) throw InputError(path_, "cannot write a temporary copy of the OBJ file");
  }
  ~TemporaryObj() {
    std::error_code ignored;
    std::filesystem::remove(path_, ignored);
  }
  TemporaryObj(const TemporaryObj&) = delete;
  TemporaryObj& operator=(const TemporaryObj&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// The file names of an `mtllib` statement as tinyobjloader splits them: at spaces, a backslash
// escaping the next character, the last (possibly empty) name always kept.
std::vector<std::string> mtllibFileNames(const std::string& rest) {
  std::vector<std::string> names;
  std::string name;
  bool escaping = false;
  for (char c : rest) {
    if (escaping) {
      escaping = false;
    } else if (c == '\\') {
      escaping = true;
      continue;
    } else if (c == ' ') {
      if (!name.empty()) names.push_back(name);
      name.clear();
      continue;
    }
    name += c;
  }
  names.push_back(name);
  return names;
}

// The checks tinyobjloader does not make, and what it forgets: the line of every `f` statement
// and the `usemtl` name in force there (tinyobjloader drops names its MTL does not define, but the
// scene's JSON materials may define them), and the vertex coordinates correctly rounded.
Prescan prescan(const std::string& path) {
  std::ifstream in = openInputFile(path, "OBJ file");
  Prescan result;
  std::vector<FaceStatement>& faceLines = result.faces;
  std::string currentMaterial;
  long vertexCount = 0;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    // A carriage return inside a line: the file ends its lines with CR alone (old Mac), which
    // neither this reader nor tinyobjloader splits (it failed deep inside with no file named).
    const size_t cr = text.find('\r');
    if (cr != std::string::npos && cr + 1 < text.size())
      throw InputError(at(path, line),
                       "lines end with a carriage return alone (CR); convert them to LF or CR LF");
    // A comment may end a vertex or face statement (`f 1 2 3 4 # the lid`), which
    // tinyobjloader does not accept: such lines are handed to it without their comments.
    // (Names after usemtl or mtllib are left whole: they may hold a '#'.)
    const std::string statement = text.substr(0, text.find('#'));
    std::vector<std::string> fields = objFields(statement);
    const std::string keyword = fields.empty() ? "" : fields[0];
    const bool vertexOrFace = keyword == "v" || keyword == "f";
    result.hasTrailingComments = result.hasTrailingComments || (vertexOrFace && statement != text);
    result.lines.push_back(vertexOrFace ? statement : text);
    if (!vertexOrFace) fields = objFields(text);
    if (keyword == "v") {
      double c[3];
      for (int k = 0; k < 3; ++k) {
        if (k + 1 >= int(fields.size()) || !parseFiniteDouble(fields[k + 1], c[k]))
          throw InputError(at(path, line), "vertex needs 3 finite coordinates, got '" + text + "'");
      }
      result.vertices.push_back({c[0], c[1], c[2]});
      ++vertexCount;
    } else if (keyword == "f") {
      int count = 0;
      for (size_t k = 1; k < fields.size(); ++k) {
        const std::string& token = fields[k];
        const long index = std::strtol(token.c_str(), nullptr, 10);  // "i", "i/t", "i/t/n", "i//n"
        const long resolved = index < 0 ? vertexCount + index + 1 : index;
        if (index == 0 || resolved < 1 || resolved > vertexCount)
          throw InputError(at(path, line), "face refers to vertex " + std::to_string(index) +
                                               " but only " + std::to_string(vertexCount) +
                                               " vertices are defined before it");
        ++count;
      }
      if (count < 3)
        throw InputError(at(path, line),
                         "face with fewer than 3 vertices (" + std::to_string(count) + ")");
      faceLines.push_back({line, currentMaterial});
    } else if (keyword == "usemtl") {
      if (fields.size() > 1) currentMaterial = fields[1];
    } else if (keyword == "mtllib") {
      // tinyobjloader takes the rest of the line after "mtllib" and one blank.
      std::string rest = text.substr(std::min(text.size(), text.find("mtllib") + 7));
      if (!rest.empty() && rest.back() == '\r') rest.pop_back();
      result.mtllibs.push_back(mtllibFileNames(rest));
    }
  }
  return result;
}

Rgb toRgb(const tinyobj::real_t* c) {
  return {double(c[0]), double(c[1]), double(c[2])};
}

struct MtlDefinition {
  std::string name;
  std::string location;  // of the last `Kd` after its `newmtl`, else of the `newmtl`
};

// The material definitions of the MTL files tinyobjloader reads, in its order: for each `mtllib`
// statement, its first file name (relative to the OBJ's directory) that was not read before and
// opens; a name read before is skipped. Lines are classified as tinyobjloader does (leading
// blanks skipped, trailing blanks trimmed, the name is the rest of the `newmtl` line), so the
// definitions line up with its materials.
std::vector<MtlDefinition> scanMtlDefinitions(
    const std::string& objPath, const std::vector<std::vector<std::string>>& mtllibs) {
  const auto slash = objPath.find_last_of('/');
  const std::string directory = slash == std::string::npos ? "" : objPath.substr(0, slash + 1);
  std::vector<MtlDefinition> definitions;
  std::set<std::string> read;
  for (const std::vector<std::string>& names : mtllibs) {
    for (const std::string& name : names) {
      if (read.count(name)) continue;
      const std::string mtlPath = directory + name;
      std::ifstream in(mtlPath);
      if (!in) continue;
      read.insert(name);
      std::string text;
      for (int line = 1; std::getline(in, text); ++line) {
        if (!text.empty() && text.back() == '\r') text.pop_back();
        text.erase(std::min(text.size(), text.find_last_not_of(" \t") + 1));
        const size_t start = std::min(text.size(), text.find_first_not_of(" \t"));
        const auto isBlank = [&](size_t i) {
          return i < text.size() && (text[i] == ' ' || text[i] == '\t');
        };
        if (text.compare(start, 6, "newmtl") == 0 && isBlank(start + 6))
          definitions.push_back({text.substr(start + 7), at(mtlPath, line)});
        else if (text.compare(start, 2, "Kd") == 0 && isBlank(start + 2) && !definitions.empty())
          definitions.back().location = at(mtlPath, line);
        // tinyobjloader reads `Kd red` or `Ke inf` as 0: a colour (a light's channel) would vanish
        // silently. Both take one grey value or three finite numbers.
        for (const char* colour : {"Kd", "Ke"})
          if (text.compare(start, 2, colour) == 0 && isBlank(start + 2)) {
            std::istringstream values(text.substr(start + 2));
            std::string token;
            int count = 0;
            double value = 0;
            bool finite = true;
            while (values >> token) {
              ++count;
              finite = finite && parseFiniteDouble(token, value);
            }
            if (!finite || (count != 1 && count != 3))
              throw InputError(at(mtlPath, line), std::string(colour) +
                                                      " needs one or three finite numbers, got '" +
                                                      text.substr(start) + "'");
          }
      }
      break;
    }
  }
  return definitions;
}

}  // namespace

ObjMesh readObjMesh(const std::string& path) {
  const Prescan scanned = prescan(path);
  const std::vector<FaceStatement>& faceLines = scanned.faces;

  tinyobj::ObjReaderConfig config;
  config.triangulate = false;  // faces are polygons (DESIGN.md §4)
  config.vertex_color = false;
  const auto slash = path.find_last_of('/');
  config.mtl_search_path = slash == std::string::npos ? "./" : path.substr(0, slash + 1);
  tinyobj::ObjReader reader;
  // MTL files are still found beside the original (mtl_search_path above).
  std::optional<TemporaryObj> uncommented;
  if (scanned.hasTrailingComments) uncommented.emplace(scanned.lines);
  if (!reader.ParseFromFile(uncommented ? uncommented->path() : path, config)) {
    std::string error = reader.Error();
    while (!error.empty() && (error.back() == '\n' || error.back() == '.')) error.pop_back();
    throw InputError(path, "cannot parse OBJ: " + error);
  }
  // tinyobjloader reports a missing or broken MTL only as a warning; a missing material
  // definition must not silently turn into a default one.
  if (reader.Warning().find("Material file [") != std::string::npos ||
      reader.Warning().find("Failed to load material file") != std::string::npos)
    throw InputError(path, "cannot load its MTL file: " + reader.Warning());

  ObjMesh mesh;
  mesh.path = path;
  // The k-th material named N is the k-th definition named N (names may repeat).
  const std::vector<MtlDefinition> definitions = scanMtlDefinitions(path, scanned.mtllibs);
  std::map<std::string, size_t> seen;
  for (const tinyobj::material_t& m : reader.GetMaterials()) {
    std::string location = path;
    size_t k = seen[m.name]++;
    for (const MtlDefinition& definition : definitions)
      if (definition.name == m.name && k-- == 0) {
        location = definition.location;
        break;
      }
    mesh.mtlMaterials.push_back({m.name, toRgb(m.diffuse), toRgb(m.emission), location});
  }

  size_t faceIndex = 0;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    size_t offset = 0;
    for (size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f, ++faceIndex) {
      ObjFace face;
      const int n = shape.mesh.num_face_vertices[f];
      for (int k = 0; k < n; ++k) {
        const int vi = shape.mesh.indices[offset + k].vertex_index;
        // The pre-scan checked every index against its own count of vertices; should
        // tinyobjloader still count them differently, that is this file's error, not a crash.
        if (vi < 0 || size_t(vi) >= scanned.vertices.size())
          throw InputError(
              faceIndex < faceLines.size() ? at(path, faceLines[faceIndex].line) : path,
              "face refers to a vertex the OBJ reader does not have (index " +
                  std::to_string(vi + 1) + " of " + std::to_string(scanned.vertices.size()) + ")");
        face.vertices.push_back(scanned.vertices[vi]);
      }
      offset += n;
      if (faceIndex < faceLines.size()) {
        face.line = faceLines[faceIndex].line;
        face.materialName = faceLines[faceIndex].materialName;
      }
      mesh.faces.push_back(std::move(face));
    }
  }
  if (mesh.faces.size() != faceLines.size())
    throw InputError(path, "internal OBJ reader mismatch: " + std::to_string(faceLines.size()) +
                               " face lines but " + std::to_string(mesh.faces.size()) +
                               " faces parsed");
  return mesh;
}

}  // namespace penumbra
