#pragma once
// Scripted drags (`penumbra-view --drag "OBJECT:dx,dy,dz[:degrees]"`, repeatable): the headless
// stand-in for a mouse drag, for tests and screenshots. Each one translates the named object by
// (dx, dy, dz) and then, when degrees is given, rotates it about world up through the centre of
// its bounds, through the same calls as the mouse and the Q/E keys (object_drag.h, then
// SceneView::moveObject).

#include <optional>
#include <string>
#include <vector>

#include "penumbra/geometry/vec3.h"
#include "penumbra/scene/scene.h"
#include "scene_view.h"

namespace penumbra::viewer {

struct ScriptedDrag {
  std::string object;  // the object's name in the scene
  Vec3 translation;
  double degrees = 0;  // about world up through the bounds centre, after the translation
};

// Parses "OBJECT:dx,dy,dz" or "OBJECT:dx,dy,dz:degrees" (finite decimal numbers; OBJECT may itself
// contain ':', the numbers are taken from the right). Nothing when malformed.
std::optional<ScriptedDrag> parseScriptedDrag(const std::string& text);

// The index of the object named `name` in `scene`. Throws OptionError naming --drag when no
// object, or more than one, has that name.
int findDraggedObject(const Scene& scene, const std::string& name);

// Moves object `object` (found by findDraggedObject) as `drag` says: one move for the
// translation, one for the rotation (each skipped when zero), as the mouse and Q/E would make them.
void applyScriptedDrag(SceneView& view, int object, const ScriptedDrag& drag);

}  // namespace penumbra::viewer
