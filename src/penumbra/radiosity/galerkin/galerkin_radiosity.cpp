// Hierarchical Galerkin radiosity: building, queries and statistics. The steps live in
// galerkin_links.cpp (link estimation), galerkin_refinement.cpp and galerkin_solve.cpp.

#include "penumbra/radiosity/galerkin/galerkin_radiosity.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>
#include <unordered_set>

#include "penumbra/base/check.h"
#include "penumbra/base/stopwatch.h"
#include "penumbra/radiosity/face_contacts.h"
#include "penumbra/radiosity/galerkin/galerkin_internals.h"
#include "penumbra/radiosity/hierarchy_building.h"
#include "penumbra/scene/scene.h"
#include "penumbra/spatial/dynamic_scene.h"
#include "penumbra/spatial/receiver_locator.h"

namespace penumbra {

namespace {

// A steep linear function dips below zero near a leaf's corner; light does not.
Rgb nonNegative(const Rgb& c) {
  return {std::max(c.r, 0.0), std::max(c.g, 0.0), std::max(c.b, 0.0)};
}

}  // namespace

GalerkinOptions galerkinOptionsFrom(const RadiosityOptions& radiosity) {
  GalerkinOptions galerkin;
  galerkin.tolerance = radiosity.tolerance;
  galerkin.maxLinks = radiosity.maxLinks;
  galerkin.maxElements = radiosity.maxElements;
  galerkin.threads = radiosity.threads;
  return galerkin;
}

GalerkinRadiosity::GalerkinRadiosity(const GalerkinOptions& options) : options_(options) {}

void GalerkinRadiosity::clear() {
  elements_.clear();
  polygonRoots_.clear();
  clusters_.clear();
  rootOrder_.clear();
  links_.clear();
  linkCount_ = 0;
  droppedPairs_ = 0;
  shaftHolders_.clear();
  lastMovedAfter_.clear();
  lastEnds_.clear();
  lastEndsOf_.clear();
  lastMovedIds_.clear();
  stats_ = {};
  invalidateSolveState();
  dropPassKeys();
}

void GalerkinRadiosity::takeScene(const DynamicScene& scene) {
  scene_ = scene.posed();
  polygonBounds_.resize(scene_.polygons.size());
  for (const WorldPolygon& polygon : scene_.polygons) polygonBounds_[polygon.id] = polygon.bounds;
  grid_ = &scene.grid();
  rays_ = &scene.rays();
}

void GalerkinRadiosity::build(const DynamicScene& scene) {
  awaitShaftWork();
  const Stopwatch total;
  clear();
  takeScene(scene);

  const std::vector<Element> roots = rootElements(scene_, polygonRoots_);
  CHECK(!roots.empty());
  contacts_ = coveringPolygons(scene_);
  double totalArea = 0, emittedPower = 0;
  elements_.reserve(roots.size() * 4);
  for (const Element& root : roots) {
    GElement e;
    e.shape = root;
    prepare(e);
    e.polygon = root.polygon;
    e.area = root.area;
    e.reflectance = root.reflectance;
    e.node.emission = root.radiometry.emission;
    elements_.push_back(e);
    totalArea += e.area;
    emittedPower += e.area * e.node.emission.maxComponent();
  }
  for (GElement& e : elements_) {
    e.cover = coverOf(e);
    e.coveredPoints = coveredPointsOf(e);
    e.exposedShare = exposedShareOf(e);
  }
  buildHierarchy(scene.scene(), roots);
  threshold_ = options_.tolerance * emittedPower;
  minArea_ = options_.minAreaFactor * options_.tolerance * totalArea;
  pullEmission({NodeRef::kCluster, 0});

  Counters counters;
  Stopwatch stage;
  auto all = std::make_shared<std::vector<PolygonId>>(scene_.polygons.size());
  for (size_t i = 0; i < all->size(); ++i) (*all)[i] = PolygonId(i);
  const NodeRef root{NodeRef::kCluster, 0};
  refine({{root, root, all, -1}}, counters);
  stats_.refineSeconds += stage.lap();
  solve(options_.convergence);
  stats_.solveSeconds += stage.lap();
  const Settling settling = settle(counters);
  stats_.refineSeconds += settling.refineSeconds;
  stats_.solveSeconds += settling.solveSeconds;
  stats_.passes = 1 + settling.passes();
  stats_.settled = settling.settled;
  storeIrradiance();
  if (settling.dropped > 0) {
    compactPairs();
    compactElements();
  }
  if (managed()) releaseShafts();  // the root pair's alone: the moves make what they need
  stats_.pointPairs = counters.pointPairs;
  stats_.visibilityRays = counters.visibilityRays;
  stats_.unoccludedLinks = counters.unoccludedLinks;
  statsCounted_ = false;
  stats_.totalSeconds = total.seconds();
}

const GalerkinStats& GalerkinRadiosity::stats() const {
  awaitShaftWork();
  if (!statsCounted_) countStats();
  return stats_;
}

void GalerkinRadiosity::countStats() const {
  statsCounted_ = true;
  stats_.elements = (long long)elements_.size();
  stats_.clusters = (long long)clusters_.size();
  stats_.leaves = stats_.activeLinks = stats_.passiveLinks = 0;
  for (const GElement& e : elements_) stats_.leaves += e.isLeaf() ? 1 : 0;
  for (const GLink& l : links_) {
    stats_.activeLinks += l.state == GLink::kActive ? 1 : 0;
    stats_.passiveLinks += l.state == GLink::kPassive ? 1 : 0;
  }
  stats_.elementBytes = elements_.capacity() * sizeof(GElement);
  stats_.clusterBytes = clusters_.capacity() * sizeof(GCluster);
  for (const GCluster& c : clusters_)
    stats_.clusterBytes += c.structure.children.capacity() * sizeof(NodeRef);
  stats_.linkBytes = links_.capacity() * sizeof(GLink);
  stats_.solveBytes = solveStateBytes();
  countShafts();
}

void GalerkinRadiosity::buildHierarchy(const Scene& scene, const std::vector<Element>& roots) {
  // The static scene's roots sit at their centroids; a moving object's at its polygons' vertex
  // means in object coordinates, which no pose changes.
  std::vector<std::vector<int>> groups(1);
  std::vector<int> groupOfObject(scene.objects.size(), 0);
  for (size_t o = 0; o < scene.objects.size(); ++o)
    if (scene.objects[o].isDynamic()) {
      groupOfObject[o] = int(groups.size());
      groups.emplace_back();
    }
  std::vector<Vec3> keys(roots.size());
  for (size_t i = 0; i < roots.size(); ++i) {
    const WorldPolygon& polygon = scene_.polygons[roots[i].polygon];
    const int object = polygon.objectIndex;
    groups[groupOfObject[object]].push_back(int(i));
    if (groupOfObject[object] == 0) {
      keys[i] = roots[i].centroid();
      continue;
    }
    const Polygon3& local =
        scene.objects[object].polygons[polygon.id - scene_.objectFirstPolygon[object]];
    Vec3 sum;
    for (const Vec3& v : local) sum = sum + v;
    keys[i] = sum / double(local.size());
  }
  ClusterHierarchy hierarchy = groups.size() == 1 ? buildClusterHierarchy(roots)
                                                  : buildClusterHierarchy(roots, groups, keys);
  rootOrder_ = std::move(hierarchy.rootOrder);
  clusters_.resize(hierarchy.clusters.size());
  for (size_t i = 0; i < clusters_.size(); ++i)
    clusters_[i].structure = std::move(hierarchy.clusters[i]);
}

void GalerkinRadiosity::prepare(GElement& e) {
  e.basis = LinearBasis(e.shape);
  e.cubature = linkCubature(e.shape);
  for (int i = 0; i < e.cubature.count; ++i) e.cubatureBasis[i] = e.basis.at(e.cubature.points[i]);
}

bool GalerkinRadiosity::isCovered(PolygonId polygon, const Vec3& x) const {
  for (PolygonId partner : contacts_[polygon])
    for (int root : polygonRoots_[partner])
      if (elements_[root].shape.insideness(x) > 0) return true;
  return false;
}

namespace {

// Do two convex shapes of one plane overlap with positive area? Separating axes: the edges'
// in-plane normals of both; shapes that only touch along an edge or at a corner do not.
bool overlapInPlane(const ElementShape& a, const ElementShape& b, double slack) {
  for (const ElementShape* shape : {&a, &b})
    for (int i = 0; i < shape->vertexCount; ++i) {
      const Vec3 edge = shape->vertices[(i + 1) % shape->vertexCount] - shape->vertices[i];
      const Vec3 axis = cross(shape->normal, edge);
      const double axisLength = length(axis);
      if (!(axisLength > 0)) continue;
      const auto extent = [&](const ElementShape& s) {
        double low = INFINITY, high = -INFINITY;
        for (int k = 0; k < s.vertexCount; ++k) {
          const double t = dot(s.vertices[k], axis) / axisLength;
          low = std::min(low, t);
          high = std::max(high, t);
        }
        return std::pair{low, high};
      };
      const auto [lowA, highA] = extent(a);
      const auto [lowB, highB] = extent(b);
      if (highA <= lowB + slack || highB <= lowA + slack) return false;
    }
  return true;
}

}  // namespace

// Exposed only where no polygon in contact overlaps the element at all, so that an element's
// children may take its cover without looking (freshCover): judged at a few points, the floor
// under a sofa standing clear of the floor's Gauss points read exposed down to its leaves, and
// there the furnace lost 9% of its energy. Covered where its centroid, its cubature points and
// its corners all are.
GalerkinRadiosity::GElement::Cover GalerkinRadiosity::coverOf(const GElement& e) const {
  if (contacts_[e.polygon].empty()) return GElement::kExposed;
  const double slack = 1e-9 * std::max(1.0, scene_.extent.diagonalLength());
  bool overlapped = false;
  for (PolygonId partner : contacts_[e.polygon])
    for (int root : polygonRoots_[partner])
      overlapped = overlapped || overlapInPlane(e.shape, elements_[root].shape, slack);
  if (!overlapped) return GElement::kExposed;
  const Cubature& rule = e.cubature;
  bool covered = isCovered(e.polygon, e.shape.centroid());
  for (int i = 0; i < rule.count && covered; ++i) covered = isCovered(e.polygon, rule.points[i]);
  for (int k = 0; k < e.shape.vertexCount && covered; ++k) {
    double inside = -INFINITY;
    for (PolygonId partner : contacts_[e.polygon])
      for (int root : polygonRoots_[partner])
        inside = std::max(inside, elements_[root].shape.insideness(e.shape.vertices[k]));
    covered = inside >= -slack;
  }
  return covered ? GElement::kCovered : GElement::kPartlyCovered;
}

float GalerkinRadiosity::exposedShareOf(const GElement& e) const {
  if (e.cover != GElement::kPartlyCovered) return e.cover == GElement::kCovered ? 0.0f : 1.0f;
  constexpr int kSide = 8;
  int open = 0;
  for (int i = 0; i < kSide; ++i)
    for (int j = 0; j < kSide; ++j)
      open +=
          isCovered(e.polygon, e.shape.samplePoint((i + 0.5) / kSide, (j + 0.5) / kSide)) ? 0 : 1;
  return float(open) / float(kSide * kSide);
}

std::uint8_t GalerkinRadiosity::coveredPointsOf(const GElement& e) const {
  if (e.cover != GElement::kPartlyCovered) return 0;
  std::uint8_t covered = 0;
  for (int i = 0; i < e.cubature.count; ++i)
    if (isCovered(e.polygon, e.cubature.points[i])) covered |= std::uint8_t(1u << i);
  return covered;
}

GalerkinRadiosity::GElement::Cover GalerkinRadiosity::freshCover(const GElement& e) const {
  if (e.parent < 0) return coverOf(e);
  const GElement::Cover parent = elements_[e.parent].cover;
  return parent == GElement::kPartlyCovered ? coverOf(e) : parent;
}

std::optional<int> GalerkinRadiosity::leafContaining(const Vec3& point, const Vec3& normal) const {
  if (elements_.empty() || !grid_) return std::nullopt;
  const auto receiver = locateReceiver(scene_, *grid_, point, normal);
  if (!receiver) return std::nullopt;
  // The locator may have found a polygon under another lying on it facing the same way.
  const PolygonId polygon = polygonOnTop(scene_, contacts_, receiver->polygon, [&](PolygonId p) {
    return std::any_of(polygonRoots_[p].begin(), polygonRoots_[p].end(),
                       [&](int root) { return elements_[root].shape.insideness(point) > 0; });
  });
  if (polygonRoots_[polygon].empty()) return std::nullopt;
  const auto& roots = polygonRoots_[polygon];
  int id = roots[0];
  for (int root : roots)
    if (elements_[root].shape.insideness(point) > elements_[id].shape.insideness(point)) id = root;
  while (!elements_[id].isLeaf())
    id = elements_[id].firstChild + elements_[id].shape.childContaining(point);
  return id;
}

std::optional<RadiositySample> GalerkinRadiosity::sample(const Vec3& point,
                                                         const Vec3& normal) const {
  const std::optional<int> leaf = leafContaining(point, normal);
  if (!leaf) return std::nullopt;
  const GElement& e = elements_[*leaf];
  // A point under a polygon lying on it face to face receives nothing (it reflects nothing and
  // emits what it emits), wherever the linear function of its partly covered leaf, fitted over
  // the leaf's open part too, would say otherwise: the floor under the chair room's sofa read
  // 0.09-0.87 at tolerance 3e-3.
  if (e.cover != GElement::kExposed && isCovered(e.polygon, point))
    return RadiositySample{Rgb{}, Rgb{}, e.node.emission};
  return RadiositySample{nonNegative(e.basis.evaluate(e.node.irradianceDirect, point)),
                         nonNegative(e.basis.evaluate(e.node.irradianceIndirect, point)),
                         nonNegative(e.basis.evaluate(e.node.radiosity, point))};
}

Rgb GalerkinRadiosity::irradiance(const Vec3& point, const Vec3& normal) const {
  const auto s = sample(point, normal);
  return s ? s->total() : Rgb{};
}

RadiosityMesh GalerkinRadiosity::leafMesh() const {
  // Corners shared by leaves of one polygon take the area-weighted mean of the leaves' values
  // there: the functions are discontinuous across leaves, and drawn as they are every leaf's
  // edge shows as a seam.
  RadiosityMesh mesh;
  std::map<std::tuple<PolygonId, double, double, double>, std::uint32_t> corners;
  std::vector<double> weights;
  for (const GElement& e : elements_) {
    if (!e.isLeaf() || e.cover == GElement::kCovered) continue;
    std::array<std::uint32_t, 4> index{};
    for (int i = 0; i < e.shape.vertexCount; ++i) {
      const Vec3& x = e.shape.vertices[i];
      const auto [at, inserted] =
          corners.try_emplace({e.polygon, x.x, x.y, x.z}, std::uint32_t(mesh.positions.size()));
      if (inserted) {
        mesh.positions.push_back(x);
        mesh.normals.push_back(e.shape.normal);
        mesh.polygons.push_back(e.polygon);
        mesh.radiosity.emplace_back();
        mesh.directIrradiance.emplace_back();
        mesh.indirectIrradiance.emplace_back();
        weights.push_back(0);
      }
      const std::uint32_t v = index[i] = at->second;
      mesh.radiosity[v] += e.basis.evaluate(e.node.radiosity, x) * e.area;
      mesh.directIrradiance[v] += e.basis.evaluate(e.node.irradianceDirect, x) * e.area;
      mesh.indirectIrradiance[v] += e.basis.evaluate(e.node.irradianceIndirect, x) * e.area;
      weights[v] += e.area;
    }
    mesh.indices.insert(mesh.indices.end(), {index[0], index[1], index[2]});
    if (e.shape.vertexCount == 4)
      mesh.indices.insert(mesh.indices.end(), {index[0], index[2], index[3]});
  }
  for (size_t v = 0; v < weights.size(); ++v) {
    mesh.radiosity[v] = nonNegative(mesh.radiosity[v] / weights[v]);
    mesh.directIrradiance[v] = nonNegative(mesh.directIrradiance[v] / weights[v]);
    mesh.indirectIrradiance[v] = nonNegative(mesh.indirectIrradiance[v] / weights[v]);
  }
  return mesh;
}

Rgb GalerkinRadiosity::emittedPower() const {
  Rgb power;
  for (const GElement& e : elements_)
    if (e.parent < 0) power += e.node.emission * (e.area * e.exposedShare);
  return power;
}

Rgb GalerkinRadiosity::absorbedPower() const {
  Rgb power;
  for (const GElement& e : elements_) {
    if (!e.isLeaf()) continue;
    const Rgb irradiance = e.node.irradianceDirect[0] + e.node.irradianceIndirect[0];
    power += (Rgb::gray(1) - e.reflectance) * irradiance * e.area;
  }
  return power;
}

// Node accessors.

GalerkinRadiosity::Node& GalerkinRadiosity::nodeOf(NodeRef n) {
  return n.isCluster() ? clusters_[n.index].node : elements_[n.index].node;
}
const GalerkinRadiosity::Node& GalerkinRadiosity::nodeOf(NodeRef n) const {
  return n.isCluster() ? clusters_[n.index].node : elements_[n.index].node;
}
Box3 GalerkinRadiosity::bounds(NodeRef n) const {
  return n.isCluster() ? clusters_[n.index].structure.bounds : elements_[n.index].shape.bounds();
}
double GalerkinRadiosity::area(NodeRef n) const {
  return n.isCluster() ? clusters_[n.index].structure.area : elements_[n.index].area;
}
double GalerkinRadiosity::size(NodeRef n) const {
  return bounds(n).diagonalLength();
}

}  // namespace penumbra
