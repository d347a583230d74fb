#pragma once
// Moving one object (or a light: an object with emitting polygons) by hand. The mouse drag, the
// Q/E keys and the scripted --drag all build the object's new object-to-world transform with these
// functions and hand it to SceneView::moveObject, so a scripted drag is the mouse's code path.
//
// The new transforms are composed from the current one so that a keyframe written as
// translate . rotate (DESIGN.md §4) gives the same Transform bit for bit: a translation only adds
// to the translation, and a rotation about world up multiplies the linear part by the same matrix
// the scene loader makes from { "axis": [0, 1, 0], "degrees": d } (Quaternion::fromAxisAngle with
// d * pi / 180).

#include <optional>

#include "penumbra/geometry/transform.h"
#include "penumbra/geometry/vec3.h"

namespace penumbra::viewer {

// The world's up axis: the scene format's and the scene cameras' +y.
inline constexpr Vec3 kWorldUp{0, 1, 0};

// `transform` followed by a translation by `offset`.
Transform translatedBy(const Transform& transform, const Vec3& offset);
// `transform` followed by a rotation by `degrees` (counter-clockwise seen from above) about the
// vertical line through `centre`.
Transform rotatedAboutUp(const Transform& transform, const Vec3& centre, double degrees);

// A mouse drag of one object: the point grabbed on it follows the cursor in a plane through that
// point (horizontal, or facing the camera), and the object translates with it.
class ObjectDrag {
 public:
  // `start`: the object's transform when it was grabbed at `grabbed`. Precondition: planeNormal is
  // not the zero vector.
  ObjectDrag(int object, const Transform& start, const Vec3& grabbed, const Vec3& planeNormal);

  int object() const { return object_; }
  // The object's transform with the grabbed point where the ray origin + t direction (t > 0)
  // meets the drag plane; nothing when the ray runs parallel to the plane, meets it behind the
  // eye, or farther than `maxDistance` from the grabbed point (a ray grazing the plane would throw
  // the object out of the scene).
  std::optional<Transform> transformFor(const Vec3& origin, const Vec3& direction,
                                        double maxDistance) const;

 private:
  int object_;
  Transform start_;
  Vec3 grabbed_;
  Vec3 normal_;
};

}  // namespace penumbra::viewer
