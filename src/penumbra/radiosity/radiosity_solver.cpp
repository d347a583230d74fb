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
// Form factors. Between two elements the transfer is the receiver-area mean of the exact
// point-to-polygon form factor (Lambert's formula on the source clipped to the receiver point's
// front half-space) at the centroids of the receiver's four children: exact per point, so the
// sum over the sources seen from a point is 1 in a closed scene up to visibility. When a cluster
// is involved the transfer is a Monte Carlo estimate over area-uniform point pairs of
// cos⁺ cos⁺ / (π r² + A_s / N) (the disk regularisation keeps it bounded), with each pair's ray
// giving the visibility, so form factor and visibility use the same pairs.

#include "penumbra/radiosity/radiosity_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <numbers>
#include <unordered_map>

#include "penumbra/base/check.h"
#include "penumbra/geometry/triangulation.h"
#include "penumbra/lighting/form_factor.h"
#include "penumbra/spatial/ray_caster.h"
#include "penumbra/spatial/receiver_locator.h"
#include "penumbra/spatial/uniform_grid.h"

namespace penumbra {

namespace {

constexpr int kMaxElementsPerLeafCluster = 4;
constexpr int kMaxClusterDepth = 24;

// SplitMix64 (Steele, Lea & Flood 2014): a tiny seeded generator; one per link keeps the
// estimates independent of the order links are refined in.
class SplitMix {
 public:
  explicit SplitMix(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  double uniform() { return double(next() >> 11) * 0x1.0p-53; }

 private:
  std::uint64_t state_;
};

std::uint64_t linkSeed(std::uint64_t seed, NodeRef r, NodeRef s) {
  SplitMix mix(seed ^ (std::uint64_t(r.index) << 1 | r.kind) * 0x100000001b3ull ^
               (std::uint64_t(s.index) << 33 | std::uint64_t(s.kind) << 32));
  mix.next();
  return mix.next();
}

double elapsedSeconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

bool isConvexQuad(const Polygon3& q, const Vec3& normal) {
  for (int i = 0; i < 4; ++i)
    if (dot(cross(q[(i + 1) % 4] - q[i], q[(i + 2) % 4] - q[(i + 1) % 4]), normal) <= 0)
      return false;
  return true;
}

Polygon3 loopOf(const Element& e) {
  return Polygon3(e.vertices.begin(), e.vertices.begin() + e.vertexCount);
}

// Form factor from the point x (normal n) to the front side of element s.
double pointToElement(const Vec3& x, const Vec3& n, const Element& s) {
  if (dot(s.normal, x - s.vertices[0]) <= 0) return 0;  // x behind the source: it emits forward
  const Polygon3 clipped = clipByPlane(loopOf(s), Plane::fromPointNormal(x, n));
  if (clipped.size() < 3) return 0;
  return std::max(0.0, pointToPolygonFormFactor(x, n, clipped));
}

}  // namespace

RadiositySolver::RadiositySolver(const RadiosityOptions& options) : options_(options) {}
RadiositySolver::~RadiositySolver() = default;

void RadiositySolver::clear() {
  elements_.clear();
  polygonRoots_.clear();
  rootOrder_.clear();
  rootCumulativeArea_.clear();
  clusters_.clear();
  links_.clear();
  shafts_.clear();
  leafVertices_.clear();
  mesh_ = {};
  stats_ = {};
}

void RadiositySolver::build(const Scene& scene, double frame) {
  build(poseAt(scene, frame));
}

void RadiositySolver::update(const Scene& scene, double newFrame) {
  build(scene, newFrame);
}

void RadiositySolver::build(const PosedScene& scene) {
  const auto start = std::chrono::steady_clock::now();
  clear();
  scene_ = scene;
  grid_ = std::make_unique<UniformGrid>(scene_);
  rays_ = std::make_unique<RayCaster>(scene_);
  buildElements();
  CHECK(!elements_.empty());
  rootOrder_.resize(elements_.size());
  for (size_t i = 0; i < elements_.size(); ++i) rootOrder_[i] = int(i);
  clusters_.reserve(elements_.size());
  buildCluster(0, int(rootOrder_.size()), 0);
  rootCumulativeArea_.assign(rootOrder_.size() + 1, 0);
  for (size_t i = 0; i < rootOrder_.size(); ++i)
    rootCumulativeArea_[i + 1] = rootCumulativeArea_[i] + elements_[rootOrder_[i]].area;

  double totalArea = 0;
  totalPower_ = 0;
  for (const Element& e : elements_) {
    totalArea += e.area;
    totalPower_ += e.area * e.radiometry.emission.maxComponent();
  }
  minArea_ = options_.minElementArea > 0 ? options_.minElementArea
                                         : options_.minAreaFactor * options_.tolerance * totalArea;
  pullEmission({NodeRef::kCluster, 0});

  // The root self-link: every interaction of the scene starts as this one link and is refined.
  addLink({NodeRef::kCluster, 0}, {NodeRef::kCluster, 0}, false);
  for (int pass = 0; pass < std::max(1, options_.refinementPasses); ++pass) {
    const auto refineStart = std::chrono::steady_clock::now();
    const bool refined = refineActiveLinks();
    stats_.refineSeconds += elapsedSeconds(refineStart);
    if (!refined && pass > 0) break;
    const auto solveStart = std::chrono::steady_clock::now();
    solve();
    stats_.solveSeconds += elapsedSeconds(solveStart);
  }
  buildMesh();
  computeStats();
  stats_.totalSeconds = elapsedSeconds(start);
}

void RadiositySolver::buildElements() {
  polygonRoots_.assign(scene_.polygons.size(), {});
  for (const WorldPolygon& polygon : scene_.polygons) {
    const Material& material = scene_.materialOf(polygon);
    const Polygon3 loop = withoutRepeatedVertices(polygon.vertices);
    if (loop.size() < 3 || polygon.area <= 0) continue;
    std::vector<std::array<Vec3, 4>> pieces;
    std::vector<int> counts;
    if (loop.size() == 3 || (loop.size() == 4 && isConvexQuad(loop, polygon.plane.normal))) {
      std::array<Vec3, 4> v{};
      std::copy(loop.begin(), loop.end(), v.begin());
      pieces.push_back(v);
      counts.push_back(int(loop.size()));
    } else {
      for (const auto& t : triangulate(loop)) {
        pieces.push_back({loop[t[0]], loop[t[1]], loop[t[2]], {}});
        counts.push_back(3);
      }
    }
    for (size_t k = 0; k < pieces.size(); ++k) {
      Element e;
      e.vertices = pieces[k];
      e.vertexCount = std::uint8_t(counts[k]);
      e.polygon = polygon.id;
      e.normal = polygon.plane.normal;
      e.area = elementArea(e.vertices, e.vertexCount);
      if (e.area <= 0) continue;
      e.reflectance = material.reflectance;
      e.radiometry.emission = material.emission;
      polygonRoots_[polygon.id].push_back(int(elements_.size()));
      elements_.push_back(e);
    }
  }
}

// Volume clustering (Sillion 1995): the box of the element centroids is cut into octants
// recursively; an octant with one element contributes that element directly.
int RadiositySolver::buildCluster(int begin, int end, int depth) {
  const int index = int(clusters_.size());
  clusters_.emplace_back();
  Cluster cluster;
  cluster.elementBegin = begin;
  cluster.elementEnd = end;
  Box3 centroids;
  for (int i = begin; i < end; ++i) {
    const Element& e = elements_[rootOrder_[i]];
    cluster.bounds.extend(e.bounds());
    cluster.area += e.area;
    centroids.extend(e.centroid());
  }
  const bool isSmall = end - begin <= kMaxElementsPerLeafCluster || depth >= kMaxClusterDepth ||
                       centroids.diagonalLength() == 0;
  if (isSmall) {
    for (int i = begin; i < end; ++i)
      cluster.children.push_back({NodeRef::kElement, rootOrder_[i]});
  } else {
    const Vec3 mid = centroids.center();
    const auto octant = [&](int element) {
      const Vec3 c = elements_[element].centroid();
      return (c.x > mid.x ? 1 : 0) | (c.y > mid.y ? 2 : 0) | (c.z > mid.z ? 4 : 0);
    };
    std::stable_sort(rootOrder_.begin() + begin, rootOrder_.begin() + end,
                     [&](int a, int b) { return octant(a) < octant(b); });
    int first = begin;
    while (first < end) {
      int last = first + 1;
      while (last < end && octant(rootOrder_[last]) == octant(rootOrder_[first])) ++last;
      if (last - first == 1)
        cluster.children.push_back({NodeRef::kElement, rootOrder_[first]});
      else if (first == begin && last == end)  // one octant holds all: stop here
        for (int i = begin; i < end; ++i)
          cluster.children.push_back({NodeRef::kElement, rootOrder_[i]});
      else
        cluster.children.push_back({NodeRef::kCluster, buildCluster(first, last, depth + 1)});
      first = last;
    }
  }
  clusters_[index] = std::move(cluster);
  return index;
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

std::vector<NodeRef> RadiositySolver::split(NodeRef n) {
  if (n.isCluster()) return clusters_[n.index].children;
  if (elements_[n.index].isLeaf()) {
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

bool RadiositySolver::isBehind(NodeRef n, const Plane& plane) const {
  // Relative slack so that a polygon touching the plane (a wall meeting the floor) counts as
  // behind it: it can exchange no energy with the plane's front side.
  const double slack = 1e-9 * std::max(1.0, scene_.bounds.diagonalLength());
  if (n.isCluster()) {
    const Box3 b = clusters_[n.index].bounds;
    for (int corner = 0; corner < 8; ++corner) {
      const Vec3 p{corner & 1 ? b.max.x : b.min.x, corner & 2 ? b.max.y : b.min.y,
                   corner & 4 ? b.max.z : b.min.z};
      if (plane.signedDistance(p) > slack) return false;
    }
    return true;
  }
  const Element& e = elements_[n.index];
  for (int i = 0; i < e.vertexCount; ++i)
    if (plane.signedDistance(e.vertices[i]) > slack) return false;
  return true;
}

RadiositySolver::SurfacePoint RadiositySolver::samplePoint(NodeRef n, double u, double v,
                                                           double w) const {
  if (!n.isCluster()) {
    const Element& e = elements_[n.index];
    return {e.samplePoint(u, v), e.normal};
  }
  // A root element chosen in proportion to its area, then a uniform point on it.
  const Cluster& c = clusters_[n.index];
  const double lo = rootCumulativeArea_[c.elementBegin], hi = rootCumulativeArea_[c.elementEnd];
  const double target = lo + w * (hi - lo);
  auto it = std::upper_bound(rootCumulativeArea_.begin() + c.elementBegin + 1,
                             rootCumulativeArea_.begin() + c.elementEnd + 1, target);
  const int k = std::min(int(it - rootCumulativeArea_.begin()) - 1, c.elementEnd - 1);
  const Element& e = elements_[rootOrder_[k]];
  return {e.samplePoint(u, v), e.normal};
}

int RadiositySolver::addLink(NodeRef receiver, NodeRef source, bool doEstimate) {
  Link link;
  link.receiver = receiver;
  link.source = source;
  if (doEstimate) estimate(link);
  if (options_.storeShafts) {
    link.shaft = int(shafts_.size());
    shafts_.emplace_back(bounds(receiver), bounds(source));
  }
  links_.push_back(std::move(link));
  return int(links_.size()) - 1;
}

void RadiositySolver::estimate(Link& link) {
  SplitMix rng(linkSeed(options_.seed, link.receiver, link.source));
  const NodeRef r = link.receiver, s = link.source;
  if (!r.isCluster() && !s.isCluster()) {
    const Element& re = elements_[r.index];
    const Element& se = elements_[s.index];
    // Midpoint rule on the receiver's grandchildren: 16 points, enough for pairs that share an
    // edge, where the point form factor has a logarithmic profile.
    double transfer = 0, lowest = 1e300, highest = 0;
    for (const auto& loop : re.childVertices()) {
      Element child;
      child.vertices = loop;
      child.vertexCount = re.vertexCount;
      for (const auto& subLoop : child.childVertices()) {
        const double a = elementArea(subLoop, re.vertexCount);
        Vec3 c{0, 0, 0};
        for (int i = 0; i < re.vertexCount; ++i) c += subLoop[i];
        c = c / double(re.vertexCount);
        const double f = pointToElement(c, re.normal, se);
        transfer += a * f;
        lowest = std::min(lowest, f);
        highest = std::max(highest, f);
      }
    }
    link.unoccludedTransfer = float(transfer / re.area);
    link.transferSpread = float(highest - lowest);
    if (link.unoccludedTransfer <= 0) {
      link.visibility = 0;
      return;
    }
    // Stratified jittered points on both ends, the source strata shuffled against the receiver's.
    const int n = std::max(1, options_.visibilityRays);
    const int side = std::max(1, int(std::lround(std::sqrt(double(n)))));
    std::vector<int> order(n);
    for (int i = 0; i < n; ++i) order[i] = i;
    for (int i = n - 1; i > 0; --i) std::swap(order[i], order[rng.next() % (i + 1)]);
    int unoccluded = 0;
    for (int i = 0; i < n; ++i) {
      const auto stratum = [&](int k, double& u, double& v) {
        const int cell = k % (side * side);
        u = (cell % side + rng.uniform()) / side;
        v = (cell / side + rng.uniform()) / side;
      };
      double u, v;
      stratum(i, u, v);
      const Vec3 x = re.samplePoint(u, v);
      stratum(order[i], u, v);
      const Vec3 y = se.samplePoint(u, v);
      if (!rays_->isOccluded(x, y)) ++unoccluded;
    }
    stats_.visibilityRays += n;
    link.visibility = float(double(unoccluded) / n);
    return;
  }
  // A cluster at one end or both: point pairs, each with its kernel and its ray.
  const int n = std::max(1, options_.clusterSamples);
  const double sourceArea = area(s);
  double unoccluded = 0, visible = 0;
  for (int i = 0; i < n; ++i) {
    const SurfacePoint x = samplePoint(r, rng.uniform(), rng.uniform(), (i + rng.uniform()) / n);
    const SurfacePoint y = samplePoint(s, rng.uniform(), rng.uniform(), rng.uniform());
    const Vec3 d = y.position - x.position;
    const double r2 = dot(d, d);
    if (r2 == 0) continue;
    const double cx = dot(x.normal, d), cy = -dot(y.normal, d);
    if (cx <= 0 || cy <= 0) continue;
    const double kernel = cx * cy / r2 / (std::numbers::pi * r2 + sourceArea / n);
    unoccluded += kernel;
    ++stats_.visibilityRays;
    if (!rays_->isOccluded(x.position, y.position)) visible += kernel;
  }
  link.unoccludedTransfer = float(sourceArea * unoccluded / n);
  link.transferSpread = link.unoccludedTransfer;
  link.visibility = unoccluded > 0 ? float(visible / unoccluded) : 0.f;
}

// A BF oracle on the error rather than on the transfer itself: refine while B_max(source) x (the
// form factor's variation over the receiver, plus the whole transfer when the source is partly
// hidden) — a bound on the irradiance error of the link anywhere on the receiver — exceeds
// tolerance x the largest emitted exitance. The bound is in irradiance, not in power, because a
// power bound lets small receivers keep large pointwise errors (and the furnace test sees them).
// Constant-element gathering is exact where the form factor is constant and the source fully
// visible, so those links need not be split however much power they carry; a cluster end has
// unknown variation, so its whole transfer counts. Clusters whose boxes overlap cannot be linked as
// wholes (their mutual form factor is meaningless), so such links are always refined.
void RadiositySolver::refineLink(int index) {
  const NodeRef r = links_[index].receiver, s = links_[index].source;
  const bool selfLink = r == s;
  const bool overlapping =
      (r.isCluster() || s.isCluster()) && (selfLink || bounds(r).overlaps(bounds(s)));
  const bool splitR = canSplit(r), splitS = canSplit(s);
  if (!splitR && !splitS) return;
  if (!overlapping) {
    const Link& link = links_[index];
    const bool partlyVisible = link.visibility > 0 && link.visibility < 1;
    const double error =
        (double(link.transferSpread) + (partlyVisible ? double(link.unoccludedTransfer) : 0)) *
        radiometry(s).maxRadiosity * area(r);
    if (!(error > options_.tolerance * totalPower_)) return;
  }
  std::vector<std::pair<NodeRef, NodeRef>> pairs;
  if (selfLink) {
    for (NodeRef a : split(r))
      for (NodeRef b : clusters_[r.index].children)
        if (!(a == b && !a.isCluster())) pairs.push_back({a, b});
  } else {
    // Split the larger end (clusters before elements of the same size), as far as allowed.
    const bool splitReceiver =
        splitR && (!splitS || size(r) + (r.isCluster() ? 1e-12 : 0) >= size(s));
    if (splitReceiver)
      for (NodeRef a : split(r)) pairs.push_back({a, s});
    else
      for (NodeRef b : split(s)) pairs.push_back({r, b});
  }
  std::vector<int> children;
  for (const auto& [a, b] : pairs) {
    const bool bothElements = !a.isCluster() && !b.isCluster();
    if (bothElements && elements_[a.index].polygon == elements_[b.index].polygon) continue;
    // Nothing passes between a node entirely behind the other's element plane and that element.
    if (!a.isCluster()) {
      const Element& e = elements_[a.index];
      if (isBehind(b, Plane::fromPointNormal(e.vertices[0], e.normal))) continue;
    }
    if (!b.isCluster()) {
      const Element& e = elements_[b.index];
      if (isBehind(a, Plane::fromPointNormal(e.vertices[0], e.normal))) continue;
    }
    const bool mustRefine =
        (a.isCluster() || b.isCluster()) && (a == b || bounds(a).overlaps(bounds(b)));
    Link probe;
    probe.receiver = a;
    probe.source = b;
    if (!mustRefine) {
      estimate(probe);
      if (bothElements && probe.unoccludedTransfer <= 0) continue;
    }
    const int child = addLink(a, b, false);
    links_[child].unoccludedTransfer = probe.unoccludedTransfer;
    links_[child].visibility = probe.visibility;
    links_[child].transferSpread = probe.transferSpread;
    children.push_back(child);
  }
  links_[index].active = false;
  links_[index].children = children;
  for (int child : children) refineLink(child);
}

bool RadiositySolver::refineActiveLinks() {
  const size_t before = links_.size();
  const size_t count = links_.size();
  for (size_t i = 0; i < count; ++i)
    if (links_[i].active) refineLink(int(i));
  return links_.size() != before;
}

void RadiositySolver::pullEmission(NodeRef node) {
  NodeRadiometry& m = radiometry(node);
  if (!node.isCluster() && elements_[node.index].isLeaf()) {
    m.radiosity = m.emission;
    m.reflected = Rgb{};
    m.maxRadiosity = m.emission.maxComponent();
    return;
  }
  const std::vector<NodeRef> children =
      node.isCluster()
          ? clusters_[node.index].children
          : std::vector<NodeRef>{{NodeRef::kElement, elements_[node.index].firstChild}};
  Rgb emission;
  double maxRadiosity = 0;
  for (NodeRef c : children) {
    pullEmission(c);
    emission += radiometry(c).emission * area(c);
    maxRadiosity = std::max(maxRadiosity, radiometry(c).maxRadiosity);
  }
  NodeRadiometry& pulled = radiometry(node);
  pulled.emission = emission / area(node);
  pulled.radiosity = pulled.emission;
  pulled.reflected = Rgb{};
  pulled.maxRadiosity = maxRadiosity;
}

// Push irradiance down to the leaves, compute B there, pull area means back up (Hanrahan et al.).
void RadiositySolver::pushPull(NodeRef node, const Rgb& direct, const Rgb& indirect,
                               double& largestChange) {
  Rgb eDirect, eIndirect;
  {
    NodeRadiometry& m = radiometry(node);
    eDirect = direct + m.gatheredDirect;
    eIndirect = indirect + m.gatheredIndirect;
    m.irradianceDirect = eDirect;
    m.irradianceIndirect = eIndirect;
  }
  if (!node.isCluster() && elements_[node.index].isLeaf()) {
    Element& e = elements_[node.index];
    NodeRadiometry& m = e.radiometry;
    const Rgb b = m.emission + e.reflectance * (eDirect + eIndirect);
    const Rgb change = b - m.radiosity;
    largestChange =
        std::max({largestChange, std::abs(change.r), std::abs(change.g), std::abs(change.b)});
    m.radiosity = b;
    m.reflected = b - m.emission;
    m.maxRadiosity = b.maxComponent();
    return;
  }
  Rgb b, reflected;
  double maxRadiosity = 0;
  const auto visit = [&](NodeRef c) {
    pushPull(c, eDirect, eIndirect, largestChange);
    const NodeRadiometry& cm = radiometry(c);
    b += cm.radiosity * area(c);
    reflected += cm.reflected * area(c);
    maxRadiosity = std::max(maxRadiosity, cm.maxRadiosity);
  };
  if (node.isCluster()) {
    const size_t count = clusters_[node.index].children.size();
    for (size_t i = 0; i < count; ++i) visit(clusters_[node.index].children[i]);
  } else {
    const int first = elements_[node.index].firstChild;
    for (int k = 0; k < 4; ++k) visit({NodeRef::kElement, first + k});
  }
  NodeRadiometry& m = radiometry(node);
  m.radiosity = b / area(node);
  m.reflected = reflected / area(node);
  m.maxRadiosity = maxRadiosity;
}

// Jacobi gathering over the active links. The direct part depends on emission only, so it is
// gathered once; the indirect part is iterated to convergence.
void RadiositySolver::solve() {
  for (Element& e : elements_) e.radiometry.gatheredDirect = e.radiometry.gatheredIndirect = {};
  for (Cluster& c : clusters_) c.radiometry.gatheredDirect = c.radiometry.gatheredIndirect = {};
  for (const Link& link : links_)
    if (link.active)
      radiometry(link.receiver).gatheredDirect +=
          radiometry(link.source).emission * link.transfer();
  stats_.iterations = 0;
  for (int iteration = 0; iteration < options_.maxIterations; ++iteration) {
    for (Element& e : elements_) e.radiometry.gatheredIndirect = {};
    for (Cluster& c : clusters_) c.radiometry.gatheredIndirect = {};
    for (const Link& link : links_)
      if (link.active)
        radiometry(link.receiver).gatheredIndirect +=
            radiometry(link.source).reflected * link.transfer();
    double largestChange = 0;
    pushPull({NodeRef::kCluster, 0}, {}, {}, largestChange);
    stats_.iterations = iteration + 1;
    const double scale = std::max(clusters_[0].radiometry.maxRadiosity, 1e-300);
    stats_.residual = largestChange / scale;
    if (stats_.residual < options_.convergence) break;
  }
}

void RadiositySolver::buildMesh() {
  mesh_ = {};
  leafVertices_.assign(elements_.size(), {0, 0, 0, 0});
  std::vector<double> weights;
  for (size_t p = 0; p < polygonRoots_.size(); ++p) {
    // Leaves sharing a vertex inside one polygon computed it from the same parents' vertices in
    // the same way, so equal coordinates identify shared vertices exactly.
    std::unordered_map<std::string, std::uint32_t> index;
    std::vector<int> stack(polygonRoots_[p].begin(), polygonRoots_[p].end());
    while (!stack.empty()) {
      const int id = stack.back();
      stack.pop_back();
      const Element& e = elements_[id];
      if (!e.isLeaf()) {
        for (int k = 0; k < 4; ++k) stack.push_back(e.firstChild + k);
        continue;
      }
      for (int i = 0; i < e.vertexCount; ++i) {
        std::string key(sizeof(Vec3), '\0');
        std::memcpy(key.data(), &e.vertices[i], sizeof(Vec3));
        auto [it, inserted] = index.try_emplace(key, std::uint32_t(mesh_.positions.size()));
        if (inserted) {
          mesh_.positions.push_back(e.vertices[i]);
          mesh_.normals.push_back(e.normal);
          mesh_.polygons.push_back(PolygonId(p));
          mesh_.radiosity.push_back({});
          mesh_.directIrradiance.push_back({});
          mesh_.indirectIrradiance.push_back({});
          weights.push_back(0);
        }
        const std::uint32_t v = it->second;
        leafVertices_[id][i] = v;
        mesh_.radiosity[v] += e.radiometry.radiosity * e.area;
        mesh_.directIrradiance[v] += e.radiometry.irradianceDirect * e.area;
        mesh_.indirectIrradiance[v] += e.radiometry.irradianceIndirect * e.area;
        weights[v] += e.area;
      }
      const auto& lv = leafVertices_[id];
      mesh_.indices.insert(mesh_.indices.end(), {lv[0], lv[1], lv[2]});
      if (e.vertexCount == 4) mesh_.indices.insert(mesh_.indices.end(), {lv[0], lv[2], lv[3]});
    }
  }
  for (size_t v = 0; v < weights.size(); ++v) {
    mesh_.radiosity[v] = mesh_.radiosity[v] / weights[v];
    mesh_.directIrradiance[v] = mesh_.directIrradiance[v] / weights[v];
    mesh_.indirectIrradiance[v] = mesh_.indirectIrradiance[v] / weights[v];
  }
}

std::optional<RadiositySample> RadiositySolver::sample(const Vec3& point,
                                                       const Vec3& normal) const {
  if (elements_.empty()) return std::nullopt;
  const auto receiver = locateReceiver(scene_, *grid_, point, normal);
  if (!receiver || polygonRoots_[receiver->polygon].empty()) return std::nullopt;
  const auto mostInside = [&](auto begin, auto end) {
    int best = *begin;
    for (auto it = begin; it != end; ++it)
      if (elements_[*it].insideness(point) > elements_[best].insideness(point)) best = *it;
    return best;
  };
  const auto& roots = polygonRoots_[receiver->polygon];
  int id = mostInside(roots.begin(), roots.end());
  while (!elements_[id].isLeaf()) {
    const int first = elements_[id].firstChild;
    const std::array<int, 4> children{first, first + 1, first + 2, first + 3};
    id = mostInside(children.begin(), children.end());
  }
  // Barycentric interpolation on the leaf's triangle (a quadrilateral is two triangles).
  const Element& e = elements_[id];
  const auto& lv = leafVertices_[id];
  int a = 0, b = 1, c = 2;
  if (e.vertexCount == 4 &&
      dot(cross(e.vertices[2] - e.vertices[0], point - e.vertices[0]), e.normal) > 0)
    b = 2, c = 3;
  const Vec3 p = e.normal * 0 + point;
  const double total =
      dot(cross(e.vertices[b] - e.vertices[a], e.vertices[c] - e.vertices[a]), e.normal);
  double wa = dot(cross(e.vertices[b] - p, e.vertices[c] - p), e.normal) / total;
  double wb = dot(cross(e.vertices[c] - p, e.vertices[a] - p), e.normal) / total;
  double wc = dot(cross(e.vertices[a] - p, e.vertices[b] - p), e.normal) / total;
  wa = std::max(wa, 0.0), wb = std::max(wb, 0.0), wc = std::max(wc, 0.0);
  const double sum = wa + wb + wc;
  if (!(sum > 0))
    wa = wb = wc = 1.0 / 3;
  else
    wa /= sum, wb /= sum, wc /= sum;
  const auto lerp = [&](const std::vector<Rgb>& values) {
    return values[lv[a]] * wa + values[lv[b]] * wb + values[lv[c]] * wc;
  };
  return RadiositySample{lerp(mesh_.directIrradiance), lerp(mesh_.indirectIrradiance),
                         lerp(mesh_.radiosity)};
}

Rgb RadiositySolver::irradiance(const Vec3& point, const Vec3& normal) const {
  const auto s = sample(point, normal);
  return s ? s->total() : Rgb{};
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
      power +=
          absorptance * (e.radiometry.irradianceDirect + e.radiometry.irradianceIndirect) * e.area;
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
    const std::size_t bytes = sizeof(Link) + link.children.capacity() * sizeof(int);
    if (link.active) {
      ++stats_.activeLinks;
      stats_.activeLinkBytes += bytes;
    } else {
      ++stats_.passiveLinks;
      stats_.passiveLinkBytes += bytes;
    }
  }
  stats_.shafts = (long long)shafts_.size();
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
}

}  // namespace penumbra
