#pragma once
// Camera orbit for the viewer: drag to turn the eye around the target, scroll to move it closer
// or farther. Until the user orbits, camera() is the scene's camera unchanged (bit for bit), so
// that what the viewer shows can be compared with `penumbra render`.

#include "penumbra/scene/camera.h"

namespace penumbra::viewer {

class OrbitCamera {
 public:
  explicit OrbitCamera(const Camera& base) : base_(base), current_(base) {}

  // Turns the eye around the target: `yawRadians` about the camera's up axis, `pitchRadians`
  // about its right axis (kept short of the poles so up stays meaningful).
  void orbit(double yawRadians, double pitchRadians);
  // Multiplies the eye's distance to the target by `factor` (> 0).
  void zoom(double factor);
  // Back to the scene's camera.
  void reset() { current_ = base_; }

  const Camera& camera() const { return current_; }
  bool isModified() const;

 private:
  Camera base_;
  Camera current_;
};

}  // namespace penumbra::viewer
