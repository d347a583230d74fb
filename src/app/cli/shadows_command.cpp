// `penumbra shadows SCENE [--frames A:B] --mode full [--report R.json] [--out DIR]`: the exact
// soft-shadow engine (discontinuity mesh with backprojections) over a range of frames, with the
// statistics of every stage and structure.

#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "frame_range.h"
#include "frame_walk.h"
#include "penumbra/dm/discontinuity_mesh_engine.h"
#include "penumbra/dm/irradiance_mesh.h"
#include "penumbra/render/ply_writer.h"
#include "penumbra/scene/scene_loader.h"
#include "progress.h"
#include "report_file.h"

namespace penumbra::cli {

namespace {

nlohmann::json statsJson(const DmStats& s) {
  return {{"lights", s.lights},
          {"update",
           {{"moved_objects", s.movedObjects},
            {"recomputed_all", s.recomputedAll},
            {"kept_meshes", s.keptMeshes},
            {"carried_inputs", s.carriedInputs},
            {"rebuilt_meshes", s.rebuiltMeshes},
            {"edited_meshes", s.editedMeshes},
            {"removed_surfaces", s.removedSurfaces},
            {"inserted_surfaces", s.insertedSurfaces},
            {"reswept_meshes", s.resweptMeshes},
            {"reused_faces", s.reusedFaces},
            {"recomputed_faces", s.recomputedFaces},
            {"kept_casts", s.keptCasts},
            {"recast_with_moved_only", s.recastMovedCasts},
            {"kept_traces", s.keptTraces},
            {"kept_eee_candidate_cuts", s.keptCandidateCuts},
            {"examined_eee_candidate_cuts", s.examinedCandidateCuts},
            {"kept_non_emitter_vertices", s.keptNonEmitterVertices},
            {"examined_non_emitter_vertices", s.examinedNonEmitterVertices},
            {"kept_coplanar_crossing_pairs", s.keptCoplanarPairs},
            {"examined_coplanar_crossing_pairs", s.examinedCoplanarPairs},
            {"kept_parallel_crossing_planes", s.keptParallelPlanes},
            {"examined_parallel_crossing_planes", s.examinedParallelPlanes},
            {"kept_occluder_planes", s.keptOccluderPlanes},
            {"examined_occluder_planes", s.examinedOccluderPlanes}}},
          {"surfaces",
           {{"ev_light_vertex_occluder_edge", s.surfacesEmitterVertex},
            {"ev_light_edge_occluder_vertex", s.surfacesEmitterEdge},
            {"ev_non_emitter", s.surfacesNonEmitter},
            {"eee_light_edge_occluder_plane", s.surfacesOccluderPlane},
            {"ev_occluder_plane_occluder_edge", s.surfacesOccluderPlaneEdge},
            {"ev_occluder_plane_own_vertex", s.surfacesOccluderPlaneVertex},
            {"eee_light_edge_coplanar_edges", s.surfacesCoplanarEdges},
            {"eee_light_edge_parallel_edge_crossing", s.surfacesParallelEdgeCrossing},
            {"eee_coplanar_edges_occluder_crossing", s.surfacesCoplanarEdgeCrossing},
            {"eee_light_edge_two_occluder_edges", s.surfacesEee},
            {"eee_three_occluder_edges", s.surfacesEeeOccluder},
            {"total", s.surfacesEmitterVertex + s.surfacesEmitterEdge + s.surfacesNonEmitter +
                          s.surfacesOccluderPlane + s.surfacesOccluderPlaneEdge +
                          s.surfacesOccluderPlaneVertex + s.surfacesCoplanarEdges +
                          s.surfacesParallelEdgeCrossing + s.surfacesCoplanarEdgeCrossing +
                          s.surfacesEee + s.surfacesEeeOccluder}}},
          {"eee_polyline_segments", s.eeeSegments},
          {"eee_surfaces_truncated", s.eeeSurfacesTruncated},
          {"stored_intersections", s.storedIntersections},
          {"visible_segments", s.visibleSegments},
          {"contact_segments", s.contactSegments},
          {"light_plane_segments", s.lightPlaneSegments},
          {"horizon_segments", s.horizonSegments},
          {"mesh",
           {{"vertices", s.meshVertices},
            {"edges", s.meshEdges},
            {"faces", s.meshFaces},
            {"unresolved_faces", s.unresolvedFaces},
            {"sliver_faces", s.sliverFaces}}},
          {"backprojection_vertices", s.backprojectionVertices},
          {"unlabelled_backprojections", s.unlabelledBackprojections},
          {"memory_bytes",
           {{"grid_cell_lists", s.gridBytes},
            {"surface_cell_lists", s.surfaceCellBytes},
            {"stored_intersections", s.intersectionBytes},
            {"meshes", s.meshBytes},
            {"backprojections", s.backprojectionBytes},
            {"update_caches", s.updateCacheBytes}}},
          {"stage_seconds",
           {{"surfaces", s.secondsSurfaces},
            {"casting", s.secondsCasting},
            {"visibility", s.secondsVisibility},
            {"eee_tracing", s.secondsEee},
            {"face_verification", s.secondsVerification},
            {"meshing", s.secondsMeshing},
            {"backprojections", s.secondsBackprojections}}}};
}

nlohmann::json receiversJson(const DiscontinuityMeshEngine& engine) {
  nlohmann::json receivers = nlohmann::json::array();
  for (const WorldPolygon& polygon : engine.posedScene().polygons) {
    const ReceiverMesh* mesh = engine.meshOf(polygon.id);
    if (!mesh) continue;
    receivers.push_back({{"polygon", polygon.id},
                         {"vertices", mesh->vertexCount()},
                         {"edges", mesh->edgeCount()},
                         {"faces", mesh->faces().size()}});
  }
  return receivers;
}

}  // namespace

int runShadows(const ShadowsOptions& options, const CommonOptions& common) {
  if (options.mode != "incremental" && options.mode != "full" && options.mode != "verify")
    throw UsageError("--mode must be incremental, full or verify, got '" + options.mode + "'");
  const Scene scene = loadScene(options.scene);
  const FrameRange range = parseFrameRange(options.frames, scene.frames);
  if (!options.outDirectory.empty()) std::filesystem::create_directories(options.outDirectory);
  // incremental and verify: one live scene and one engine held across frames, told each change;
  // full and verify: a fresh scene and engine per frame.
  const bool updating = options.mode != "full";
  const bool verifying = options.mode == "verify";
  DynamicScene live(scene, range.first);
  DiscontinuityMeshEngine engine(options.dm);
  nlohmann::json frames = nlohmann::json::array();
  int differences = 0;
  Progress progress("shadows", range.last - range.first + 1, common.quiet);
  for (int frame = range.first; frame <= range.last; ++frame) {
    const auto start = std::chrono::steady_clock::now();
    std::unique_ptr<DynamicScene> fresh;
    int moved = 0;
    if (!updating) {
      fresh = std::make_unique<DynamicScene>(scene, frame);
      engine.build(*fresh);
    } else {
      moved = buildOrStep(live, engine, frame, frame == range.first);
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const DmStats& s = engine.stats();
    nlohmann::json entry = statsJson(s);
    entry["frame"] = frame;
    entry["seconds"] = seconds;
    entry["moved_objects"] = moved;
    entry["receivers"] = receiversJson(engine);
    std::string verdict;
    if (verifying) {
      const auto fullStart = std::chrono::steady_clock::now();
      const DynamicScene scratchScene(scene, frame);
      DiscontinuityMeshEngine scratch(options.dm);
      scratch.build(scratchScene);
      entry["full_seconds"] =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - fullStart).count();
      const auto difference =
          firstDifference(buildIrradianceMesh(engine), buildIrradianceMesh(scratch));
      entry["identical_to_full"] = !difference;
      if (difference) {
        ++differences;
        entry["difference"] = *difference;
        verdict = ", DIFFERS from a full recomputation: " + *difference;
      } else {
        verdict = ", identical to a full recomputation";
      }
    }
    frames.push_back(entry);
    if (!options.outDirectory.empty()) {
      const IrradianceMesh mesh = buildIrradianceMesh(engine);
      double brightest = 0;
      for (const Rgb& e : mesh.irradiance) brightest = std::max(brightest, e.maxComponent());
      const std::filesystem::path path =
          std::filesystem::path(options.outDirectory) / ("frame-" + std::to_string(frame) + ".ply");
      writeIrradiancePly(mesh, brightest > 0 ? 1 / brightest : 1, path);
    }
    if (!common.quiet)
      std::fprintf(stderr,
                   "frame %d: %.3f s, %lld visible segments, mesh %lld vertices / %lld edges / "
                   "%lld faces%s\n",
                   frame, seconds, s.visibleSegments, s.meshVertices, s.meshEdges, s.meshFaces,
                   verdict.c_str());
    progress.advance();
  }
  if (!options.report.empty()) {
    const nlohmann::json report = {{"method", "dm"},
                                   {"mode", options.mode},
                                   {"eee_surfaces", options.dm.eeeSurfaces},
                                   {"differences", differences}};
    writeReport(report, options.report, options.scene, scene.polygonCount(), frames);
  }
  if (differences > 0) {
    std::fprintf(stderr, "penumbra: verification failed: %d of %d frames differ\n", differences,
                 range.last - range.first + 1);
    return kVerificationFailed;
  }
  return kOk;
}

}  // namespace penumbra::cli
