#pragma once
// The penumbra-view main loop: a GLFW window showing SceneView's image 1:1 with a Dear ImGui
// panel beside it (method, frame, play/step, light samples, exposure, camera, screenshot, the
// selected object and what the last update did).
//
// Keys: Space play/pause, Right/Left step a frame, 1/2/3 raytrace/radiosity/volumes, R reset the
// camera, P screenshot, Q/E turn the selected object 5 degrees about world up, Esc quit.
// Left-drag orbits the camera, the wheel zooms. Ctrl+click picks the object (or light) under the
// cursor; Ctrl+drag moves it in the horizontal plane through the picked point (with Shift: the
// plane facing the camera). Every move goes to the engines as a SceneChange
// (SceneView::moveObject).

#include "viewer_options.h"

namespace penumbra::viewer {

// Runs the viewer until the window closes (or, with options.screenshot, until the screenshot is
// written). Returns the process exit code. Throws InputError for a bad scene and RenderError when
// no window can be opened.
int runViewer(const ViewerOptions& options);

}  // namespace penumbra::viewer
