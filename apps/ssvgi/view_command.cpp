// ssvgi view: the renderer's image of a scene in a window, every frame, with a panel of controls and readouts over it
// (SPEC §6.6). The window shows exactly what `ssvgi render` computes for the same view (the renderer's tonemapped image,
// copied), then the panel; a scripted run (--frames) renders without input and saves the window's image.
#include "commands.h"
#include "fly_camera.h"
#include "rendering_options.h"
#include "scene_options.h"
#include "view_overlay.h"
#include "view_panel.h"
#include "view_swapchain.h"
#include "view_window.h"

#include "gpu_host/host_command_list.h"
#include "gpu_host/transfers.h"
#include "image_io.h"
#include "renderer.h"

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

namespace ssvgi::cli {

namespace {

struct ViewOptions {
  SceneOptions scene;
  RenderingOptions rendering;
  uint32_t frames = 0;     // a scripted run of this many frames; 0: until the window is closed
  std::string screenshot;  // where a screenshot goes (the key, the button, the end of a scripted run)
};

class Viewer {
 public:
  explicit Viewer(const ViewOptions& options);
  int run();

 private:
  bool scripted() const { return options_.frames > 0; }
  VkExtent2D size() const { return {resolved_.width, resolved_.height}; }
  void resize(VkExtent2D size);
  void buildRenderer();
  void reloadScene();
  void applyLights();
  void apply(const PanelActions& actions);
  FlyCamera::Input readInput();
  void drawFrame(float seconds);
  void saveScreenshot();

  ViewOptions options_;
  ResolvedScene resolved_;
  std::vector<glm::vec3> lightIntensities_;  // the local lights' as loaded: what "on" restores
  glm::vec3 sunColour_{1.0f};                // the sun's illuminance over its brightest channel
  bool lightsEdited_ = false;                // the panel has changed the lights: keep them over a scene reload
  ViewerWindow window_;
  gpu::OwnedDevice device_;
  Swapchain swapchain_;
  gpu::DescriptorArena descriptors_;
  ImGuiOverlay overlay_;
  gpu::Image windowImage_;  // what the window shows: the renderer's image, then the panel over it
  std::unique_ptr<renderer::Renderer> renderer_;
  ViewerControls controls_;
  ssvgi::Settings builtGi_;  // the settings of the renderer that runs: what a refused edit returns to
  std::string builtTier_;
  FlyCamera camera_;
  PassTimingHistory timings_;
  std::optional<ssvgi::Stats> giStats_;
  std::string error_;
  std::string lastScreenshot_;
  float animationSeconds_ = 0.0f;
  uint32_t frame_ = 0;
  bool screenshotRequested_ = false;
  bool dragging_ = false;
  bool swapchainStale_ = false;  // the surface changed under the last present: a new swapchain before the next frame
  glm::dvec2 lastCursor_{0.0};
};

gpu::DeviceDesc windowDeviceDesc(const SceneOptions& options) {
  gpu::DeviceDesc desc{options.device, options.validation};
  desc.instanceExtensions = ViewerWindow::requiredInstanceExtensions();
  desc.deviceExtensions = {VK_KHR_SWAPCHAIN_EXTENSION_NAME};
  return desc;
}

VkSurfaceKHR presentableSurface(const ViewerWindow& window, const gpu::OwnedDevice& device) {
  if (!window.canPresent(device.instance(), device.physicalDevice(), device.queueFamily()))
    throw WindowError("view: " + device.description() + " cannot present to the window; choose another --device");
  return window.createSurface(device.instance());
}

// The scene's sun in the panel's terms.
void readSun(const renderer::Scene& scene, ViewerControls& controls, glm::vec3& colour) {
  const glm::vec3 direction = glm::normalize(scene.sun.direction);
  controls.sunEnabled = scene.sun.enabled;
  controls.sunAzimuthDegrees = scene.sunCycle ? scene.sunCycle->azimuthDegrees
                                              : glm::degrees(std::atan2(direction.x, direction.z));
  controls.sunElevationDegrees = scene.sunCycle ? scene.sunCycle->elevationDegrees
                                                : glm::degrees(std::asin(std::clamp(direction.y, -1.0f, 1.0f)));
  const glm::vec3 illuminance = scene.sun.illuminance;
  controls.sunIlluminance = std::max({illuminance.r, illuminance.g, illuminance.b});
  colour = controls.sunIlluminance > 0.0f ? illuminance / controls.sunIlluminance : glm::vec3(1.0f);
}

std::vector<glm::vec3> lightIntensities(const renderer::Scene& scene) {
  std::vector<glm::vec3> intensities;
  for (const renderer::LocalLight& light : scene.lights) intensities.push_back(light.intensity);
  return intensities;
}

Viewer::Viewer(const ViewOptions& options)
    : options_(options),
      resolved_(resolveScene(options.scene)),
      lightIntensities_(lightIntensities(resolved_.scene)),
      window_("ssvgi view: " + resolved_.scene.name, resolved_.width, resolved_.height),
      device_(openDevice(windowDeviceDesc(options.scene))),
      swapchain_(device_, presentableSurface(window_, device_), {resolved_.width, resolved_.height}),
      descriptors_(device_),
      overlay_(device_, window_.handle()),
      camera_(resolved_.camera) {
  const renderer::RendererSettings settings = rendererSettings(options.rendering, resolved_, true);
  controls_.giLighting = settings.giLighting;
  controls_.tier = options.rendering.giOptions.tier;
  controls_.gi = *settings.gi;
  controls_.exposure = settings.exposure;
  controls_.movingObject = options.scene.movingObject;
  controls_.followCameraPath = !resolved_.scene.cameraPath.empty();
  readSun(resolved_.scene, controls_, sunColour_);
  resize(size());  // the window's framebuffer may differ: the frame loop follows it
}

void Viewer::resize(VkExtent2D size) {
  swapchain_.recreate(size);  // waits for the device: nothing uses the old images any more
  windowImage_ = gpu::Image(device_, {"viewer window", ImGuiOverlay::kTargetFormat, size.width, size.height, 1, 1,
                                      VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT});
  overlay_.setTarget(windowImage_);
  resolved_.width = size.width;
  resolved_.height = size.height;
  buildRenderer();
}

// A renderer for the controls' settings; one the renderer refuses leaves the last that worked, and says why.
void Viewer::buildRenderer() {
  renderer::RendererSettings settings = rendererSettings(options_.rendering, resolved_, true);
  settings.gi = controls_.gi;
  settings.giLighting = controls_.giLighting;
  settings.exposure = controls_.exposure;
  settings.shownLight = controls_.shownLight;
  renderer_.reset();  // its GPU memory first
  try {
    renderer_ = std::make_unique<renderer::Renderer>(device_, resolved_.scene, settings);
  } catch (const std::exception& error) {
    if (builtTier_.empty()) throw;  // the options' own settings: the command fails
    error_ = error.what();
    controls_.gi = builtGi_;
    settings.gi = builtGi_;
    controls_.tier = builtTier_;
    renderer_ = std::make_unique<renderer::Renderer>(device_, resolved_.scene, settings);
  }
  builtGi_ = controls_.gi;
  builtTier_ = controls_.tier;
}

void Viewer::reloadScene() {
  SceneOptions sceneOptions = options_.scene;
  sceneOptions.movingObject = controls_.movingObject;
  renderer_.reset();  // it reads the scene it was made with
  resolved_.scene = resolveScene(sceneOptions).scene;
  lightIntensities_ = lightIntensities(resolved_.scene);
  if (lightsEdited_) applyLights();
  buildRenderer();
}

void Viewer::applyLights() {
  renderer::Scene& scene = resolved_.scene;
  scene.sun.enabled = controls_.sunEnabled;
  pointSun(scene, controls_.sunAzimuthDegrees, controls_.sunElevationDegrees);
  scene.sun.illuminance = sunColour_ * controls_.sunIlluminance;
  for (size_t i = 0; i < scene.lights.size(); ++i)
    scene.lights[i].intensity = controls_.localLights ? lightIntensities_[i] : glm::vec3(0.0f);
  lightsEdited_ = true;
}

void Viewer::apply(const PanelActions& actions) {
  if (actions.lightsChanged) applyLights();
  if (actions.sceneCamera) {
    camera_.place(resolved_.scene.cameras[*actions.sceneCamera]);
    controls_.followCameraPath = false;
  }
  if (actions.sceneChanged) {
    reloadScene();
  } else if (actions.rendererChanged) {
    error_.clear();
    buildRenderer();
  }
  renderer_->setGiLighting(controls_.giLighting);
  renderer_->setExposure(controls_.exposure);
  renderer_->setShownLight(controls_.shownLight);
  screenshotRequested_ |= actions.screenshot;
}

FlyCamera::Input Viewer::readInput() {
  const ImGuiIO& io = ImGui::GetIO();
  FlyCamera::Input input;
  const auto axis = [&](int positive, int negative) {
    return float(window_.keyDown(positive)) - float(window_.keyDown(negative));
  };
  if (!io.WantCaptureKeyboard) {
    input.move = {axis(GLFW_KEY_D, GLFW_KEY_A), axis(GLFW_KEY_E, GLFW_KEY_Q), axis(GLFW_KEY_W, GLFW_KEY_S)};
    if (window_.keyPressed(GLFW_KEY_SPACE)) controls_.paused = !controls_.paused;
    if (window_.keyPressed(GLFW_KEY_ESCAPE)) window_.requestClose();
  }
  // A drag turns the camera only when it starts outside the panel.
  const glm::dvec2 cursor = window_.cursorPosition();
  const bool down = window_.mouseButtonDown(GLFW_MOUSE_BUTTON_LEFT);
  if (down && dragging_) input.turn = glm::vec2(cursor - lastCursor_);
  dragging_ = down && (dragging_ || !io.WantCaptureMouse);
  lastCursor_ = cursor;
  const double scroll = window_.takeScroll();
  if (!io.WantCaptureMouse) input.speedSteps = float(scroll);
  return input;
}

void Viewer::drawFrame(float seconds) {
  overlay_.newFrame();
  const PanelReadout readout{resolved_.scene, camera_,     timings_,
                             giStats_,        device_.properties().deviceName,
                             options_.rendering.giOptions.litFrame == "direct",
                             error_,          lastScreenshot_};
  apply(drawViewerPanel(controls_, readout, size()));
  if (window_.keyPressed(GLFW_KEY_F12)) screenshotRequested_ = true;
  if (!scripted()) camera_.update(readInput(), seconds);

  renderer::AnimatedState state = renderer::evaluateAnimation(resolved_.scene, camera_.camera(), animationSeconds_);
  if (controls_.followCameraPath)
    camera_.place(state.camera);
  else
    state.camera = camera_.camera();
  renderer_->render(state);
  if (!controls_.debugView.empty()) renderer_->drawGiDebugView(debugViewsByName().at(controls_.debugView));
  timings_.add(renderer_->passTimings());
  giStats_ = renderer_->giStats();
  if (!controls_.paused) animationSeconds_ += seconds;
  ++frame_;

  std::optional<uint32_t> image = swapchain_.acquire();
  if (!image) {
    swapchain_.recreate(size());
    image = swapchain_.acquire();
  }
  device_.submitAndWait([&](VkCommandBuffer commandBuffer) {
    gpu::HostCommandList commands(device_, commandBuffer, descriptors_);
    commands.blitImage(renderer_->tonemappedImage(), windowImage_);
    overlay_.record(commands);
    if (image)
      commands.blitToExternalImage(windowImage_, swapchain_.image(*image), swapchain_.size(),
                                   VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR);
  });
  if (image && !swapchain_.present(*image)) swapchainStale_ = true;
  if (screenshotRequested_) saveScreenshot();
}

void Viewer::saveScreenshot() {
  screenshotRequested_ = false;
  const std::string path =
      options_.screenshot.empty() ? "ssvgi-view-" + std::to_string(frame_) + ".png" : options_.screenshot;
  const auto bytes = gpu::readImage(device_, windowImage_);
  std::vector<uint8_t> rgba(bytes.size());
  for (size_t i = 0; i < rgba.size(); ++i)
    rgba[i] = i % 4 == 3 ? 255 : uint8_t(bytes[i]);  // the window is opaque, whatever alpha the panel blended
  renderer::writePng(path, resolved_.width, resolved_.height, rgba);
  lastScreenshot_ = path;
}

int Viewer::run() {
  using Clock = std::chrono::steady_clock;
  Clock::time_point last = Clock::now();
  while (!window_.closeRequested() && (!scripted() || frame_ < options_.frames)) {
    window_.pollEvents();
    const VkExtent2D framebuffer = window_.framebufferSize();
    if (framebuffer.width == 0 || framebuffer.height == 0) {  // minimised: nothing to draw until it comes back
      window_.waitEvents();
      last = Clock::now();
      continue;
    }
    if (framebuffer.width != resolved_.width || framebuffer.height != resolved_.height) {
      resize(framebuffer);
    } else if (swapchainStale_) {
      swapchain_.recreate(framebuffer);
    }
    swapchainStale_ = false;
    const Clock::time_point now = Clock::now();
    // A scripted run steps the animation as `ssvgi render` does; a person sees it in real time (at most 0.1 s a
    // frame, so that a slow frame does not jump the scene).
    const float seconds = scripted() ? kFrameSeconds : std::min(std::chrono::duration<float>(now - last).count(), 0.1f);
    last = now;
    if (scripted() && frame_ + 1 == options_.frames && !options_.screenshot.empty()) screenshotRequested_ = true;
    drawFrame(seconds);
  }
  if (reportValidationErrors(options_.scene, device_)) return 1;
  if (scripted()) {
    const PanelRect panel = viewerPanelRect(size());
    std::printf("rendered %u frames of %s at %ux%u on %s", frame_, resolved_.scene.name.c_str(), resolved_.width,
                resolved_.height, device_.description().c_str());
    if (!lastScreenshot_.empty())
      std::printf("; saved %s, the panel at %u,%u %ux%u", lastScreenshot_.c_str(), panel.x, panel.y, panel.width,
                  panel.height);
    std::printf("\n");
  }
  return 0;
}

}  // namespace

CommandRunner addViewCommand(CLI::App& app) {
  auto options = std::make_shared<ViewOptions>();
  CLI::App* command = app.add_subcommand(
      "view", "Show a scene in a window, rendered every frame, with a panel of the GI's controls, GPU times and memory");
  addSceneOptions(*command, options->scene);
  addRenderingOptions(*command, options->rendering);
  command->add_option("--frames", options->frames,
                      "A scripted run: render this many frames without input (the animation advancing 1/30 s per "
                      "frame, as render does), save --screenshot if given, and exit")
      ->check(CLI::Range(1u, 100000u));
  command->add_option("--screenshot", options->screenshot,
                      "PNG file for the window's image, panel included: saved at the end of a scripted run, and by F12 "
                      "or the panel's button (default: ssvgi-view-FRAME.png)");
  return [options] { return Viewer(*options).run(); };
}

}  // namespace ssvgi::cli
