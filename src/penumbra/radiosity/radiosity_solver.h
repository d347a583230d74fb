#pragma once
// Hierarchical radiosity with clustering: the static solver of the global-illumination engine.
//
// Input polygons become element quadtrees under a volume cluster hierarchy with a single root;
// links between clusters and elements carry a form factor estimate, a visibility estimate (Embree
// rays aimed in the solid angle of the source) and a shaft (polygon-to-polygon between elements,
// box-to-box otherwise). Refinement follows power oracles on links and on receivers; solving
// gathers over active links and push-pulls until the radiosities stop changing. Direct irradiance
// (transported from emission) and indirect irradiance (from reflected radiosity) are kept apart.
// Polygons in face-to-face contact exchange energy where they overlap and nothing else there.
//
// Units: B, M in W/m²; irradiance in W/m²; B = M + ρ (E_direct + E_indirect) (DESIGN.md §5).

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "penumbra/radiosity/cluster.h"
#include "penumbra/radiosity/element.h"
#include "penumbra/radiosity/link.h"
#include "penumbra/scene/posed_scene.h"
#include "penumbra/spatial/shaft.h"

namespace penumbra {

class InputError;

class RayCaster;
class SplitMix;
class ExactReference;
class UniformGrid;
class DynamicScene;
struct SceneChange;

struct RadiosityOptions {
  // Power oracles (refinement.cpp), all against tolerance x the power emitted by the scene:
  //  - link: A_receiver x B_max(source) x the unoccluded transfer when the source is partly
  //    hidden; A_source x (B_max − B_min over the source) x the variation over the source of the
  //    form factor to the receiver;
  //  - receiver: A_receiver x the variation over the receiver of Σ_links F(x, source) V B_source;
  //  - cluster receiver: B_max(source) x the transfer, an irradiance error at every point of the
  //    cluster (its surfaces all get the same irradiance whatever their orientation), weighed
  //    with an area of at least total area / irradianceFactor (see below); a cluster receiver is
  //    always the end that is split.
  double tolerance = 1e-3;
  // A cluster receiver's error counts as if the cluster had at least total area /
  // irradianceFactor: the power oracle alone let a small cluster (a chair, a bin) keep any
  // irradiance error below tolerance x power / its area, at every point of it. So an irradiance
  // error above irradianceFactor x tolerance x the mean emitted exitance is refined.
  double irradianceFactor = 20;
  // Elements are not split below this area (0: minAreaFactor x tolerance x total surface area,
  // so the finest element scales with the power criterion).
  double minElementArea = 0;
  double minAreaFactor = 0.05;
  // Element-to-element visibility computed exactly at the receiver's 16 grandchild centres (the
  // source minus the projections of the polygons in the link's shaft, as the exact reference
  // computes a light's visible part) instead of by rays. Exact per point, so a point's visible
  // form factors sum to 1 in a closed scene, and the receiver oracle sees where visibility
  // varies; rays leave each link's visibility with a 16-sample noise. Not with
  // elementSourceShares, which needs the rays' ends. Off by default for its cost: under the
  // bundled rooms' lamps, whose links refine down to every shadow boundary, it makes the
  // solution 3-11x slower (furnished room at 1e-3: 118 s against 10 s; docs/radiosity.md).
  bool exactVisibility = false;
  // Links whose unoccluded transfer is below this keep ray visibility: their noise adds little
  // (errors of independent links add in quadrature) and they are most of the links; every link
  // exact cost about 1.5x more for no measurable gain in the furnace (docs/radiosity.md).
  double exactVisibilityMinTransfer = 0.005;
  // Rays per element link (stratified receiver points) whose shaft holds a polygon. A link's
  // visibility only steers refinement (the final gather shows what each leaf sees itself), and
  // 4 rays steer it as well as 16 did (Cornell box: 3.9% median error at 1e-3 both ways, links
  // estimated 2x faster; bench/radiosity_error_curve).
  int visibilityRays = 4;
  int clusterSamples = 16;    // receiver points (one ray each) for links with a cluster end
  double convergence = 1e-5;  // stop when the largest change of B < convergence x max B
  int maxIterations = 1000;
  int refinementPasses = 4;  // refine, solve, refine with the new radiosities, ...
  bool storeShafts = true;   // one shaft per link (the "all" shaft policy)
  // Element sources send per grandchild cell, by where the link's visible transfer lands
  // (Link::sourceShares): under a real lamp this brings absorbed / emitted in the chair rooms
  // from 0.97 to within 1%, but in the one-lamp box (EnergyBalanceWithOneLamp) the error grows
  // from 0.27% at tolerance 1e-3 to 0.70% at 3e-4 (energy created on the floor, cause not yet
  // found), so it is off until that is understood (docs/radiosity.md, known limits).
  bool elementSourceShares = false;
  // The leaves' irradiance re-gathered over each leaf's own 16 cells from every active link above
  // it, and the leaves' radiosities solved again with it (final_gather.cpp): exactly for element
  // sources that are wholly visible or emit more than exactGatherContrast x the scene's mean
  // radiosity (lamps), by rounds of finalGatherRays cosine-distributed rays per cell (more rounds
  // where few meet the rest) for the others and for cluster sources, which share what the exact
  // ones leave of the hemisphere. This final solution is what is shown (mesh, probes) and what the
  // energy balance counts; off, the hierarchical solution's pushed means are.
  bool finalGather = true;
  int finalGatherRays = 32;
  double exactGatherContrast = 4;
  std::uint64_t seed = 1;
  // When set, the final solution takes each leaf's direct irradiance from this function (the
  // mean over the leaf's exposed grandchild-cell centres) instead of gathering the emitters over
  // its links, so that the light reflected into the indirect part starts from an exact first
  // bounce (CombinedSolution passes the discontinuity mesh's exact irradiance). Nothing at any
  // point of a leaf: that leaf keeps its gathered direct part. Called from one thread.
  std::function<std::optional<Rgb>(const Vec3& point, const Vec3& normal, PolygonId polygon)>
      exactDirect;
  // Worker threads for link estimation, the receiver oracle and the final gather (0: all
  // cores); the result does not depend on it.
  int threads = 1;
  // What refinement may create: a tolerance too fine for the scene (1e-12 splits elements down
  // to nothing) stops with an InputError naming --tolerance instead of taking all memory. The
  // process peaks at about 1 KB per link (Cornell box at 1e-4: 467,000 links, 490 MB), so the
  // defaults stop near 1 GB (1e-12: after 2.5 s); the furnished room at 1e-3 needs 137,000
  // links and 5,000 elements.
  long long maxLinks = 1'000'000;
  long long maxElements = 500'000;
};

// Memory is what the structures hold (capacity x record size plus owned vectors), in bytes.
struct RadiosityStats {
  long long clusters = 0;
  long long elements = 0;
  long long leaves = 0;
  long long links = 0;  // every link ever created and kept: active + passive
  long long activeLinks = 0;
  long long passiveLinks = 0;
  long long shafts = 0;
  long long polygonShafts = 0;  // element-to-element links; the others are box-to-box
  long long visibilityRays = 0;
  long long unoccludedByShaft = 0;      // element links found wholly visible by their shaft alone
  long long exactVisibilityPoints = 0;  // receiver points whose visible form factor was clipped
  long long finalGatherRays = 0;        // rays cast by the final gather
  long long finalGatherMisses = 0;      // ... that met a back face or nothing
  int iterations = 0;                   // gathering iterations of the last solve
  int finalIterations = 0;              // Jacobi iterations of the final solution
  double residual = 0;                  // last largest relative change of B
  bool converged = true;                // the last solve reached `convergence` in maxIterations
  std::size_t clusterBytes = 0;
  std::size_t elementBytes = 0;
  std::size_t activeLinkBytes = 0;
  std::size_t passiveLinkBytes = 0;
  std::size_t shaftBytes = 0;
  std::size_t meshBytes = 0;  // per-vertex output mesh
  // The final solution: each element's and each leaf cell's radiosity, and the index of the
  // links above each leaf that point queries gather from.
  std::size_t finalBytes = 0;
  std::size_t totalBytes() const {
    return clusterBytes + elementBytes + activeLinkBytes + passiveLinkBytes + shaftBytes +
           meshBytes + finalBytes;
  }
  double refineSeconds = 0;
  double solveSeconds = 0;
  double finalGatherSeconds = 0;
  double totalSeconds = 0;
};

// Per-vertex solution over the leaf elements (shared vertices within a polygon carry the
// area-weighted mean of the leaves around them), ready to be drawn with Gouraud shading.
struct RadiosityMesh {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;
  std::vector<PolygonId> polygons;
  std::vector<Rgb> radiosity;
  std::vector<Rgb> directIrradiance;
  std::vector<Rgb> indirectIrradiance;
  std::vector<std::uint32_t> indices;  // three per triangle
};

struct RadiositySample {
  Rgb direct;
  Rgb indirect;
  Rgb radiosity;
  Rgb total() const { return direct + indirect; }
};

class RadiositySolver {
 public:
  explicit RadiositySolver(const RadiosityOptions& options = {});
  ~RadiositySolver();
  RadiositySolver(const RadiositySolver&) = delete;
  RadiositySolver& operator=(const RadiositySolver&) = delete;

  // Builds the hierarchy at the current pose of a shared live scene and solves, with its grid and
  // ray caster (the scene must outlive the solver's use of it). Replaces any previous solution.
  void build(const DynamicScene& scene);
  // The solution at the scene's new pose after `change` was applied to it. For now a full
  // recomputation through the same call (the line-space hierarchy, issue 8, makes it incremental).
  void update(const DynamicScene& scene, const SceneChange& change);
  // Conveniences that own a live scene of their own: keyframe pose `frame`, or a static posed
  // scene (tests, tools).
  void build(const Scene& scene, double frame);
  void build(const PosedScene& scene);

  // Total irradiance (direct + indirect) at a point on the front side of a receiver; black when
  // the point lies on no polygon facing `normal`.
  Rgb irradiance(const Vec3& point, const Vec3& normal) const;
  // The indirect irradiance at a point, gathered there (RadiosityOptions::finalGather): every
  // active link above the point's leaf sends its source's reflected radiosity, wholly visible and
  // bright element sources by their exact point form factor and visibility, the rest by `rays`
  // cosine-distributed rays from the point (deterministic for a seed). Nothing is interpolated,
  // so a point under a desk gets what it sees, not the mean of a leaf reaching out into the
  // light. With RadiosityOptions::exactDirect, a ray that meets a leaf closer than the leaf's size
  // takes what the point it met reflects, not the leaf's mean (reflectedAlong: the exact direct
  // light there and a path on through the gap). Nothing when the point lies on no polygon facing
  // `normal`, or without a final gather.
  std::optional<Rgb> gatheredIndirect(const Vec3& point, const Vec3& normal, int rays,
                                      std::uint64_t seed) const;
  // Direct and indirect irradiance and radiosity interpolated from the leaf's vertices, or
  // nothing when the point lies on no polygon facing `normal`.
  std::optional<RadiositySample> sample(const Vec3& point, const Vec3& normal) const;

  const RadiosityStats& stats() const { return stats_; }
  const RadiosityMesh& mesh() const { return mesh_; }
  const PosedScene& scene() const { return scene_; }
  const std::vector<Element>& elements() const { return elements_; }
  const std::vector<Cluster>& clusters() const { return clusters_; }
  const std::vector<Link>& links() const { return links_; }
  const std::vector<Shaft>& shafts() const { return shafts_; }
  const Cluster& root() const { return clusters_[0]; }
  const RadiosityOptions& options() const { return options_; }

  // Power (W per channel) emitted by all polygons and absorbed by all leaves, (1 − ρ) A E summed.
  Rgb emittedPower() const;
  Rgb absorbedPower() const;  // of the final solution with RadiosityOptions::finalGather

 private:
  void clear();
  // Appends a link (with its shaft when shafts are stored) and returns its index.
  int addLink(const Link& link, const std::optional<Shaft>& shaft);
  // The receiver oracle's point values of a link (see pointTransfers_).
  struct PointTransfers {
    std::array<float, 16> values{};
    bool valid = false;
    // values are unoccluded point form factors, to be multiplied by the link's visibility and
    // zeroed at points covered by a polygon in contact; otherwise they are the point transfers.
    bool unoccluded = false;
  };
  // What estimating links counts, per link (links are estimated in parallel), summed after.
  struct EstimateCounters {
    long long visibilityRays = 0;
    long long unoccludedByShaft = 0;
    long long exactVisibilityPoints = 0;
  };
  // Estimates the link; `pointValues`, when given, receives the unoccluded form factors at the
  // receiver's 16 grandchild centres when the quadrature computed them; `shaft`, when given,
  // receives the link's shaft if the estimate built it (to cull occluder candidates).
  // Thread-safe: reads the hierarchy only.
  void estimate(Link& link, EstimateCounters& counters, PointTransfers* pointValues = nullptr,
                std::optional<Shaft>* shaft = nullptr) const;
  // The shaft between a link's ends: polygon-to-polygon between elements, box-to-box otherwise.
  Shaft linkShaft(NodeRef receiver, NodeRef source) const;
  // Exact visibility of the source element from the receiver element's 16 grandchild centres
  // (the receiver oracle's points): fills link.pointVisibleTransfers and link.visibility.
  void estimateExactVisibility(Link& link, const Element& receiver, const Element& source,
                               EstimateCounters& counters) const;
  // The exact visible form factor from x (normal `normal`, on polygon `receiver`) to `source`,
  // whose unoccluded form factor from x is `unoccluded`, hidden only by `occluders` (none: the
  // unoccluded one). Snapped to exactly 0 or `unoccluded` within rounding of either.
  double visibleTransfer(const Vec3& x, const Vec3& normal, PolygonId receiver,
                         const Element& source, std::span<const PolygonId> occluders,
                         double unoccluded, long long& clippedPoints) const;
  // Polygons that may hide part of `source` from `receiver`: those meeting their polygon shaft.
  std::vector<PolygonId> shaftOccluders(const Element& receiver, const Element& source) const;
  std::vector<PolygonId> shaftOccluders(const Shaft& shaft, PolygonId receiver,
                                        PolygonId source) const;
  // Refinement runs in waves (breadth first): the oracles decide and nodes are split in link
  // order on one thread, then the new links are estimated in parallel, then appended in order,
  // so the hierarchy is the same for any number of threads.
  // The node pairs that replace link `index` when the link oracle refines it (splitting its
  // receiver or source), or nothing.
  std::optional<std::vector<std::pair<NodeRef, NodeRef>>> refinementOf(int index);
  // Each (link, pairs): the link becomes passive and its children are the pairs that can
  // exchange energy, estimated in parallel. Returns the new links, in order.
  std::vector<int> replaceLinks(
      const std::vector<std::pair<int, std::vector<std::pair<NodeRef, NodeRef>>>>& replacements);
  // Refines the links, then their children, ..., until the link oracle is satisfied.
  void refineInWaves(std::vector<int> links);
  bool refineReceivers();
  // The receiver oracle for element p and its active links. Thread-safe across receivers: writes
  // only the point-transfer cache of those links.
  bool receiverNeedsSplit(int p, const std::vector<int>& links);
  // The link's transfer seen from the point x of its element receiver (`covered`: x lies under a
  // polygon in contact with the receiver).
  double pointTransfer(const Link& link, const Vec3& x, const Vec3& normal, bool covered) const;
  // The same without visibility: the exact point form factor to the source.
  double unoccludedPointTransfer(const Link& link, const Vec3& x, const Vec3& normal,
                                 bool covered) const;
  // The exact form factor from x (normal `normal`) to the front of element e.
  double pointFormFactor(const Vec3& x, const Vec3& normal, const Element& e) const;
  // The mean over `cell` (a part of `receiver`, in its plane) of the point form factor to
  // `source`, by the links' adaptive quadrature.
  double cellFormFactor(const std::array<Vec3, 4>& cell, const Element& receiver,
                        const Element& source) const;
  bool refineActiveLinks();
  void solve();
  // What the link's source sends per unit transfer: its `quantity` (emission, reflected or total
  // radiosity), per root element of a cluster source weighted by the link's source shares.
  Rgb sourceValue(const Link& link, Rgb NodeRadiometry::*quantity) const;
  void pushPull(NodeRef node, const Rgb& direct, const Rgb& indirect, double& largestChange);
  void pullEmission(NodeRef node);
  // What a leaf gathers in the final solution: weight x the radiosity of an element.
  struct GatherEntry;
  struct LeafGather;
  // Re-gathers every leaf's irradiance at its own points and solves the leaves' radiosities
  // again with it (NodeRadiometry::finalDirect/Indirect, radiosity, reflected).
  void finalGather();
  // The points where the final gather evaluates a leaf (see final_gather.cpp).
  static std::array<Vec3, 16> gatherPoints(const Element& leaf);
  // Is a ray's hit at `distance` from its origin closer than the size of the leaf it met?
  bool isNearHit(int leaf, double distance) const;
  // What a gather entry's source sends per unit weight: the reflected radiosity of the leaf's
  // cell (0-15), or the element's exposed mean (cell -1).
  Rgb reflectedAt(int element, int cell) const;
  // The light reflected at `point` (on `polygon`, in `leaf`) met by a ray that close: the exact
  // direct irradiance there and one ray further (final_gather.cpp).
  Rgb reflectedAlong(int leaf, const Vec3& point, PolygonId polygon, SplitMix& rng,
                     int depth) const;
  void splitRemainder(const Element& leaf, const std::array<Vec3, 4>& cell, const Vec3& x,
                      double remainder, const std::vector<int>& rayElements,
                      const std::vector<int>& exactSources, int rays, SplitMix& rng,
                      LeafGather& gather) const;
  // What the final gather needs to find the active links above a leaf (built by finalGather).
  struct GatherIndex {
    std::vector<std::vector<int>> elementLinks, clusterLinks;  // active links by receiver
    std::vector<int> parentCluster, rootCluster;
    double brightRadiosity = 0;  // sources emitting more are gathered exactly
  };
  void indexGatherSources();
  // The sources above a leaf, split into those gathered exactly and those by rays.
  struct LeafSources {
    std::vector<int> exactLinks;
    std::vector<std::vector<PolygonId>> occluders;  // per exact link: polygons in its shaft
    std::vector<int> exactSources;                  // their source elements, sorted
    std::vector<int> rayElements;
  };
  LeafSources leafSources(int leaf) const;
  // For a gather at `point`: the exact sources close to it handed to the rays (final_gather.cpp).
  LeafSources nearSourcesByRays(const Vec3& point, LeafSources sources) const;
  // The leaf holding the point of a receiver facing `normal`, if any.
  std::optional<int> leafContaining(const Vec3& point, const Vec3& normal) const;
  void solveLeaves(const std::vector<LeafGather>& gathered);
  // The leaf element of `polygon` holding its point y (nearest by insideness), -1 if none.
  int leafAt(PolygonId polygon, const Vec3& y) const;
  // The leaf of a polygon in contact with `polygon` that covers its point x, -1 if none.
  int coveringLeaf(PolygonId polygon, const Vec3& x) const;
  void buildMesh();
  void computeStats();

  NodeRadiometry& radiometry(NodeRef n);
  const NodeRadiometry& radiometry(NodeRef n) const;
  Box3 bounds(NodeRef n) const;
  double area(NodeRef n) const;
  double size(NodeRef n) const;
  bool canSplit(NodeRef n) const;
  // The error thrown when refinement would pass maxLinks or maxElements (`what`).
  InputError budgetExceeded(const char* what, long long limit) const;
  std::vector<NodeRef> split(NodeRef n);
  bool isBehind(NodeRef n, const Element& e) const;
  // Does an irradiance error over all of the receiver `n`, taken as at least referenceArea_
  // large, exceed the oracles' power threshold?
  bool exceedsTolerance(NodeRef n, double irradianceError) const;

  struct SurfacePoint {
    Vec3 position;
    Vec3 normal;
    PolygonId polygon = 0;
  };
  SurfacePoint samplePoint(NodeRef n, double u, double v, double w) const;
  // Is x, a point of `polygon`, covered by a polygon in face-to-face contact with it? Such a point
  // sees only that polygon (the ray caster, which ignores polygons through a ray's ends, would
  // let it see through).
  bool isCovered(PolygonId polygon, const Vec3& x) const;
  // Does light pass between x (on polygon p) and y (on polygon q)?
  bool isVisible(PolygonId p, const Vec3& x, PolygonId q, const Vec3& y) const;

  // The full computation over scene_, grid_ and rays_.
  void compute();
  // Throws InputError when the scene is closed and some channel's reflectance is 1 everywhere.
  void refuseLosslessClosedScene(const DynamicScene& scene);

  RadiosityOptions options_;
  std::unique_ptr<DynamicScene> ownedScene_;  // only for the convenience builds
  PosedScene scene_;                          // the pose solved (a copy: the live one moves)
  const UniformGrid* grid_ = nullptr;
  const RayCaster* rays_ = nullptr;
  std::unique_ptr<ExactReference> visibleParts_;  // exact visible form factors (exactVisibility)
  std::vector<Element> elements_;
  std::vector<std::vector<int>> polygonRoots_;    // root elements of each polygon
  std::vector<std::vector<PolygonId>> contacts_;  // polygons in face-to-face contact with each
  std::vector<int> rootOrder_;                    // root elements in cluster order
  std::vector<double> rootCumulativeArea_;        // prefix sums of areas over rootOrder_
  std::vector<Cluster> clusters_;                 // [0] is the root
  std::vector<Link> links_;                       // [0] is the root self-link
  std::vector<Shaft> shafts_;
  // The receiver oracle's point transfers of each link at its receiver's 16 grandchild centres,
  // computed once per link (geometry does not change; B does, between passes). Dropped after
  // building.
  std::vector<PointTransfers> pointTransfers_;
  std::vector<std::array<std::uint32_t, 4>> leafVertices_;  // mesh vertices of each leaf
  GatherIndex gatherIndex_;
  // The final solution's reflected radiosity (B − M) of every element as the rest of the scene
  // sees it, and of a partly covered leaf's covered part (what only the covering polygon sees).
  std::vector<Rgb> exposedReflected_, coveredReflected_;
  // What a ray meeting a leaf's cell takes, per leaf and grandchild cell (16 each): the leaf's
  // reflectance times the cell's own direct and indirect irradiance, as its point and its own
  // rays gathered them (a covered cell: the covered part's). A leaf's mean would send a ray that
  // meets its lit part the light of its shadowed part too, and what a point sees of a surface is
  // more often its lit part (the floor under a table hides from the walls as it hides from the
  // lamp): with means the chair room's indirect light came out 1% of the total too low.
  std::vector<Rgb> cellReflected_;
  RadiosityMesh mesh_;
  double minArea_ = 0;
  double totalPower_ = 0;     // emitted power (largest channel per polygon), the oracle's scale
  double referenceArea_ = 0;  // total area / irradianceFactor: cluster receivers count as larger
  RadiosityStats stats_;
};

}  // namespace penumbra
