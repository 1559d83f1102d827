#pragma once
// The viewer's fly camera: WASD (Q/E down/up) moves it along its view, a mouse drag turns it, the wheel sets its speed.
// It keeps the camera it starts from exactly until the first input, so that an untouched viewer sees what
// `ssvgi render` sees.
#include "scene.h"

#include <glm/glm.hpp>

namespace ssvgi::cli {

class FlyCamera {
 public:
  struct Input {
    glm::vec3 move{0.0f};     // x right, y up, z forward; each -1, 0 or 1
    glm::vec2 turn{0.0f};     // pixels dragged: x right, y down
    float speedSteps = 0.0f;  // wheel steps: each scales the speed by 1.25
  };

  explicit FlyCamera(const renderer::Camera& camera);

  void place(const renderer::Camera& camera);  // e.g. one of the scene's cameras, or where a camera path is
  void update(const Input& input, float seconds);
  const renderer::Camera& camera() const { return camera_; }
  float speed() const { return speed_; }  // metres per second

 private:
  renderer::Camera camera_;
  float speed_ = 2.0f;
};

}  // namespace ssvgi::cli
