#pragma once
// The ray through a point of the viewer's image, for picking: the same pinhole as the ray-traced
// image (render/ray_traced_image.cpp) and the GL renderers' projection, so the ray through a
// pixel's centre meets what that pixel shows.

#include "penumbra/geometry/vec3.h"
#include "penumbra/scene/camera.h"

namespace penumbra::viewer {

// The unit direction from camera.eye through image point (x, y) of a width x height image, in
// pixel units from its top-left corner (pixel (i, j) spans [i, i + 1) x [j, j + 1)).
// Preconditions: width, height >= 1; eye != target; up not along the view direction.
Vec3 cameraRayDirection(const Camera& camera, int width, int height, double x, double y);

}  // namespace penumbra::viewer
