#include "view_panel.h"

#include "rendering_options.h"
#include "scene_options.h"

#include <imgui.h>

#include <algorithm>
#include <cinttypes>
#include <variant>

namespace ssvgi::cli {

namespace {

constexpr uint32_t kPanelWidth = 300;

void pushLimited(std::deque<float>& values, float value) {
  values.push_back(value);
  if (values.size() > PassTimingHistory::kFrames) values.pop_front();
}

void plot(const char* id, const std::deque<float>& values, float height) {
  const std::vector<float> series(values.begin(), values.end());
  const float maximum = std::max(1e-3f, *std::max_element(series.begin(), series.end()));
  ImGui::PlotLines(id, series.data(), int(series.size()), 0, nullptr, 0.0f, maximum,
                   ImVec2(ImGui::GetContentRegionAvail().x, height));
}

// One field of ssvgi::Settings as an input; true once an edit is finished: a click on a checkbox, or a number field
// left after a change (Enter, Tab or a click elsewhere). Not Enter alone: ImGui 1.86 misses a key pressed and
// released within one frame, and a frame on lavapipe is long.
bool settingInput(const ssvgi::SettingInfo& field, ssvgi::Settings& settings) {
  return std::visit(
      [&](auto member) {
        auto& value = settings.*member;
        using Value = std::remove_reference_t<decltype(value)>;
        if constexpr (std::is_same_v<Value, bool>) {
          return ImGui::Checkbox(field.name, &value);
        } else {
          if constexpr (std::is_same_v<Value, float>)
            ImGui::InputFloat(field.name, &value, 0.0f, 0.0f, "%.4g");
          else if constexpr (std::is_same_v<Value, uint32_t>)
            ImGui::InputScalar(field.name, ImGuiDataType_U32, &value);
          else
            ImGui::InputScalarN(field.name, ImGuiDataType_U32, value.data(), 3);
          return ImGui::IsItemDeactivatedAfterEdit();
        }
      },
      field.member);
}

void cameraSection(ViewerControls& controls, const PanelReadout& readout, PanelActions& actions) {
  const renderer::Camera& camera = readout.camera.camera();
  ImGui::Text("at %.2f, %.2f, %.2f  %.1f m/s", camera.position.x, camera.position.y, camera.position.z,
              readout.camera.speed());
  ImGui::TextDisabled("WASD, Q/E move; a drag turns;");
  ImGui::TextDisabled("the wheel sets the speed; Esc quits");
  for (size_t i = 0; i < readout.scene.cameras.size(); ++i) {
    const std::string& name = readout.scene.cameras[i].name;
    const std::string label = (name.empty() ? "camera " + std::to_string(i) : name) + "##camera" + std::to_string(i);
    if (ImGui::Button(label.c_str())) actions.sceneCamera = i;
    ImGui::SameLine();
  }
  ImGui::NewLine();
  if (!readout.scene.cameraPath.empty()) ImGui::Checkbox("follow the camera path", &controls.followCameraPath);
  ImGui::Checkbox("pause (space)", &controls.paused);
}

void giSection(ViewerControls& controls, const PanelReadout& readout, PanelActions& actions) {
  ImGui::Checkbox("GI on", &controls.giLighting);
  for (const char* tier : {"low", "medium", "high"}) {
    ImGui::SameLine();
    if (ImGui::RadioButton(tier, controls.tier == tier) && controls.tier != tier) {
      controls.tier = tier;
      controls.gi = renderer::giSettingsFor(qualityTier(tier), readout.scene);
      actions.rendererChanged = true;
    }
  }
  if (ImGui::TreeNode("settings (applied when left)")) {
    ImGui::PushItemWidth(ImGui::GetFontSize() * 8.0f);  // room for the longest names beside their inputs
    for (const ssvgi::SettingInfo& field : ssvgi::settingInfos()) actions.rendererChanged |= settingInput(field, controls.gi);
    ImGui::PopItemWidth();
    ImGui::TreePop();
  }
}

void viewSection(ViewerControls& controls, const PanelReadout& readout) {
  int shown = int(controls.shownLight);
  ImGui::TextUnformatted("light");
  ImGui::BeginDisabled(!readout.litFrameDirect);
  ImGui::SameLine();
  ImGui::RadioButton("all", &shown, int(renderer::ShownLight::All));
  ImGui::SameLine();
  ImGui::RadioButton("direct", &shown, int(renderer::ShownLight::Direct));
  ImGui::SameLine();
  ImGui::RadioButton("indirect", &shown, int(renderer::ShownLight::Indirect));
  ImGui::EndDisabled();
  controls.shownLight = renderer::ShownLight(shown);
  if (ImGui::BeginCombo("debug view", controls.debugView.empty() ? "none" : controls.debugView.c_str())) {
    if (ImGui::Selectable("none", controls.debugView.empty())) controls.debugView.clear();
    for (const auto& [name, view] : debugViewsByName())
      if (ImGui::Selectable(name.c_str(), controls.debugView == name)) controls.debugView = name;
    ImGui::EndCombo();
  }
  ImGui::SliderFloat("exposure", &controls.exposure, 0.01f, 16.0f, "%.2f", ImGuiSliderFlags_Logarithmic);
}

void lightSection(ViewerControls& controls, const PanelReadout& readout, PanelActions& actions) {
  actions.lightsChanged |= ImGui::Checkbox("sun", &controls.sunEnabled);
  actions.lightsChanged |= ImGui::SliderFloat("azimuth", &controls.sunAzimuthDegrees, -180.0f, 180.0f, "%.0f deg");
  actions.lightsChanged |= ImGui::SliderFloat("elevation", &controls.sunElevationDegrees, -10.0f, 90.0f, "%.0f deg");
  actions.lightsChanged |= ImGui::SliderFloat("sun W/m2", &controls.sunIlluminance, 0.0f, 50.0f, "%.1f",
                                              ImGuiSliderFlags_Logarithmic);
  if (!readout.scene.lights.empty())
    actions.lightsChanged |= ImGui::Checkbox(
        ("local lights (" + std::to_string(readout.scene.lights.size()) + ")").c_str(), &controls.localLights);
  actions.sceneChanged |= ImGui::Checkbox("moving object", &controls.movingObject);
  if (controls.movingObject && !readout.scene.movingObject) ImGui::TextDisabled("(this scene has none)");
}

void timingSection(const PanelReadout& readout) {
  const auto& frames = readout.timings.frameMilliseconds();
  if (frames.empty()) return;
  ImGui::Text("frame %.2f ms (GPU, last %zu frames)", frames.back(), frames.size());
  plot("##frame", frames, 32.0f);
  if (ImGui::BeginTable("passes", 3)) {
    ImGui::TableSetupColumn("pass", ImGuiTableColumnFlags_WidthStretch);
    ImGui::TableSetupColumn("ms", ImGuiTableColumnFlags_WidthFixed, 44.0f);
    ImGui::TableSetupColumn("last frames", ImGuiTableColumnFlags_WidthFixed, 64.0f);
    for (const PassTimingHistory::Pass& pass : readout.timings.passes()) {
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(pass.name.c_str());
      ImGui::TableNextColumn();
      ImGui::Text("%.3f", pass.milliseconds.back());
      ImGui::TableNextColumn();
      plot(("##" + pass.name).c_str(), pass.milliseconds, 14.0f);
    }
    ImGui::EndTable();
  }
}

void memorySection(const ssvgi::Stats& stats) {
  ImGui::Text("ssvgi total %.2f MiB", double(stats.totalBytes) / (1024.0 * 1024.0));
  if (ImGui::BeginTable("memory", 2, ImGuiTableFlags_SizingStretchProp)) {
    for (const ssvgi::ResourceMemory& resource : stats.memory) {
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(resource.name.c_str());
      ImGui::TableNextColumn();
      ImGui::Text("%.1f KiB", double(resource.bytes) / 1024.0);
    }
    ImGui::EndTable();
  }
}

void countersSection(const ssvgi::Stats& stats) {
  const std::pair<const char*, uint32_t> counters[] = {
      {"brick pool capacity", stats.brickPoolCapacity},
      {"bricks live", stats.bricksLive},
      {"bricks free", stats.bricksFree},
      {"bricks never used", stats.bricksNeverUsed},
      {"bricks allocated last frame", stats.bricksAllocatedLastFrame},
      {"bricks released last frame", stats.bricksReleasedLastFrame},
      {"bricks injected last frame", stats.bricksVisibleLastFrame},
      {"bricks dropped last frame", stats.bricksDroppedLastFrame},
      {"bricks dropped in all", stats.bricksDroppedTotal},
      {"voxels valid", stats.voxelsValid},
      {"probe level updated", stats.probeLevelUpdatedLastFrame},
      {"probes updated", stats.probesUpdatedLastFrame},
      {"probes watched for change", stats.probesWatchedForChange},
      {"probes cut by a change", stats.probesCutByChange},
      {"shared change recovery", uint32_t(stats.sharedChangeRecovery)},
      {"shared drift", uint32_t(stats.sharedDrift)},
  };
  for (const auto& [name, value] : counters) ImGui::Text("%-28s %" PRIu32, name, value);
}

}  // namespace

void PassTimingHistory::add(const std::vector<gpu::PassTiming>& frame) {
  float total = 0.0f;
  for (Pass& pass : passes_) pushLimited(pass.milliseconds, 0.0f);
  for (const gpu::PassTiming& timing : frame) {
    auto pass = std::find_if(passes_.begin(), passes_.end(), [&](const Pass& p) { return p.name == timing.name; });
    if (pass == passes_.end()) {
      // Zero in the frames before it first ran, and a place for this frame's time.
      passes_.push_back({timing.name, std::deque<float>(std::min(frames_.size() + 1, kFrames), 0.0f)});
      pass = passes_.end() - 1;
    }
    pass->milliseconds.back() = float(timing.milliseconds);
    total += float(timing.milliseconds);
  }
  pushLimited(frames_, total);
}

PanelRect viewerPanelRect(VkExtent2D size) {
  return {0, 0, std::min(kPanelWidth, size.width / 2), size.height};
}

PanelActions drawViewerPanel(ViewerControls& controls, const PanelReadout& readout, VkExtent2D windowSize) {
  PanelActions actions;
  const PanelRect rect = viewerPanelRect(windowSize);
  ImGui::SetNextWindowPos(ImVec2(float(rect.x), float(rect.y)));
  ImGui::SetNextWindowSize(ImVec2(float(rect.width), float(rect.height)));
  ImGui::Begin("ssvgi", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
  ImGui::TextWrapped("%s on %s", readout.scene.name.c_str(), readout.device.c_str());
  if (!readout.error.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.4f, 0.3f, 1.0f));
    ImGui::TextWrapped("%s", readout.error.c_str());
    ImGui::PopStyleColor();
  }
  if (ImGui::Button("screenshot (F12)")) actions.screenshot = true;
  if (!readout.screenshot.empty()) {
    ImGui::SameLine();
    ImGui::TextDisabled("%s", readout.screenshot.c_str());
  }
  if (ImGui::CollapsingHeader("camera", ImGuiTreeNodeFlags_DefaultOpen)) cameraSection(controls, readout, actions);
  if (ImGui::CollapsingHeader("GI", ImGuiTreeNodeFlags_DefaultOpen)) giSection(controls, readout, actions);
  if (ImGui::CollapsingHeader("view", ImGuiTreeNodeFlags_DefaultOpen)) viewSection(controls, readout);
  if (ImGui::CollapsingHeader("lights", ImGuiTreeNodeFlags_DefaultOpen)) lightSection(controls, readout, actions);
  if (ImGui::CollapsingHeader("GPU time per pass", ImGuiTreeNodeFlags_DefaultOpen)) timingSection(readout);
  if (readout.giStats) {
    if (ImGui::CollapsingHeader("ssvgi memory")) memorySection(*readout.giStats);
    if (ImGui::CollapsingHeader("ssvgi counters")) countersSection(*readout.giStats);
  }
  ImGui::End();
  return actions;
}

}  // namespace ssvgi::cli
