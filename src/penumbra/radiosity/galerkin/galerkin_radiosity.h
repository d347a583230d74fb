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
//  - The line-space update (Drettakis & Sillion 1997; galerkin_update.cpp): every node pair the
//    refinement met is kept, split ones too (passive), with the occluder candidates its children
//    filter; a move re-poses the moving objects' elements (each object its own cluster subtree,
//    cut in its own coordinates, so the hierarchy has the same shape at every pose), walks the
//    pairs from the root and re-estimates only those whose shaft the object's old or new box
//    meets, refines or cleans up there, and solves from the previous solution.
//  - Dynamic shaft management (Schöffel & Pomi 1999; galerkin_shafts.cpp): the pairs' candidate
//    lists are kept only near the moving objects, made ahead of them on predicted boxes and
//    collected when old (ShaftPolicy, ShaftManagement); results are the same bits whatever is kept.
//
// Units: B, M in W/m²; irradiance in W/m²; B = M + ρ E (DESIGN.md §5).

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <unordered_map>
#include <utility>
#include <vector>

#include "penumbra/base/stopwatch.h"
#include "penumbra/radiosity/cluster.h"
#include "penumbra/radiosity/galerkin/axis_lobes.h"
#include "penumbra/radiosity/galerkin/linear_basis.h"
#include "penumbra/radiosity/radiosity_solver.h"
#include "penumbra/scene/posed_scene.h"

namespace penumbra {

class DynamicScene;
struct Scene;
class RayCaster;
class Shaft;
struct SceneChange;
class UniformGrid;

// Which node pairs keep their shaft's occluder candidates (the polygons the shaft may hold,
// which a move edits and a pair's children filter) between updates. The shaft itself, box to
// box, is made from the ends' bounds whenever it is tested; the candidates are what costs memory.
enum class ShaftPolicy {
  kAll,      // every estimated pair keeps its list (Drettakis & Sillion's line-space hierarchy)
  kManaged,  // only where moves need them (Schöffel & Pomi 1999; galerkin_shafts.cpp)
};

// Dynamic shaft management (Schöffel & Pomi 1999): after a build only the root pair keeps its
// candidates; an update makes a met pair's list when it needs one (from its parent's), or needs
// only how many candidates it has (see keepCount); lists are made ahead of each moving object on
// its predicted boxes, and lists no update has used for a while are collected. Results never
// depend on any of it: a missing list is made again exactly as it was (verifyLinks), only the
// cost changes.
struct ShaftManagement {
  // Movement prediction: each object the update moved is extrapolated `predictedFrames` moves
  // ahead from its last three poses (constant acceleration), its box scaled by `predictionScale`
  // about its centre (the paper's s in (1, 1.2]), and every pair whose shaft meets such a box
  // gets its list made now, not during the next update.
  bool prediction = true;
  int predictedFrames = 2;
  double predictionScale = 1.1;
  // Garbage collection once the lists use more than `collectAbove` bytes (the paper's
  // T_shafts): a list no update, walk or prediction has used in the last `minAge` updates (the
  // paper's T_min) is released.
  std::size_t collectAbove = 0;
  int minAge = 1;
  // Which lists outlive the update that used them: those of at most this many candidates. A
  // longer list is not needed to estimate its pair again after a move that leaves its ends and
  // its parent's static candidates as they were (the estimate then reads only how many there
  // are, which the pair keeps, and the move's own polygons, which are few); it is made again
  // only for a pair whose ends changed, which a move makes from the parent's list anyway.
  std::size_t keepCount = 16;
  // Whether a list a moved object's own pairs were made from (its parent pairs': no end of theirs
  // moved) outlives the update whatever its length, while the object goes on moving (it is
  // released once an update leaves it unused, by minAge): each move of the object needs it again.
  bool keepMoversParents = true;
  // Prediction and collection on a second thread after each update, while the caller draws or
  // waits for input; the next call that reads or changes the pairs waits for it first.
  bool workerThread = true;
};

struct GalerkinOptions {
  // The power oracle's threshold, relative to the power the scene emits.
  double tolerance = 1e-3;
  // Elements are not split below minAreaFactor x tolerance x the total surface area.
  double minAreaFactor = 0.05;
  // Refinement passes at most: from the root pair, then on each solve's radiosities (with the
  // clean-up of split pairs they no longer need), until a pass changes no pair. An update ends
  // the same way: one more pass after it changes nothing unless the budget stopped it.
  int refinementPasses = 8;
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
  // How many times the transfer of a pair whose every point pair was found hidden counts in the
  // oracle. Its estimate is zero and its spread zero, yet the 16 segments may all meet an
  // occluder that hides only part of each end: unweighted, no pass ever split such a pair. In
  // the Cornell box the lit floor in front of the blocks sends light past them to the back wall:
  // with only the floor reflecting, the back wall's indirect light stayed 2.3% of its total low at
  // tolerances 1e-3 and 1e-4 alike; with weight 1, 1.05% at 1e-4. In the furnished room a wall
  // lost 5.3% of its light, most of it to the bookshelves in front of it whose pairs with it were
  // wholly hidden at cluster level; 3.0% with weight 1 (docs/radiosity.md, "Session 27").
  double wholeHiddenWeight = 1;
  // How many times the spread of directions between a pair's points counts in the oracle where
  // an end is a cluster: its lobes take or give all the light along one direction (between the
  // ends' centres), and a wide source around a cluster (the floor under a chair, the room's static
  // cluster around a moving object) sends along many. With the weight 0 the chair room's moving
  // chair took 30% too little of the floor's light (its legs' sides and its seat's underside, lit
  // from below, faced away from the one direction); 7% with 1 (docs/radiosity.md, "Session 28").
  double directionWeight = 1;
  // Frame-rate control for the update (Drettakis & Sillion 1997, §6): past this many seconds
  // into an update (0: no limit), it splits no more links and runs no more refinement passes;
  // the links it would have split stay links, carrying light at their coarser level, and later
  // updates' passes split them. The pairs a move meets are still all estimated again (the
  // light must not pass through the moved object), and the solve still runs. With a limit the
  // hierarchy depends on the machine's speed: verification runs without one.
  double frameBudgetSeconds = 0;
  // Worker threads for link estimation (0: all cores); the result does not depend on it.
  int threads = 1;
  ShaftPolicy shafts = ShaftPolicy::kManaged;
  ShaftManagement management;  // for ShaftPolicy::kManaged
};

// The Galerkin options a front end's radiosity options ask for: the tolerance, the budgets, the
// threads.
GalerkinOptions galerkinOptionsFrom(const RadiosityOptions& radiosity);

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
  int passes = 0;                 // refinement passes (a build's first from the root)
  bool settled = false;           // the last pass changed no pair (refinementPasses)
  std::size_t elementBytes = 0;   // memory in use (vector capacities)
  std::size_t clusterBytes = 0;
  std::size_t linkBytes = 0;
  // The occluder candidate lists held (each shared list once) and what holding every estimated
  // pair's list would take (ShaftPolicy::kAll), by the bytes each list's ids and its block use.
  long long shafts = 0;
  std::size_t shaftBytes = 0;
  std::size_t allShaftBytes = 0;
  std::size_t solveBytes = 0;  // what a solve keeps for the next (its links' copy and sums)
  std::size_t totalBytes() const {
    return elementBytes + clusterBytes + linkBytes + shaftBytes + solveBytes;
  }
  double refineSeconds = 0;
  double solveSeconds = 0;
  double totalSeconds = 0;
};

// What one line-space update did (GalerkinRadiosity::update).
struct GalerkinUpdateStats {
  bool rebuilt = false;  // recomputed from scratch instead (the reason below)
  const char* rebuildReason = "";
  long long movedElements = 0;     // elements re-posed
  long long coverChanged = 0;      // elements whose contact cover changed
  long long clustersChanged = 0;   // clusters whose box changed
  long long shaftTests = 0;        // pairs whose shaft was tested against the moved boxes
  long long met = 0;               // pairs the move may have changed (shaft or end)
  long long endMoved = 0;          // of them, pairs with an end (or inherited candidates) changed
  long long coverOnly = 0;         // of those, an end only re-covered: shaft and candidates kept
  long long reestimated = 0;       // of them, estimated again (the others: a cluster's self pair)
  long long reusedVisibility = 0;  // point pairs whose stored visibility the move left as it was
  long long refined = 0;           // links split because of the move
  long long cleanedUp = 0;         // split pairs made links again, their children dropped
  long long created = 0;           // new pairs estimated below new splits
  long long dropped = 0;           // pairs dropped with cleaned-up subtrees
  bool compacted = false;          // the dropped pairs' storage was reclaimed
  long long mergedElements = 0;    // elements merged back into their parents (then)
  long long laterSplits = 0;       // pairs added by the passes on the solves' radiosities
  long long laterCleanUps = 0;     // split pairs those passes made links again
  long long deferredSplits = 0;    // splits the frame budget left to later updates
  bool overBudget = false;         // the frame budget ran out (frameBudgetSeconds)
  // Shaft management (Schöffel & Pomi's Table 2); the prediction's and collection's figures are
  // those of the work after this update, for the next (ShaftManagement::workerThread).
  long long shaftsAtOld = 0;      // tested pairs whose shaft a moved object's old box meets
  long long shaftsAtNew = 0;      // ... its new box
  long long shaftsMade = 0;       // lists made on the fly where they were not kept
  long long shaftsRemade = 0;     // met pairs whose ends or parent's list changed: made anew
  long long shaftsThere = 0;      // met pairs whose candidates were kept from before
  long long shaftsCounted = 0;    // met pairs that needed only how many they hold (kManaged)
  long long predictionTests = 0;  // shafts tested against the predicted boxes
  long long shaftsPredicted = 0;  // lists made ahead on the predicted boxes
  long long shaftsCollected = 0;  // lists released by garbage collection
  double shaftSeconds = 0;        // prediction and collection (on the worker thread if any)
  double shaftWaitSeconds = 0;    // this update waited for the last one's shaft work
  double reposeSeconds = 0;       // elements, contacts, cluster boxes, emission lobes
  double traverseSeconds = 0;     // the walk and the re-estimates
  double walkSeconds = 0;         // of it, deciding which pairs are met (shaft tests)
  double refineSeconds = 0;       // new subtrees, and the passes after the first solve
  double solveSeconds = 0;
  double totalSeconds = 0;
};

class GalerkinRadiosity {
 public:
  explicit GalerkinRadiosity(const GalerkinOptions& options = {});
  ~GalerkinRadiosity();  // waits for the shaft work
  // The shaft worker holds `this`: neither copied nor moved.
  GalerkinRadiosity(const GalerkinRadiosity&) = delete;
  GalerkinRadiosity& operator=(const GalerkinRadiosity&) = delete;

  // Builds the hierarchy at the scene's current pose and solves (the scene's grid and ray
  // caster are used during the call only).
  void build(const DynamicScene& scene);
  // The solution at the scene's new pose after `change` was applied to it, by the line-space
  // update (galerkin_update.cpp): not bit for bit a fresh build (refinement keeps its history),
  // but every pair it keeps is estimated exactly as a fresh estimate at this pose would be
  // (verifyLinks). Rebuilds from scratch when the scene's extent grew or nothing was built.
  void update(const DynamicScene& scene, const SceneChange& change);
  // Re-estimates every pair of the hierarchy as it stands (candidates from the root down,
  // cluster boxes, element shapes and covers recomputed from the scene) and compares each with
  // what is stored, bit for bit: empty when all agree, else the first difference in words.
  std::string verifyLinks() const;
  // Compares this solution with another bit for bit — every pair's state, ends and coefficients,
  // every element's radiosity — and returns the first difference in words (empty: none). Two
  // solvers that differ only in cost settings (shaft policy, threads) must agree.
  std::string differenceFrom(const GalerkinRadiosity& other) const;
  const GalerkinUpdateStats& lastUpdate() const {
    awaitShaftWork();
    return lastUpdate_;
  }
  // Frame-rate control from the next update on (GalerkinOptions::frameBudgetSeconds; 0: none):
  // an interactive front end can tighten it while an object is dragged, and lift it after.
  void setFrameBudget(double seconds) { options_.frameBudgetSeconds = seconds; }
  // What one more refinement and clean-up pass on the present radiosities would change: links it
  // would split, and split pairs whose own estimate it would find good enough.
  struct PendingRefinement {
    long long splits = 0, cleanUps = 0;
  };
  PendingRefinement pendingRefinement() const;

  // Direct and indirect irradiance and radiosity at a point on the front of a receiver, from the
  // linear functions of the leaf holding it (negative values of a steep linear function clamped
  // to 0); nothing when the point lies on no polygon facing `normal`.
  std::optional<RadiositySample> sample(const Vec3& point, const Vec3& normal) const;
  Rgb irradiance(const Vec3& point, const Vec3& normal) const;
  // The solution as drawn: the leaves' triangles, each corner with the area-weighted mean of the
  // linear functions of the leaves of its polygon that meet there.
  RadiosityMesh leafMesh() const;

  // Power emitted (over the polygons' exposed parts: a part a polygon in contact covers emits
  // nothing) and absorbed ((1 − ρ) ∫ E over the leaves), W per channel.
  Rgb emittedPower() const;
  Rgb absorbedPower() const;

  // The counts and memory are taken when asked for (a walk over every pair: reporting, not part
  // of a build's or an update's work or time).
  const GalerkinStats& stats() const;

  // What the solver holds per element and per cluster (public for tests).
  // The fields each Jacobi iteration reads and writes come first, together: push-pull visits
  // every node in every iteration, and an element is ~900 bytes of which it reads ~300 (on the
  // furnished room's updates, three runs in turns: 37.7 -> 35.7 ms median, a gain of the size
  // of the machine's drift between runs).
  struct Node {
    Rgb emission;                // M (area mean for a cluster)
    LinearRgb gatheredDirect{};  // over the node's own links (the indirect: in the solve's state)
    LinearRgb radiosity{};       // B (a cluster: its area mean in [0])
    double maxRadiosity = 0;     // a bound on B over the leaves below
    double maxReflectance = 0;   // the largest reflectance below
    LinearRgb irradianceDirect{}, irradianceIndirect{};  // with what ancestors pushed down
  };
  struct GElement {
    int firstChild = -1;
    double area = 0;
    Rgb reflectance;
    BasisTransfer fromParent{};  // the parent's basis over this element (push and pull)
    Node node;
    LinearBasis basis;
    ElementShape shape;
    Cubature cubature;  // where links sample it (linkCubature), kept: links read it often
    std::array<std::array<double, 3>, 4> cubatureBasis{};  // the basis at those points
    PolygonId polygon = 0;
    int parent = -1;
    // How much of it a polygon in face-to-face contact covers (face_contacts.h), judged at its
    // link cubature points and centroid: a covered point sees only the covering polygon.
    enum Cover : std::uint8_t { kExposed, kPartlyCovered, kCovered };
    Cover cover = kExposed;
    // kPartlyCovered: which of its cubature points are covered (bit i: point i), what its
    // links' estimates read; a move of a polygon in contact changes the estimates only if it
    // changes these.
    std::uint8_t coveredPoints = 0;
    // A root element: the share of its area no polygon in contact covers, by which it takes what
    // arrives on its cluster's lobes and gives them its emission (exposedShareOf; its reflected
    // light it gives whole: addLobes).
    float exposedShare = 1;
    bool isLeaf() const { return firstChild < 0; }
  };
  struct GCluster {
    ClusterNode structure;
    Node node;
    // What the cluster's surfaces send (B A per lobe: emission, and reflected radiosity pulled
    // up), and what arrived over the cluster's own links and from the clusters above it, on the
    // six axis lobes (axis_lobes.h); the node's linear functions hold only area means.
    AxisLobes emittedLobes{}, reflectedLobes{};
    AxisLobes gatheredDirectLobes{};  // (the indirect: in the solve's state)
  };
  // The occluder candidates of a pair's shaft (shared: a split hands them to every child).
  using Candidates = std::shared_ptr<const std::vector<PolygonId>>;
  // A node pair the refinement met. All are kept, not only the links (the refinement's history,
  // Drettakis & Sillion's passive links), so that a move can revisit exactly the pairs whose
  // shafts it crosses. A pair's children are contiguous in links().
  struct GLink {
    enum State : std::uint8_t {
      kActive,   // a link: carries light in the solve
      kPassive,  // split: its children (one end's children with the other end) replace it
      kSelf,     // a cluster with itself: every pair of its children
      kNone,     // the ends cannot exchange light (back to back, covered, one polygon)
      kDropped,  // removed by an update's clean-up (storage left until the next build)
    };
    NodeRef receiver, source;
    // K[β][α], β over the receiver's basis, α over the source's. A cluster end has one
    // coefficient: a cluster source's is per unit of the exitance its lobes send towards the
    // receiver, a cluster receiver's is the flux density arriving over `lobes`.
    std::array<double, 9> k{};
    // With a cluster end: its point pairs' directions from the receiver towards the source
    // (Estimate::lobes): a cluster receiver takes its light over them, a cluster source sends
    // over opposite(lobes).
    LobeWeights lobes{};
    float meanTransfer = 0;         // the mean point-pair transfer (K[0][0])
    float spread = 0;               // max − min of the point-pair transfers
    float hiddenTransfer = 0;       // what its pairs found hidden would carry
    std::uint16_t hiddenPairs = 0;  // which point pairs were hidden (Estimate::hiddenPairs)
    bool everyRay = false;
    State state = kActive;
    bool splitReceiver = false;  // kPassive: the end split was the receiver
    // kPassive: a child with a moved end made its list from this one's in an update (so the
    // next move of that object needs it again, however long it is).
    bool feedsMovedEnd = false;
    int parent = -1;      // the pair it came from (-1: the root's pair with itself)
    int firstChild = -1;  // kPassive, kSelf: its children, contiguous
    int childCount = 0;
    // The occluder candidates its estimate used (kSelf: its parent's), which its children's
    // are filtered from; a move edits them (Drettakis & Sillion's shafts, here as their
    // contents). Under ShaftPolicy::kManaged they may be absent: made again when needed.
    Candidates candidates;
    std::uint32_t candidateCount = 0;  // how many there are, kept or not
    std::uint32_t shaftUsed = 0;       // the update that last made or used them (their age)
    bool active() const { return state == kActive; }
  };
  const std::vector<GElement>& elements() const { return elements_; }
  const std::vector<GLink>& links() const {
    awaitShaftWork();
    return links_;
  }

 private:
  struct EndTerms;
  struct Estimate;
  struct Counters;
  void clear();
  void countStats() const;
  void countShafts() const;  // GalerkinStats' shafts, shaftBytes, allShaftBytes
  // The share of the element's area that no polygon in contact covers: 1 exposed, 0 covered,
  // else counted on a stratified 8 x 8 sample of it.
  float exposedShareOf(const GElement& e) const;
  // Can any light leave s and reach r (their fronts face each other somewhere)?
  bool canExchange(NodeRef r, NodeRef s) const;
  struct VisibilityReuse;
  // A segment is tested against its link's candidates' boxes before a ray is cast only when there
  // are at most this many; past them an estimate reads only how many there are.
  static constexpr std::size_t kMostBoxesTested = 16;
  // What an estimate reads of a pair's occluder candidates: how many, and the polygons
  // themselves when there are at most kMostBoxesTested.
  struct CandidateView {
    std::size_t count = 0;
    const std::vector<PolygonId>* ids = nullptr;
    static CandidateView of(const std::vector<PolygonId>& list) { return {list.size(), &list}; }
  };
  Estimate estimate(NodeRef r, NodeRef s, const CandidateView& candidates, Counters& counters,
                    const VisibilityReuse* reuse = nullptr) const;
  // The polygons of `among` that may meet the link's shaft.
  std::vector<PolygonId> shaftCandidates(NodeRef r, NodeRef s,
                                         const std::vector<PolygonId>& among) const;
  // The polygons of `among` that may meet `shaft`, but for the pair's own and those `skip` marks.
  std::vector<PolygonId> candidatesIn(const Shaft& shaft, NodeRef r, NodeRef s,
                                      const std::vector<PolygonId>& among,
                                      const std::vector<char>* skip = nullptr) const;
  // The polygons of the pair's element ends (-1 for a cluster end): never their own occluders.
  std::pair<PolygonId, PolygonId> ownPolygons(NodeRef r, NodeRef s) const;
  double oracle(NodeRef r, NodeRef s, double meanTransfer, double spread,
                double hiddenTransfer) const;
  // What the oracle weighs the receiver's area and the source's largest radiosity by.
  double oracleVariation(NodeRef r, NodeRef s, double meanTransfer, double spread,
                         double hiddenTransfer) const;
  // What a refinement pass reads of a pair, but the source's radiosity, kept in a dense array
  // beside the pairs: a pass scans every pair, twice per update, and a pair's record is large.
  // A pair's key is made again when it has changed (beforeChange marks it stale), all of them
  // after a compaction renumbers the pairs. The oracle from a key is the stored pair's, bit for
  // bit (the same terms multiplied in the same order).
  struct PassKey {
    double receiverArea = 0, variation = 0;
    NodeRef source;
    GLink::State state = GLink::kNone;
  };
  std::vector<PassKey> passKeys_;
  std::vector<char> passKeyStale_;  // per pair: changed since its key was made
  // A pair's key, made again first if it is stale.
  const PassKey& passKey(int pair);
  void dropPassKeys() {
    passKeys_.clear();
    passKeyStale_.clear();
  }
  PassKey passKeyOf(const GLink& link) const;
  double oracleOf(const PassKey& key) const {
    return key.receiverArea * nodeOf(key.source).maxRadiosity * key.variation;
  }
  // Empty when every key that is not stale is its pair's made again, else the first difference.
  std::string verifyPassKeys() const;
  // The oracle on a stored pair's estimate.
  double oracleOf(const GLink& link) const {
    return oracle(link.receiver, link.source, link.meanTransfer, link.spread, link.hiddenTransfer);
  }
  // The oracle on an estimate as the pair will store it (its terms rounded to float), so that a
  // pass over the stored pairs decides as the refinement that made them did.
  double oracleOf(NodeRef r, NodeRef s, const Estimate& e) const;
  // Would a refinement pass split this link (its oracle past the threshold, an end splittable)?
  bool asksToSplit(const GLink& link) const {
    return link.active() && oracleOf(link) > threshold_ &&
           endToSplit(link.receiver, link.source).has_value();
  }
  // The interactions of receivers with sources still to estimate and refine, each with the
  // occluder candidates of the pair it comes from, and that pair's index (-1: none).
  struct RefineTask {
    NodeRef receiver, source;
    Candidates candidates;
    int parent = -1;
  };
  // Refines the tasks' interactions until the oracle is satisfied (refinement.cpp).
  void refine(std::vector<RefineTask> wave, Counters& counters);
  // The end of a link to split: the larger one (by its box's diagonal) if it can be split, else
  // the other, else none.
  std::optional<NodeRef> endToSplit(NodeRef r, NodeRef s) const;
  // Queues the interactions that replace r with s once `end` (r or s) is split; `parent` is
  // their pair's index.
  void queueChildren(NodeRef r, NodeRef s, NodeRef end, const Candidates& candidates, int parent,
                     std::vector<RefineTask>& wave);
  // Appends the pair a task became (its estimate when it exchanges) and links it to its parent.
  int appendPair(const RefineTask& task, GLink::State state, const Estimate* estimate);
  static void storeEstimate(GLink& link, const Estimate& e);
  // A pair's candidates (a subset of its parent's), stored once: the parent's own list when
  // they are all of it, one shared empty list when none.
  static Candidates shared(std::vector<PolygonId> own, const Candidates& inherited);
  // A pair keeps `own`, its estimate's candidates, and their count.
  void keepCandidates(GLink& link, const Candidates& own);
  // Marks a pair's list as used by this update (its age) and, under ShaftPolicy::kManaged,
  // names it among the lists the collection looks at.
  void touchShaft(int pair);
  // The pairs whose lists were made or used since the last collection, and those it kept (ids
  // may repeat): the collection looks at these, not at every pair.
  std::vector<int> shaftHolders_;
  // A pair's candidates, made from its parent's (recursively, the root's always kept) when they
  // are absent; stamped as used by this update. On one thread only.
  const Candidates& candidatesFor(int pair);
  long long listsMade_ = 0;  // by candidatesFor (what an update counts as made on the fly)
  // Removes the dropped pairs from storage (every index changes).
  void compactPairs();
  // Merges back every split whose subtree no live pair names (a move or a clean-up left it
  // unused) and removes those elements from storage (element indices change); returns how many.
  // Run after compactPairs, so that every stored pair is live.
  long long compactElements();
  // Marks a pair's descendants dropped (their candidates released); returns how many.
  long long dropChildren(int pair);
  // The line-space update's steps (galerkin_update.cpp).
  struct Move;
  // Re-poses the moved elements, re-covers, refits the clusters; nothing when the update cannot
  // follow the move (a rebuild then).
  // `moved`: the moved polygons, ascending, with their bounds at the last pose.
  std::optional<Move> prepareMove(const SceneChange& change,
                                  const std::vector<std::pair<PolygonId, Box3>>& moved);
  // Walks the pairs from the root, re-estimating the met ones; new subtrees go to `fresh`.
  void walkPairs(const Move& move, Counters& counters, std::vector<RefineTask>& fresh);
  // The moved polygons of a pair's candidates, before the move (their old bounds, the pair's
  // old shaft) or after it, filtered from its parent's: a few positions in Move::movedIds, so
  // cheap where the whole list is not.
  using MovedPart = std::shared_ptr<const std::vector<std::uint32_t>>;
  // The moved part after the last update's move of each pair it met, and which polygons that
  // move moved: when the next update moves the same ones, a pair's part before its move is that
  // (the same filtering, from the root down, of the same boxes by the same shafts).
  std::unordered_map<int, MovedPart> lastMovedAfter_;
  // The end terms of each pair the last update's walk estimated: a pair met again with the same
  // ends reads them instead of computing its kernel and exact form factors again.
  std::vector<EndTerms> lastEnds_;
  std::unordered_map<int, int> lastEndsOf_;  // pair -> its place in lastEnds_
  std::vector<PolygonId> lastMovedIds_;
  MovedPart movedPart(const Move& move, NodeRef r, NodeRef s, const MovedPart& parentPart,
                      bool before) const;
  // The moved part after the move of a pair whose candidates were just filtered from its
  // parent's (`own`): the moved polygons among them. movedPart(…, false) gives the same, from
  // the same shaft tests, which `own` has made already.
  static MovedPart movedAmong(const Move& move, const std::vector<PolygonId>& own,
                              const MovedPart& parentPart);
  // A kept pair's candidates at the new pose: its old ones without the moved polygons, merged
  // in order with the moved ones it has now (movedPart), as a fresh filtering gives them.
  static std::vector<PolygonId> withMovedPolygons(const Move& move,
                                                  const std::vector<PolygonId>& old,
                                                  const std::vector<std::uint32_t>& movedNow);
  void setState(GLink& link, GLink::State state);  // keeps linkCount_
  // The static polygons (none of the move's) of `among` that the pair's shaft admitted at the
  // last pose: its old list's part a move cannot change, when the list itself was not kept.
  std::vector<PolygonId> staticCandidatesBefore(const Move& move, NodeRef r, NodeRef s,
                                                const std::vector<PolygonId>& among) const;
  Box3 boundsBefore(const Move& move, NodeRef n) const;
  bool reposeMovedObjects(const SceneChange& change, Move& move);
  // A cluster's box and area from its root elements, summed as the builder sums them.
  struct ClusterExtent {
    Box3 bounds;
    double area = 0;
  };
  ClusterExtent extentOf(const ClusterNode& cluster) const;
  void refitClusters(std::vector<char>& clusterChanged);
  void refreshEmission(NodeRef n);
  // Groups of root elements for the movable hierarchy: the static scene, then each object that
  // moves (keyframes), with where each root sits for the octants.
  void buildHierarchy(const Scene& scene, const std::vector<Element>& roots);
  bool refineActiveLinks(Counters& counters);
  // One refinement pass: splits the links whose oracle exceeds the threshold (refining below
  // them) and, when cleanUpBelow >= 0, makes split pairs whose oracle is at most cleanUpBelow
  // links again (their subtrees dropped).
  struct PassOutcome {
    bool split = false;
    long long cleanedUp = 0, dropped = 0;
  };
  PassOutcome refinementPass(Counters& counters, double cleanUpBelow);
  // A split pair is cleaned up when its oracle falls below this share of the threshold, not
  // at the threshold: a pair whose oracle sits at the threshold would otherwise be split and
  // cleaned up in turn as each solve moves the radiosities by a little.
  static constexpr double kCleanUpShare = 0.5;
  // Refinement brought to rest on its own radiosities: clean-up and refinement passes, each
  // followed by a solve, until a pass changes no pair (or refinementPasses in all).
  // `decideAnew`: the radiosities changed everywhere (a moved light), so the first clean-up
  // pass decides every split pair as a fresh refinement would, at the threshold itself.
  struct Settling {
    int rounds = 0;
    bool settled = false;
    long long added = 0, cleanedUp = 0, dropped = 0;
    double refineSeconds = 0, solveSeconds = 0;
    int passes() const { return rounds + (settled ? 1 : 0); }  // the last changed nothing
  };
  Settling settle(Counters& counters, bool decideAnew = false);
  // An update's record of its passes (`passesBefore` run before settle) and the end of its
  // frame budget.
  void recordPasses(const Settling& settling, int passesBefore);
  // compactPairs and compactElements once dropped pairs are a quarter of storage.
  void compactIfWorthIt();
  // Sets the element's basis and cubature from its shape.
  static void prepare(GElement& e);
  // Gives `child` its shape (one of the parent's childVertices()), basis and area: the same
  // whether the parent is split for the first time or moved with its object.
  static void shapeChild(const GElement& parent, const std::array<Vec3, 4>& vertices,
                         GElement& child);
  // The cover a fresh split would give the element (a root's own; a child's from its parent's).
  GElement::Cover freshCover(const GElement& e) const;
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
  // Jacobi iterations until the largest change of B < convergence x the largest reflected B;
  // `fromPrevious`: starting from a solution near this one (an update), carrying only what
  // changed: the links changed since the last solve, then the sources that changed.
  // The irradiance the queries read is stored once the solution is final (storeIrradiance),
  // by build and update, not by each solve.
  void solve(double convergence, bool fromPrevious = false);
  // What a solve leaves for the next (galerkin_solve.cpp): which links carry light, by source,
  // and the sums they made. Valid from a solve on; a compaction renumbers it with the pairs and
  // elements (renumberSolveState…).
  struct SolveState;
  std::unique_ptr<SolveState> solveState_;
  // The pairs whose state or coefficients changed since the last solve (while its state is
  // valid), each once: what the next solve carries anew.
  std::vector<int> changedPairs_;
  std::vector<char> pairChanged_;
  // To be called when a pair's state or coefficients change (and once a pair is appended): what
  // it carried is taken back from the sums, and the next solve carries it anew if it is then a
  // link.
  void beforeChange(int pair);
  void invalidateSolveState();
  // After a compaction: `newIndex` maps each old pair (element) to its new place, -1 where it
  // was dropped (merged away, then with nothing carried to or from it but rounding residue).
  void renumberSolveStatePairs(const std::vector<int>& newIndex, size_t pairCount);
  void renumberSolveStateElements(const std::vector<int>& newIndex, size_t elementCount);
  std::size_t solveStateBytes() const;
  // Checks the state against the pairs (the links it holds are the active ones, as stored, but
  // for the pairs noted as changed) and its sums against the sums made again from what it says
  // each source sent (equal but for rounding): empty when all agree, else what differs.
  std::string verifySolveState() const;
  // Pushes the irradiance `n` gathered, direct and indirect together (plus what element
  // ancestors pushed, in n's basis, and the lobes of cluster ancestors), down to the leaves, sets
  // B there and pulls it back up; returns the largest change of a leaf's B, and raises
  // `largestReflected` to the largest reflected B (B − M) of a leaf below n. The iterations need
  // only the sum: the two parts are pushed once, after them (storeIrradiance).
  double pushPull(NodeRef n, const LinearRgb& arrived, const AxisLobes& arrivedLobes,
                  double& largestReflected);
  // Pushes the direct and the indirect irradiance down apart and keeps them at every element
  // (Node::irradianceDirect, irradianceIndirect), for the queries of the solution.
  void storeIrradiance(NodeRef n, const LinearRgb& direct, const LinearRgb& indirect,
                       const AxisLobes& directLobes, const AxisLobes& indirectLobes);
  // From the root, once the solution is final (before a compaction renumbers the elements the
  // solve's sums are kept by).
  void storeIrradiance() { storeIrradiance({NodeRef::kCluster, 0}, {}, {}, {}, {}); }
  std::optional<int> leafContaining(const Vec3& point, const Vec3& normal) const;
  // Is x, a point of `polygon`, covered by a polygon in face-to-face contact with it?
  bool isCovered(PolygonId polygon, const Vec3& x) const;
  GElement::Cover coverOf(const GElement& e) const;
  // GElement::coveredPoints for an element whose cover is set.
  std::uint8_t coveredPointsOf(const GElement& e) const;

  // Dynamic shaft management (galerkin_shafts.cpp). After an update: the moved objects' boxes
  // predicted for the next moves (ShaftManagement), from their recorded poses.
  void recordPoses(const SceneChange& change);
  std::vector<Box3> predictedBoxes(const SceneChange& change) const;
  // Makes the lists of the pairs whose shafts the boxes meet, then collects old lists; on the
  // worker thread when there is one.
  void manageShafts(std::vector<Box3> predicted);
  // Is a pair's list worth keeping beyond the update that used it (ShaftManagement::keepCount)?
  bool worthKeeping(const GLink& link) const;
  void startShaftWork(const SceneChange& change);
  // Waits for the worker's shaft work, if any (every call that reads or changes pairs does).
  void awaitShaftWork() const;
  // Releases every list but the root pair's (a managed build's start).
  void releaseShafts();
  bool managed() const { return options_.shafts == ShaftPolicy::kManaged; }

  // Has the update run past its frame budget? (Never during a build.)
  bool overBudget() const;
  // A split the oracle asks for, left to a later update when over budget (counted).
  bool deferSplit();

  GalerkinOptions options_;
  Stopwatch frameClock_;        // since the update began
  bool frameBudgeted_ = false;  // an update with options_.frameBudgetSeconds is running
  PosedScene scene_;
  // The polygons' bounds side by side (shafts test long candidate lists against them, and the
  // scene's polygons hold far more).
  std::vector<Box3> polygonBounds_;
  void takeScene(const DynamicScene& scene);  // scene_, polygonBounds_, grid_, rays_
  const UniformGrid* grid_ = nullptr;
  const RayCaster* rays_ = nullptr;
  std::vector<GElement> elements_;
  std::vector<std::vector<int>> polygonRoots_;
  // The polygons that may cover each polygon (coveringPolygons).
  std::vector<std::vector<PolygonId>> contacts_;
  std::vector<GCluster> clusters_;  // [0] is the root
  std::vector<int> rootOrder_;      // root elements in cluster order
  std::vector<GLink> links_;
  long long linkCount_ = 0;  // active and passive pairs (the --max-links budget)
  GalerkinUpdateStats lastUpdate_;
  double threshold_ = 0;  // tolerance x emitted power
  double minArea_ = 0;
  mutable GalerkinStats stats_;
  mutable bool statsCounted_ = false;
  long long droppedPairs_ = 0;  // dropped pairs still in storage
  std::uint32_t serial_ = 0;    // updates since the build (GLink::shaftUsed)
  // Each object's box at its last poses (the newest last, at most three): movement prediction.
  std::vector<std::vector<Box3>> poses_;
  mutable std::thread shaftWorker_;
};

}  // namespace penumbra
