// Hierarchical radiosity with clustering.
//  - Hanrahan, Salzman & Aupperle 1991, "A rapid hierarchical radiosity algorithm": element
//    quadtrees, links, the BF refinement oracle, gathering and push-pull.
//  - Smits, Arvo & Greenberg 1994, "A clustering algorithm for radiosity in complex environments";
//    Sillion 1995, "A unified hierarchical algorithm for global illumination with scattering
//    volumes and object clusters": a volume cluster hierarchy above the polygons, a single root,
//    links between clusters and elements, irradiance received by a cluster pushed to its contents.
//  - Haines & Wallace 1991, "Shaft culling for efficient ray-traced radiosity": each link's shaft.
//  - Drettakis & Sillion 1997, "Interactive update of global illumination using a line-space
//    hierarchy": refined links are kept as passive links with their estimates and children.
//
// This file: building and statistics; the steps live in hierarchy_building.cpp,
// link_estimation.cpp, refinement.cpp, gathering.cpp, push_pull.cpp and solution_mesh.cpp.

#include "penumbra/radiosity/radiosity_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "penumbra/base/check.h"
#include "penumbra/base/input_error.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/radiosity/face_contacts.h"
#include "penumbra/radiosity/hierarchy_building.h"
#include "penumbra/scene/closedness.h"
#include "penumbra/spatial/dynamic_scene.h"
#include "penumbra/spatial/ray_caster.h"
#include "penumbra/spatial/uniform_grid.h"

namespace penumbra {

namespace {

double elapsedSeconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

}  // namespace

RadiositySolver::RadiositySolver(const RadiosityOptions& options) : options_(options) {}
RadiositySolver::~RadiositySolver() = default;

void RadiositySolver::clear() {
  elements_.clear();
  polygonRoots_.clear();
  contacts_.clear();
  rootOrder_.clear();
  rootCumulativeArea_.clear();
  clusters_.clear();
  links_.clear();
  shafts_.clear();
  leafVertices_.clear();
  gatherIndex_ = {};
  exposedReflected_.clear();
  coveredReflected_.clear();
  cellReflected_.clear();
  mesh_ = {};
  stats_ = {};
}

void RadiositySolver::build(const Scene& scene, double frame) {
  ownedScene_ = std::make_unique<DynamicScene>(scene, frame);
  build(*ownedScene_);
}

void RadiositySolver::build(const PosedScene& scene) {
  ownedScene_ = std::make_unique<DynamicScene>(scene);
  build(*ownedScene_);
}

void RadiositySolver::refuseLosslessClosedScene(const DynamicScene& scene) {
  // Reflectance 1 is legal (direct light does not care), but where every polygon of a closed
  // scene reflects all of a channel, no light of that channel ever leaves: B grows without bound
  // and no solver converges. Say so instead of printing whatever the last iteration reached.
  const PosedScene& posed = scene.posed();
  for (double Rgb::*channel : {&Rgb::r, &Rgb::g, &Rgb::b}) {
    bool lossless = !posed.polygons.empty();
    for (const WorldPolygon& p : posed.polygons)
      lossless = lossless && posed.materialOf(p).reflectance.*channel >= 1;
    if (!lossless || !checkClosedness(scene.scene(), posed).isSceneClosed) continue;
    const char* name = channel == &Rgb::r ? "red" : channel == &Rgb::g ? "green" : "blue";
    throw InputError(scene.scene().sourcePath,
                     std::string("radiosity cannot converge: the scene is closed and every "
                                 "polygon reflects all of the ") +
                         name +
                         " light it receives (reflectance 1), so that light never leaves; give "
                         "some surface a reflectance below 1");
  }
}

void RadiositySolver::update(const DynamicScene& scene, const SceneChange&) {
  build(scene);
}

void RadiositySolver::build(const DynamicScene& scene) {
  refuseLosslessClosedScene(scene);
  clear();
  scene_ = scene.posed();
  grid_ = &scene.grid();
  rays_ = &scene.rays();
  compute();
}

void RadiositySolver::compute() {
  const auto start = std::chrono::steady_clock::now();
  visibleParts_ = std::make_unique<ExactReference>(scene_, grid_);
  elements_ = rootElements(scene_, polygonRoots_);
  contacts_ = coveringPolygons(scene_);
  CHECK(!elements_.empty());
  ClusterHierarchy hierarchy = buildClusterHierarchy(elements_);
  rootOrder_ = std::move(hierarchy.rootOrder);
  clusters_.resize(hierarchy.clusters.size());
  for (size_t i = 0; i < clusters_.size(); ++i)
    static_cast<ClusterNode&>(clusters_[i]) = std::move(hierarchy.clusters[i]);
  rootCumulativeArea_.assign(rootOrder_.size() + 1, 0);
  for (size_t i = 0; i < rootOrder_.size(); ++i)
    rootCumulativeArea_[i + 1] = rootCumulativeArea_[i] + elements_[rootOrder_[i]].area;

  double totalArea = 0;
  totalPower_ = 0;
  for (const Element& e : elements_) {
    totalArea += e.area;
    totalPower_ += e.area * e.radiometry.emission.maxComponent();
  }
  referenceArea_ = options_.irradianceFactor > 0 ? totalArea / options_.irradianceFactor : 0;
  minArea_ = options_.minElementArea > 0 ? options_.minElementArea
                                         : options_.minAreaFactor * options_.tolerance * totalArea;
  pullEmission({NodeRef::kCluster, 0});

  // The root self-link: every interaction of the scene starts as this one link and is refined.
  Link rootLink;
  rootLink.receiver = rootLink.source = {NodeRef::kCluster, 0};
  addLink(rootLink, linkShaft(rootLink.receiver, rootLink.source));
  for (int pass = 0; pass < std::max(1, options_.refinementPasses); ++pass) {
    const auto refineStart = std::chrono::steady_clock::now();
    bool refined = refineActiveLinks();
    refined = refineReceivers() || refined;
    stats_.refineSeconds += elapsedSeconds(refineStart);
    if (!refined && pass > 0) break;
    const auto solveStart = std::chrono::steady_clock::now();
    solve();
    stats_.solveSeconds += elapsedSeconds(solveStart);
  }
  pointTransfers_ = {};
  const auto gatherStart = std::chrono::steady_clock::now();
  if (options_.finalGather) {
    finalGather();
  } else {
    for (Element& e : elements_) {
      e.radiometry.finalDirect = e.radiometry.irradianceDirect;
      e.radiometry.finalIndirect = e.radiometry.irradianceIndirect;
    }
  }
  stats_.finalGatherSeconds = elapsedSeconds(gatherStart);
  buildMesh();
  computeStats();
  stats_.totalSeconds = elapsedSeconds(start);
}

bool RadiositySolver::isCovered(PolygonId polygon, const Vec3& x) const {
  for (PolygonId partner : contacts_[polygon])
    for (int root : polygonRoots_[partner])
      if (elements_[root].insideness(x) > 0) return true;
  return false;
}

bool RadiositySolver::isVisible(PolygonId p, const Vec3& x, PolygonId q, const Vec3& y) const {
  return !isCovered(p, x) && !isCovered(q, y) && !rays_->isOccluded(x, y);
}

NodeRadiometry& RadiositySolver::radiometry(NodeRef n) {
  return n.isCluster() ? clusters_[n.index].radiometry : elements_[n.index].radiometry;
}
const NodeRadiometry& RadiositySolver::radiometry(NodeRef n) const {
  return n.isCluster() ? clusters_[n.index].radiometry : elements_[n.index].radiometry;
}
Box3 RadiositySolver::bounds(NodeRef n) const {
  return n.isCluster() ? clusters_[n.index].bounds : elements_[n.index].bounds();
}
double RadiositySolver::area(NodeRef n) const {
  return n.isCluster() ? clusters_[n.index].area : elements_[n.index].area;
}
double RadiositySolver::size(NodeRef n) const {
  return bounds(n).diagonalLength();
}

bool RadiositySolver::canSplit(NodeRef n) const {
  if (n.isCluster()) return true;
  return elements_[n.index].area > minArea_;
}

InputError RadiositySolver::budgetExceeded(const char* what, long long limit) const {
  std::ostringstream problem;
  problem << "refining to tolerance " << options_.tolerance << " needs more than " << limit << " "
          << what << " (the solver's budget: --max-" << what
          << "); use a larger tolerance or raise the budget";
  return InputError("--tolerance", problem.str());
}

std::vector<NodeRef> RadiositySolver::split(NodeRef n) {
  if (n.isCluster()) return clusters_[n.index].children;
  if (elements_[n.index].isLeaf()) {
    if ((long long)elements_.size() + 4 > options_.maxElements)
      throw budgetExceeded("elements", options_.maxElements);
    const Element parent = elements_[n.index];
    const int first = int(elements_.size());
    const auto loops = parent.childVertices();
    for (int k = 0; k < 4; ++k) {
      Element child;
      child.vertices = loops[k];
      child.vertexCount = parent.vertexCount;
      child.depth = std::uint8_t(parent.depth + 1);
      child.polygon = parent.polygon;
      child.parent = n.index;
      child.normal = parent.normal;
      child.area = elementArea(child.vertices, child.vertexCount);
      child.reflectance = parent.reflectance;
      child.radiometry = parent.radiometry;
      child.radiometry.gatheredDirect = child.radiometry.gatheredIndirect = Rgb{};
      elements_.push_back(child);
    }
    elements_[n.index].firstChild = first;
  }
  const int first = elements_[n.index].firstChild;
  return {{NodeRef::kElement, first},
          {NodeRef::kElement, first + 1},
          {NodeRef::kElement, first + 2},
          {NodeRef::kElement, first + 3}};
}

bool RadiositySolver::isBehind(NodeRef n, const Element& element) const {
  // Relative slack so that a polygon touching the element's plane (a wall meeting the floor)
  // counts as behind it: it can exchange no energy with the plane's front side. Except what lies
  // in the plane facing back at it in contact (coveringPolygons): surfaces in contact face to face
  // exchange all their energy where they overlap (the limit as the gap closes), so such a node is
  // not behind. The other side of a sheet (a two-sided card) is: it faces away.
  const Plane plane = Plane::fromPointNormal(element.vertices[0], element.normal);
  const double slack = 1e-9 * std::max(1.0, scene_.extent.diagonalLength());
  bool inPlane = true;
  if (n.isCluster()) {
    const Box3 b = clusters_[n.index].bounds;
    bool touches = false;
    for (int corner = 0; corner < 8; ++corner) {
      const Vec3 p{corner & 1 ? b.max.x : b.min.x, corner & 2 ? b.max.y : b.min.y,
                   corner & 4 ? b.max.z : b.min.z};
      const double d = plane.signedDistance(p);
      if (d > slack) return false;
      touches = touches || d >= -slack;
    }
    return !touches;  // a cluster touching the plane may hold elements lying in it facing back
  }
  const Element& e = elements_[n.index];
  for (int i = 0; i < e.vertexCount; ++i) {
    const double d = plane.signedDistance(e.vertices[i]);
    if (d > slack) return false;
    inPlane = inPlane && d >= -slack;
  }
  const std::vector<PolygonId>& partners = contacts_[element.polygon];
  return !(inPlane && dot(e.normal, plane.normal) < -1 + 1e-9 &&
           std::find(partners.begin(), partners.end(), e.polygon) != partners.end());
}

RadiositySolver::SurfacePoint RadiositySolver::samplePoint(NodeRef n, double u, double v,
                                                           double w) const {
  if (!n.isCluster()) {
    const Element& e = elements_[n.index];
    return {e.samplePoint(u, v), e.normal, e.polygon};
  }
  // A root element chosen in proportion to its area, then a uniform point on it.
  const Cluster& c = clusters_[n.index];
  const double lo = rootCumulativeArea_[c.elementBegin], hi = rootCumulativeArea_[c.elementEnd];
  const double target = lo + w * (hi - lo);
  auto it = std::upper_bound(rootCumulativeArea_.begin() + c.elementBegin + 1,
                             rootCumulativeArea_.begin() + c.elementEnd + 1, target);
  const int k = std::min(int(it - rootCumulativeArea_.begin()) - 1, c.elementEnd - 1);
  const Element& e = elements_[rootOrder_[k]];
  return {e.samplePoint(u, v), e.normal, e.polygon};
}

Rgb RadiositySolver::emittedPower() const {
  Rgb power;
  for (const Element& e : elements_)
    if (e.parent < 0) power += e.radiometry.emission * e.area;
  return power;
}

Rgb RadiositySolver::absorbedPower() const {
  Rgb power;
  for (const Element& e : elements_)
    if (e.isLeaf()) {
      const Rgb absorptance{1 - e.reflectance.r, 1 - e.reflectance.g, 1 - e.reflectance.b};
      power += absorptance * (e.radiometry.finalDirect + e.radiometry.finalIndirect) * e.area;
    }
  return power;
}

void RadiositySolver::computeStats() {
  stats_.clusters = (long long)clusters_.size();
  stats_.elements = (long long)elements_.size();
  stats_.leaves = 0;
  for (const Element& e : elements_) stats_.leaves += e.isLeaf() ? 1 : 0;
  stats_.links = (long long)links_.size();
  stats_.activeLinks = stats_.passiveLinks = 0;
  stats_.activeLinkBytes = stats_.passiveLinkBytes = 0;
  for (const Link& link : links_) {
    const std::size_t bytes = sizeof(Link) + link.children.capacity() * sizeof(int) +
                              link.sourceShares.capacity() * sizeof(float) +
                              link.pointVisibleTransfers.capacity() * sizeof(float);
    if (link.active) {
      ++stats_.activeLinks;
      stats_.activeLinkBytes += bytes;
    } else {
      ++stats_.passiveLinks;
      stats_.passiveLinkBytes += bytes;
    }
  }
  stats_.shafts = (long long)shafts_.size();
  stats_.polygonShafts = 0;
  for (const Shaft& shaft : shafts_) stats_.polygonShafts += shaft.isPolygonShaft() ? 1 : 0;
  stats_.shaftBytes = shafts_.capacity() * sizeof(Shaft);
  stats_.elementBytes =
      elements_.capacity() * sizeof(Element) + leafVertices_.capacity() * sizeof(leafVertices_[0]) +
      rootOrder_.capacity() * sizeof(int) + rootCumulativeArea_.capacity() * sizeof(double);
  for (const auto& roots : polygonRoots_) stats_.elementBytes += roots.capacity() * sizeof(int);
  stats_.clusterBytes = clusters_.capacity() * sizeof(Cluster);
  for (const Cluster& c : clusters_) stats_.clusterBytes += c.children.capacity() * sizeof(NodeRef);
  stats_.meshBytes = mesh_.positions.capacity() * (2 * sizeof(Vec3) + 3 * sizeof(Rgb)) +
                     mesh_.polygons.capacity() * sizeof(PolygonId) +
                     mesh_.indices.capacity() * sizeof(std::uint32_t);
  stats_.finalBytes =
      (exposedReflected_.capacity() + coveredReflected_.capacity() + cellReflected_.capacity()) *
      sizeof(Rgb);
  const GatherIndex& g = gatherIndex_;
  for (const auto* lists : {&g.elementLinks, &g.clusterLinks}) {
    stats_.finalBytes += lists->capacity() * sizeof(std::vector<int>);
    for (const std::vector<int>& links : *lists)
      stats_.finalBytes += links.capacity() * sizeof(int);
  }
  stats_.finalBytes += (g.parentCluster.capacity() + g.rootCluster.capacity()) * sizeof(int);
}

}  // namespace penumbra
