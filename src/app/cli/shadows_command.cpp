// `penumbra shadows SCENE [--frames A:B] --mode full [--report R.json] [--out DIR]`: the exact
// soft-shadow engine (discontinuity mesh with backprojections) over a range of frames, with the
// statistics of every stage and structure.

#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "frame_range.h"
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
          {"surfaces",
           {{"ev_light_vertex_occluder_edge", s.surfacesEmitterVertex},
            {"ev_light_edge_occluder_vertex", s.surfacesEmitterEdge},
            {"ev_non_emitter", s.surfacesNonEmitter},
            {"eee_light_edge_occluder_plane", s.surfacesOccluderPlane},
            {"ev_occluder_plane_occluder_edge", s.surfacesOccluderPlaneEdge},
            {"ev_occluder_plane_own_vertex", s.surfacesOccluderPlaneVertex},
            {"eee_light_edge_coplanar_edges", s.surfacesCoplanarEdges},
            {"eee_light_edge_parallel_edge_crossing", s.surfacesParallelEdgeCrossing},
            {"eee_light_edge_two_occluder_edges", s.surfacesEee},
            {"eee_three_occluder_edges", s.surfacesEeeOccluder},
            {"total", s.surfacesEmitterVertex + s.surfacesEmitterEdge + s.surfacesNonEmitter +
                          s.surfacesOccluderPlane + s.surfacesOccluderPlaneEdge +
                          s.surfacesOccluderPlaneVertex + s.surfacesCoplanarEdges +
                          s.surfacesParallelEdgeCrossing + s.surfacesEee + s.surfacesEeeOccluder}}},
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
            {"backprojections", s.backprojectionBytes}}},
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
  if (options.mode != "full")
    throw UsageError("--mode " + options.mode +
                     " is not available in this build (available: full; the incremental update "
                     "is a later issue)");
  const Scene scene = loadScene(options.scene);
  const FrameRange range = parseFrameRange(options.frames, scene.frames);
  if (!options.outDirectory.empty()) std::filesystem::create_directories(options.outDirectory);
  DmOptions engineOptions;
  engineOptions.eeeSurfaces = !options.noEee;
  DiscontinuityMeshEngine engine(engineOptions);
  nlohmann::json frames = nlohmann::json::array();
  Progress progress("shadows", range.last - range.first + 1, common.quiet);
  for (int frame = range.first; frame <= range.last; ++frame) {
    const auto start = std::chrono::steady_clock::now();
    engine.build(scene, frame);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const DmStats& s = engine.stats();
    nlohmann::json entry = statsJson(s);
    entry["frame"] = frame;
    entry["seconds"] = seconds;
    entry["receivers"] = receiversJson(engine);
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
                   "%lld faces\n",
                   frame, seconds, s.visibleSegments, s.meshVertices, s.meshEdges, s.meshFaces);
    progress.advance();
  }
  if (!options.report.empty()) {
    const nlohmann::json report = {
        {"method", "dm"}, {"mode", options.mode}, {"eee_surfaces", !options.noEee}};
    writeReport(report, options.report, options.scene, scene.polygonCount(), frames);
  }
  return kOk;
}

}  // namespace penumbra::cli
