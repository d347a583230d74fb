#pragma once
// Hierarchical Galerkin radiosity with linear elements and directional clusters: the fast static
// solver core (issue 22).
//
//  - Elements carry linear functions (three coefficients in an orthonormal basis, linear_basis.h;
//    Zatz 1993; Gortler, Schröder, Cohen & Hanrahan 1993). Clusters (Sillion 1995; Smits, Arvo &
//    Greenberg 1994) send and receive on six axis lobes (axis_lobes.h): which way their surfaces
//    face, not only how much area they hold.
//  - A link's coefficients K[β][α] = (1/A_r) ∫_r ∫_s k(x, y) V(x, y) φ_β(x) φ_α(y) come from
//    cubature over point pairs (2 x 2 Gauss on quadrilaterals, 3 points on triangles; 4 fixed
//    points in a cluster's box), with 0/1 visibility along each pair: a ray only where a polygon
//    lies in the link's shaft, the candidates handed down from parent link to child link.
//    Between elements each receiver point's row is scaled to its exact point form factor.
//  - Refinement by a power oracle: a link is refined when A_r B_s,max times the spread of its
//    point-pair transfers (plus the whole transfer at a cluster end or a partly covered element)
//    exceeds tolerance x the emitted power; the larger end is split.
//  - Jacobi gathering with push-pull; irradiance from emission ("direct") and from reflected
//    radiosity ("indirect") kept apart. The solution shown at a point is the linear function of
//    the leaf that holds it: no final gather.
//
// Units: B, M in W/m²; irradiance in W/m²; B = M + ρ E (DESIGN.md §5).

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "penumbra/radiosity/cluster.h"
#include "penumbra/radiosity/galerkin/axis_lobes.h"
#include "penumbra/radiosity/galerkin/linear_basis.h"
#include "penumbra/radiosity/radiosity_solver.h"
#include "penumbra/scene/posed_scene.h"

namespace penumbra {

class DynamicScene;
class RayCaster;
struct SceneChange;
class UniformGrid;

struct GalerkinOptions {
  // The power oracle's threshold, relative to the power the scene emits.
  double tolerance = 1e-3;
  // Elements are not split below minAreaFactor x tolerance x the total surface area.
  double minAreaFactor = 0.05;
  int refinementPasses = 3;   // refine, solve, refine with the new radiosities, solve, ...
  double convergence = 1e-4;  // stop when the largest change of B < convergence x max B
  int maxIterations = 200;
  long long maxLinks = 1'000'000;  // refinement's budget (an input error past it)
  long long maxElements = 1'000'000;
  // How many times a link's partly hidden transfer counts in the oracle. A linear function per
  // element cannot follow a visibility boundary, and where a source's hidden part is also its
  // dark part (behind furniture, above a lamp hanging under the ceiling) the error has one sign
  // over the whole room: counted once, the indirect light stayed 3-4% low in the chair room.
  // 16 gave the lowest error for the links spent on the three scenes' error curves (1, 2, 4, 8,
  // 16 and 32 measured; docs/radiosity.md).
  double hiddenWeight = 16;
  // Worker threads for link estimation (0: all cores); the result does not depend on it.
  int threads = 1;
};

struct GalerkinStats {
  long long elements = 0;
  long long leaves = 0;
  long long clusters = 0;
  long long activeLinks = 0;
  long long passiveLinks = 0;
  long long pointPairs = 0;       // kernel evaluations
  long long visibilityRays = 0;   // rays cast
  long long unoccludedLinks = 0;  // links whose shaft held no polygon (no rays)
  int iterations = 0;             // Jacobi iterations, all passes
  std::size_t elementBytes = 0;   // memory in use (vector capacities)
  std::size_t clusterBytes = 0;
  std::size_t linkBytes = 0;
  std::size_t totalBytes() const { return elementBytes + clusterBytes + linkBytes; }
  double refineSeconds = 0;
  double solveSeconds = 0;
  double totalSeconds = 0;
};

class GalerkinRadiosity {
 public:
  explicit GalerkinRadiosity(const GalerkinOptions& options = {});

  // Builds the hierarchy at the scene's current pose and solves (the scene's grid and ray
  // caster are used during the call only).
  void build(const DynamicScene& scene);
  // The solution at the scene's new pose after `change` was applied to it: for now a full
  // recomputation (the line-space update is issue 17's).
  void update(const DynamicScene& scene, const SceneChange& change);

  // Direct and indirect irradiance and radiosity at a point on the front of a receiver, from the
  // linear functions of the leaf holding it (negative values of a steep linear function clamped
  // to 0); nothing when the point lies on no polygon facing `normal`.
  std::optional<RadiositySample> sample(const Vec3& point, const Vec3& normal) const;
  Rgb irradiance(const Vec3& point, const Vec3& normal) const;
  // The solution as drawn: the leaves' triangles, each corner with the area-weighted mean of the
  // linear functions of the leaves of its polygon that meet there.
  RadiosityMesh leafMesh() const;

  // Power emitted and absorbed ((1 − ρ) ∫ E over the leaves), W per channel.
  Rgb emittedPower() const;
  Rgb absorbedPower() const;

  const GalerkinStats& stats() const { return stats_; }

  // What the solver holds per element and per cluster (public for tests).
  struct Node {
    Rgb emission;                                        // M (area mean for a cluster)
    LinearRgb gatheredDirect{}, gatheredIndirect{};      // over the node's own links
    LinearRgb irradianceDirect{}, irradianceIndirect{};  // with what ancestors pushed down
    LinearRgb radiosity{};                               // B (a cluster: its area mean in [0])
    double maxRadiosity = 0;                             // a bound on B over the leaves below
    double maxReflectance = 0;                           // the largest reflectance below
  };
  struct GElement {
    ElementShape shape;
    LinearBasis basis;
    BasisTransfer fromParent{};  // the parent's basis over this element (push and pull)
    Cubature cubature;           // where links sample it (linkCubature), kept: links read it often
    std::array<std::array<double, 3>, 4> cubatureBasis{};  // the basis at those points
    PolygonId polygon = 0;
    int parent = -1;
    int firstChild = -1;
    double area = 0;
    Rgb reflectance;
    Node node;
    // How much of it a polygon in face-to-face contact covers (face_contacts.h), judged at its
    // link cubature points and centroid: a covered point sees only the covering polygon.
    enum Cover : std::uint8_t { kExposed, kPartlyCovered, kCovered };
    Cover cover = kExposed;
    bool isLeaf() const { return firstChild < 0; }
  };
  struct GCluster {
    ClusterNode structure;
    Node node;
    // What the cluster's surfaces send (B A per lobe: emission, and reflected radiosity pulled
    // up), and what arrived over the cluster's own links and from the clusters above it, on the
    // six axis lobes (axis_lobes.h); the node's linear functions hold only area means.
    AxisLobes emittedLobes{}, reflectedLobes{};
    AxisLobes gatheredDirectLobes{}, gatheredIndirectLobes{};
  };
  struct GLink {
    NodeRef receiver, source;
    // K[β][α], β over the receiver's basis, α over the source's. A cluster end has one
    // coefficient: a cluster source's is per unit of the exitance its lobes send towards the
    // receiver, a cluster receiver's is the flux density arriving along `direction`.
    std::array<double, 9> k{};
    Vec3 direction;          // unit, from the receiver's centre to the source's (for cluster ends)
    float meanTransfer = 0;  // the mean point-pair transfer (K[0][0])
    float spread = 0;        // max − min of the point-pair transfers
    float hiddenTransfer = 0;  // what its pairs found hidden would carry
    bool active = true;
  };
  const std::vector<GElement>& elements() const { return elements_; }
  const std::vector<GLink>& links() const { return links_; }

 private:
  struct Estimate;
  struct Counters;
  void clear();
  // Can any light leave s and reach r (their fronts face each other somewhere)?
  bool canExchange(NodeRef r, NodeRef s) const;
  Estimate estimate(NodeRef r, NodeRef s, const std::vector<PolygonId>& candidates,
                    Counters& counters) const;
  // The polygons of `among` that may meet the link's shaft.
  std::vector<PolygonId> shaftCandidates(NodeRef r, NodeRef s,
                                         const std::vector<PolygonId>& among) const;
  std::vector<PolygonId> gridCandidates(NodeRef r, NodeRef s) const;
  double oracle(NodeRef r, NodeRef s, double meanTransfer, double spread,
                double hiddenTransfer) const;
  // The interactions of receivers with sources still to estimate and refine, each with the
  // occluder candidates of the link it comes from (shared: a split hands them to every child).
  using Candidates = std::shared_ptr<const std::vector<PolygonId>>;
  struct RefineTask {
    NodeRef receiver, source;
    Candidates candidates;
  };
  // Refines the tasks' interactions until the oracle is satisfied (refinement.cpp).
  void refine(std::vector<RefineTask> wave, Counters& counters);
  // The end of a link to split: the larger one (by its box's diagonal) if it can be split, else
  // the other, else none.
  std::optional<NodeRef> endToSplit(NodeRef r, NodeRef s) const;
  // Queues the interactions that replace r with s once `end` (r or s) is split.
  void queueChildren(NodeRef r, NodeRef s, NodeRef end, const Candidates& candidates,
                     std::vector<RefineTask>& wave);
  bool refineActiveLinks(Counters& counters);
  // Sets the element's basis and cubature from its shape.
  static void prepare(GElement& e);
  // Splits the element (once) and returns its first child.
  int splitElement(int element);
  bool canSplit(NodeRef n) const;
  std::vector<NodeRef> children(NodeRef n);
  double size(NodeRef n) const;
  Box3 bounds(NodeRef n) const;
  double area(NodeRef n) const;
  Node& nodeOf(NodeRef n);
  const Node& nodeOf(NodeRef n) const;
  void pullEmission(NodeRef n);
  // Adds a child's exitance on the lobes: its emission, or (`emitted` false) its reflected
  // radiosity.
  void addLobes(AxisLobes& lobes, NodeRef child, bool emitted) const;
  // Jacobi iterations until the largest change of B < convergence x the largest reflected B.
  void solve(double convergence);
  // Pushes what `n` gathered (plus `direct`, `indirect` from element ancestors, in n's basis,
  // and the lobes of cluster ancestors) down to the leaves, sets B there and pulls it back up;
  // returns the largest change of a leaf's B.
  double pushPull(NodeRef n, const LinearRgb& direct, const LinearRgb& indirect,
                  const AxisLobes& directLobes, const AxisLobes& indirectLobes);
  std::optional<int> leafContaining(const Vec3& point, const Vec3& normal) const;
  // Is x, a point of `polygon`, covered by a polygon in face-to-face contact with it?
  bool isCovered(PolygonId polygon, const Vec3& x) const;
  GElement::Cover coverOf(const GElement& e) const;

  GalerkinOptions options_;
  PosedScene scene_;
  const UniformGrid* grid_ = nullptr;
  const RayCaster* rays_ = nullptr;
  std::vector<GElement> elements_;
  std::vector<std::vector<int>> polygonRoots_;
  std::vector<std::vector<PolygonId>> contacts_;  // polygons in face-to-face contact with each
  std::vector<GCluster> clusters_;                // [0] is the root
  std::vector<GLink> links_;
  double threshold_ = 0;  // tolerance x emitted power
  double minArea_ = 0;
  GalerkinStats stats_;
};

}  // namespace penumbra
