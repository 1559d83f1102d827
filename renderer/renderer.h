#pragma once
#include "gbuffer_pass.h"
#include "gpu/profiler.h"
#include "gpu_scene.h"
#include "image_io.h"
#include "extra_views.h"
#include "screen_passes.h"
#include "sky_map.h"
#include "shadow_pass.h"

#include "ssvgi/ssvgi.h"

#include <array>
#include <memory>
#include <optional>
#include <vector>

namespace ssvgi::renderer {

// The per-frame constants of a view of the scene (camera matrices, sun, sky, local light count, exposure), with no
// previous frame and no shadow maps yet. Shared with the reference path tracer so that both see the same camera and
// lights through the same numbers.
shader::FrameConstants makeFrameConstants(const Scene& scene, const AnimatedState& state, uint32_t width,
                                          uint32_t height, float exposure);
// A local light as the shaders read it (intensityAndShadow.w, the shadow layer, is left for the shadow pass).
shader::GpuLight toGpuLight(const LocalLight& light);
// Reads back an rgba32f, r32f, D32 or rgba16f image's first `channels` channels.
FloatImage readFloatImage(gpu::OwnedDevice& device, const gpu::Image& image, uint32_t channels);

// The GI settings the renderer runs ssvgi with: the tier's, with the scene's detail scale (Scene::giDetailScale)
// applied to the voxel size and the probe spacing, and the probes' rays taking the sky only through space a view has
// observed (ssvgi::Settings::skyOnlyThroughObservedSpace), since the renderer's views beyond the camera
// (ExtraViewSettings) observe the space around it.
ssvgi::Settings giSettingsFor(ssvgi::QualityTier tier, const Scene& scene);

// The light the final image shows on surfaces (the sky stays): all of it, direct and emitted light only, or the GI's
// alone, albedo/π · E_indirect (the viewer's "direct only" and "indirect only").
enum class ShownLight : uint32_t {
  All = shader::kShowAllLight,
  Direct = shader::kShowDirectLight,
  Indirect = shader::kShowIndirectLight,
};

struct RendererSettings {
  uint32_t width = 1280;
  uint32_t height = 720;
  float exposure = 1.0f;  // multiplies radiance before the tonemap curve
  ShadowSettings shadows;
  std::optional<ssvgi::Settings> gi;  // run the GI library with these settings (SPEC §3 integration)
  uint64_t giMemoryBudgetBytes = 0;   // ssvgi::ContextDesc::memoryBudgetBytes: 0, none; else gi shrinks to fit it
  bool giLighting = true;  // composite its indirect light; false: it runs for its debug views only, no ambient at all
  // The lit frame ssvgi is given (SPEC §3): its direct and emitted light with its albedo (ssvgi keeps both in the
  // voxels and relights them from its probes, SPEC §6.1), or false: the final radiance, GI included, as a host that
  // has only its lit colour gives it.
  bool litFrameDirectOnly = true;
  // The views beyond the camera the renderer gives the GI (SPEC §6.3; ExtraViews): the sun's, a capture around the
  // camera, the local lights'.
  ExtraViewSettings extraViews;
  // Anything but All needs litFrameDirectOnly: a final radiance given to ssvgi as its lit frame must hold all the light.
  ShownLight shownLight = ShownLight::All;
  bool countGiWork = false;  // ssvgi's passes count their work (ssvgi::FrameDesc::countWork, Stats::work)
};

// The host renderer (headless): shadows, G-buffer, direct light, the GI library, composite and tonemap for one scene,
// one frame at a time. It records and submits its own command buffers; ssvgi records into the same ones. The G-buffer
// and the final radiance alternate between two sets, so that the previous frame's stay intact as ssvgi's lit frame.
class Renderer {
 public:
  // `scene` is read every frame and must outlive the renderer; between frames its local lights' intensities may change
  // (the viewer's light switches), not their number, kind or place (shadow layers and light views are laid out here).
  // Throws gpu::GpuError naming a setting that cannot be honoured.
  Renderer(gpu::OwnedDevice& device, const Scene& scene, const RendererSettings& settings);

  // The settings that may change between frames (the viewer's controls); the others need a new renderer.
  void setExposure(float exposure) { settings_.exposure = exposure; }
  void setGiLighting(bool giLighting) { settings_.giLighting = giLighting; }
  void setCountGiWork(bool count) { settings_.countGiWork = count; }
  void setShownLight(ShownLight shown);  // throws as the constructor does

  // Renders the scene as it is at `state` (camera, sun, moving object) and waits for the GPU.
  void render(const AnimatedState& state);

  // The GI library's counters, memory and pass times for the last frame (nothing when it does not run).
  std::optional<ssvgi::Stats> giStats();
  const ssvgi::Context* giContext() const { return gi_.get(); }
  // The views beyond the camera given to ssvgi in the last frame (SPEC §6.3; ExtraViews).
  const std::vector<ssvgi::ExtraView>& extraViews() const { return lastExtraViews_; }
  // One of ssvgi's debug images of the last frame's camera: the linear image and its tonemapped RGBA8.
  struct DebugImage {
    FloatImage radiance;
    std::vector<uint8_t> tonemapped;
  };
  // `camera`: where the debug view is seen from (default: the last frame's camera), at the frame's size.
  DebugImage giDebugView(ssvgi::DebugView view, const std::optional<Camera>& camera = std::nullopt);
  // The same left in tonemappedImage() only, nothing read back (a window shows it).
  void drawGiDebugView(ssvgi::DebugView view, const std::optional<Camera>& camera = std::nullopt);

  const std::vector<gpu::PassTiming>& passTimings() const { return timings_; }
  const Bounds& sceneBounds() const { return bounds_; }
  uint32_t unshadowedLightCount() const { return shadows_.unshadowedLightCount(); }

  // The last frame's results, read back to the CPU.
  FloatImage finalRadiance();       // linear HDR, rgb
  FloatImage directIrradiance();    // E_direct, rgb
  FloatImage indirectIrradiance();  // E_indirect each pixel was shaded with, rgb
  FloatImage skyMap();              // the sky's map given to the GI (SkyMap), rgb; throws gpu::GpuError without one
  // The GI's confidence in that E_indirect (ssvgi::Context::confidence(), sampled as the composite samples E), one
  // channel, 0–1; 0 where nothing was drawn and everywhere when the GI's light is not composited.
  FloatImage confidence();
  FloatImage albedo();              // rgb
  FloatImage normal();              // xyz, zero where there is no surface
  FloatImage viewDistance();        // metres from the camera, zero where there is no surface
  FloatImage depthBuffer();         // raw reversed-Z depth: near plane / distance along the view axis, 0 = nothing
  std::vector<uint8_t> tonemapped();  // RGBA8, sRGB
  // The same on the GPU (or the debug view drawn since), for a window to show: last used by the frame's submission,
  // which has finished.
  const gpu::Image& tonemappedImage() const { return tonemapped_; }

 private:
  const GBuffer& currentGBuffer() const { return gbuffers_[frameIndex_ & 1u]; }
  void recordGi(gpu::CommandList& commands, const shader::FrameConstants& frame, const shader::Sh2Rgb& skyRadiance);
  // The composite's fallback beyond ssvgi's voxel volume (shader::CompositeFallback); none without a volume.
  void writeCompositeFallback(const std::optional<ssvgi::WorldBox>& voxelVolume, const shader::Sh2Rgb& skyRadiance);

  gpu::OwnedDevice& device_;
  const Scene& scene_;
  RendererSettings settings_;
  Bounds bounds_;
  GpuScene gpuScene_;
  gpu::Sampler pointSampler_;
  gpu::DescriptorArena descriptors_;
  gpu::Profiler profiler_;
  ShadowPass shadows_;
  GBufferPass gbufferPass_;
  DirectLighting directLighting_;
  Composite composite_;
  Tonemap tonemap_;
  std::optional<SkyMap> skyMap_;  // with GI and ExtraViewSettings::skyMap
  std::array<GBuffer, 2> gbuffers_;
  gpu::Buffer frameConstants_;
  gpu::Buffer compositeFallback_;  // shader::CompositeFallback, written once ssvgi has placed its volume
  gpu::Buffer lights_;
  gpu::Image directIrradiance_;
  gpu::Image viewDistance_;
  gpu::Image indirectIrradiance_;  // half resolution, black: what the composite binds when the GI is off
  gpu::Image indirectUsed_;
  std::array<gpu::Image, 2> finalRadiance_;
  std::array<gpu::Image, 2> directRadiance_;  // emission + albedo/π · E_direct, beside finalRadiance_
  gpu::Image tonemapped_;
  std::unique_ptr<ssvgi::Context> gi_;
  std::optional<ExtraViews> extraViews_;  // with the GI
  std::vector<ssvgi::ExtraView> lastExtraViews_;
  ssvgi::View giView_;  // the camera of the frame rendered last: next frame's lit-frame camera
  gpu::Image debugRadiance_;
  std::vector<gpu::PassTiming> timings_;
  glm::mat4 previousViewProjection_{1.0f};
  uint32_t frameIndex_ = 0;
};

}  // namespace ssvgi::renderer
