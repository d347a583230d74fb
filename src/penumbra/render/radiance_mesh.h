#pragma once
// The engines' solutions as ColoredMesh (per-vertex radiance) for MeshRenderer, the same for the
// CLI's images and the viewer: Lambertian surfaces, radiance = B / π.

#include "penumbra/dm/irradiance_mesh.h"
#include "penumbra/radiosity/radiosity_solver.h"
#include "penumbra/render/mesh_renderer.h"

namespace penumbra {

// Radiosity B at the solution's vertices.
ColoredMesh radianceMesh(const RadiosityMesh& solution);

// Direct light only: ρE on the receivers from the exact irradiance at the triangle corners, and
// the lights' own exitance M on their polygons.
ColoredMesh radianceMesh(const IrradianceMesh& solution, const PosedScene& scene);

}  // namespace penumbra
