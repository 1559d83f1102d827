#pragma once
// The viewer's panel (Dear ImGui), docked on the window's left: the controls, which the viewer applies, and what the
// renderer and ssvgi report — per-pass GPU times over the last frames, ssvgi's memory and counters.
#include "fly_camera.h"

#include "gpu/profiler.h"
#include "renderer.h"
#include "scene.h"
#include "ssvgi/ssvgi.h"

#include <deque>
#include <optional>
#include <string>
#include <vector>

namespace ssvgi::cli {

// What the panel's controls set.
struct ViewerControls {
  bool giLighting = true;          // composite ssvgi's light (it runs either way, for its debug views)
  std::string tier = "high";
  ssvgi::Settings gi;              // the tier's, scaled to the scene, then edited
  renderer::ShownLight shownLight = renderer::ShownLight::All;
  std::string debugView;           // empty, or a name of debugViewsByName(): shown instead of the image
  float exposure = 1.0f;
  bool sunEnabled = false;
  float sunAzimuthDegrees = 0.0f;  // from +Z towards +X
  float sunElevationDegrees = 45.0f;
  float sunIlluminance = 0.0f;     // W/m², of the brightest channel (the sun keeps its colour)
  bool localLights = true;
  bool movingObject = false;
  bool paused = false;             // the animation's time stands still; the GI goes on converging
  bool followCameraPath = false;   // with a camera path (--camera-path): the camera follows it, input is ignored
};

// What the controls changed in a frame, for the viewer to act on.
struct PanelActions {
  bool rendererChanged = false;  // tier, a GI setting: a new renderer (and ssvgi context)
  bool sceneChanged = false;     // the moving object: the scene made anew, then a new renderer
  bool lightsChanged = false;    // the sun or the local lights: applied to the scene
  std::optional<size_t> sceneCamera;  // move the fly camera to the scene's camera of this index
  bool screenshot = false;
};

// The last frames' GPU time of every pass, oldest first.
class PassTimingHistory {
 public:
  static constexpr size_t kFrames = 120;
  struct Pass {
    std::string name;
    std::deque<float> milliseconds;  // kFrames values at most; 0 in a frame the pass did not run
  };
  void add(const std::vector<gpu::PassTiming>& frame);
  const std::vector<Pass>& passes() const { return passes_; }
  const std::deque<float>& frameMilliseconds() const { return frames_; }

 private:
  std::vector<Pass> passes_;  // in the order the frames first ran them
  std::deque<float> frames_;
};

// What the panel shows besides its controls.
struct PanelReadout {
  const renderer::Scene& scene;
  const FlyCamera& camera;
  const PassTimingHistory& timings;
  const std::optional<ssvgi::Stats>& giStats;
  std::string device;
  bool litFrameDirect;     // showing part of the light needs it (renderer::RendererSettings::shownLight)
  std::string error;       // the last change the renderer refused, one line; empty when none
  std::string screenshot;  // the last screenshot saved, empty when none
};

// The panel's place in a window of `size`: the left side, full height, 300 px wide (at most half the window).
struct PanelRect {
  uint32_t x = 0, y = 0, width = 0, height = 0;
};
PanelRect viewerPanelRect(VkExtent2D size);

// Draws the panel (inside an ImGui frame) and returns what its controls changed in `controls`.
PanelActions drawViewerPanel(ViewerControls& controls, const PanelReadout& readout, VkExtent2D windowSize);

}  // namespace ssvgi::cli
