#pragma once
// The camera images of a scene are taken from: the scene file's, or one that frames the scene.
// Shared by `penumbra render` and the viewer so that both show the same picture.

#include "penumbra/scene/camera.h"
#include "penumbra/scene/posed_scene.h"
#include "penumbra/scene/scene.h"

namespace penumbra {

// scene.camera when the file has one; otherwise a camera looking at the centre of `posed`'s
// bounding box from the front (+z), far enough back for the whole box to fit the field of view.
Camera sceneCamera(const Scene& scene, const PosedScene& posed);

}  // namespace penumbra
