#include "drag_script.h"

#include <charconv>
#include <cmath>

#include "object_drag.h"
#include "viewer_options.h"

namespace penumbra::viewer {
namespace {

// The whole of `text` as one finite number (from_chars rounds correctly, as the scene loader's
// JSON numbers do, so a drag and a keyframe written with the same digits agree bit for bit).
std::optional<double> parseNumber(const std::string& text) {
  double value = 0;
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(text.data(), end, value);
  if (text.empty() || error != std::errc() || stop != end || !std::isfinite(value))
    return std::nullopt;
  return value;
}

}  // namespace

std::optional<ScriptedDrag> parseScriptedDrag(const std::string& text) {
  std::size_t colon = text.rfind(':');
  if (colon == std::string::npos) return std::nullopt;
  ScriptedDrag drag;
  std::string vector = text.substr(colon + 1);
  if (vector.find(',') == std::string::npos) {  // the last field is the angle
    const std::optional<double> degrees = parseNumber(vector);
    if (!degrees || colon == 0) return std::nullopt;
    drag.degrees = *degrees;
    const std::size_t end = colon;
    colon = text.rfind(':', end - 1);
    if (colon == std::string::npos) return std::nullopt;
    vector = text.substr(colon + 1, end - colon - 1);
  }
  drag.object = text.substr(0, colon);
  if (drag.object.empty()) return std::nullopt;
  const std::size_t first = vector.find(','), second = vector.find(',', first + 1);
  if (second == std::string::npos || vector.find(',', second + 1) != std::string::npos)
    return std::nullopt;
  const std::optional<double> x = parseNumber(vector.substr(0, first));
  const std::optional<double> y = parseNumber(vector.substr(first + 1, second - first - 1));
  const std::optional<double> z = parseNumber(vector.substr(second + 1));
  if (!x || !y || !z) return std::nullopt;
  drag.translation = {*x, *y, *z};
  return drag;
}

int findDraggedObject(const Scene& scene, const std::string& name) {
  int found = -1;
  std::string names;
  for (int o = 0; o < int(scene.objects.size()); ++o) {
    names += (o == 0 ? "" : ", ") + scene.objects[o].name;
    if (scene.objects[o].name != name) continue;
    if (found >= 0) throw OptionError("--drag", "more than one object is named '" + name + "'");
    found = o;
  }
  if (found < 0)
    throw OptionError("--drag",
                      "no object named '" + name + "' in the scene (objects: " + names + ")");
  return found;
}

void applyScriptedDrag(SceneView& view, int object, const ScriptedDrag& drag) {
  if (drag.translation != Vec3{})
    view.moveObject(object, translatedBy(view.live().transformOf(object), drag.translation));
  if (drag.degrees != 0)
    view.moveObject(object, rotatedAboutUp(view.live().transformOf(object),
                                           view.boundsOf(object).center(), drag.degrees));
}

}  // namespace penumbra::viewer
