#pragma once
// The views the renderer gives ssvgi beyond its camera (SPEC §6.3), so that surfaces the camera has never seen have
// voxels and light:
//   - the sun's view: an orthographic reflective shadow map along the sun over the voxel volume around the camera,
//     its texels a voxel wide and snapped to a fixed grid, so that it does not shimmer as the camera moves; it fills
//     the sunlit surfaces the camera has not seen (a sunlit wall behind the camera); without a sun above the horizon
//     it looks straight down, so that the open space above roofs and yards, which the probes' rays cross to reach the
//     sky, is observed (SPEC §6.4) all the same;
//   - the capture around the camera: six 90° views from the camera's position (a cube), which fill the ceilings,
//     floors and walls beside and behind it;
//   - the local lights' views: six 90° views around a point light, one along a spot light's cone;
//   - the overhead view: a coarse orthographic view straight down over the whole voxel volume, given to ssvgi as depth
//     only (ssvgi::ExtraView without colour). It writes no voxels; it observes the open space above roofs and yards
//     beyond what the sun's view covers, which the probes' rays cross on their way to the sky (SPEC §6.4): without
//     it, the sky through a skylight is unknown to every ray that leaves the sun's view before the volume.
// Each is rendered with the host's own passes — G-buffer, direct light and a composite without GI — so its colour is
// direct and emitted light only, and ssvgi adds its probes' light through the albedo (ssvgi::ExtraView::albedo).
// At most `viewsPerFrame` views are rendered a frame, in turn. Every view's projection is moved by a different
// fraction of a texel each time it is rendered, so that over a few renders its texel centres land in every voxel of
// what it sees, even where a texel is wider than a voxel (a capture face at a distance, a wall the sun grazes).
#include "gbuffer_pass.h"
#include "gpu_scene.h"
#include "screen_passes.h"
#include "shadow_pass.h"

#include "ssvgi/ssvgi.h"

#include <vector>

namespace ssvgi::renderer {

struct ExtraViewSettings {
  // Pixels per side of the sun's view (0: none). Its texels are a voxel wide (ssvgi::Settings::voxelSize), or
  // narrower where the voxel volume's footprint seen from the sun is smaller than the view: it covers that footprint,
  // or the square of this many voxels around the camera where the footprint is larger (256: 64 m at the high tier's
  // 0.25 m voxels, of its 128 m volume; docs/PERFORMANCE.md has what larger views cost, docs/QUALITY.md ("Views
  // beyond the camera") what the views do to the scenario figures).
  uint32_t sunViewSize = 256;
  uint32_t surroundViewSize = 64;  // pixels per side of each face of the capture around the camera; 0: none
  uint32_t lightViewSize = 64;     // pixels per side of each view of a local light; 0: none
  // Pixels per side of the overhead view (0: none). Its texels are the voxel volume's footprint over this: about half
  // a brick at 256 and the high tier, so that its jittered rays cross every column of brick cells within a few
  // renders.
  uint32_t overheadViewSize = 256;
  // Views rendered and given to ssvgi per frame, 1..ssvgi::kMaxExtraViews; when there are more (the sun, six faces
  // around the camera, six per point light, one per spot), they take turns.
  uint32_t viewsPerFrame = 4;
  // Give the sun's view (and a local light's) as a reflective shadow map where that light alone lights the scene and
  // nothing emits (ssvgi::ExtraView::isReflectiveShadowMap): ssvgi then takes the light of what it shows in that
  // light's shadow away, so a place the sun turned from loses its light (SPEC §6.1). Off by default: with the sky map
  // as well, the dark room flickered more than issue 13 allows in some runs, when the GI still differed from run to
  // run; to be measured again on every scene before it is turned on (docs/QUALITY.md, "The same frames, the same
  // light").
  bool reflectiveShadowMaps = false;
  // Give ssvgi the sky as a map too (SkyMap, ssvgi::FrameDesc::skyRadianceMap), not only as SH2: the probes' rays that
  // leave the voxels see the sky's glow about the sun where it is, not spread over half the sky.
  bool skyMap = true;
};

class ExtraViews {
 public:
  // `gi`: the GI settings ssvgi runs with (its voxel size and volume); `sceneBounds`: what the sun's view must hold
  // between its near and far planes. Throws gpu::GpuError for settings out of range.
  ExtraViews(gpu::Device& device, const Scene& scene, const ExtraViewSettings& settings, const ssvgi::Settings& gi,
             const Bounds& sceneBounds);

  uint32_t viewCount() const { return uint32_t(sources_.size()); }  // views taking turns
  uint32_t maxViewSize() const;  // pixels per side of the largest (ssvgi::ContextDesc::maxExtraViewSize)

  // Renders this frame's views with the frame's lights and shadows (`frame`: the camera's constants, whose view
  // fields each view replaces; its camera position and sun are the ones the views follow) and returns them ready for
  // ssvgi (their images shader-readable). Labelled and timed as one pass, "renderer: ExtraViews".
  std::vector<ssvgi::ExtraView> record(gpu::HostCommandList& commands, const shader::FrameConstants& frame,
                                       const GpuScene& scene, const gpu::Buffer& lights, const ShadowPass& shadows,
                                       VkSampler pointSampler);

 private:
  enum class Kind { Sun, Overhead, Surround, Light };
  struct Source {
    Kind kind;
    uint32_t index;        // Surround: the cube face; Light: into lightCameras_
    uint32_t renders = 0;  // times rendered: picks its next sub-texel offset
  };
  // What one rendered view needs: its constants, G-buffer and radiance.
  struct Target {
    Target(Kind viewKind, gpu::Device& device, uint32_t viewSize);
    Kind kind;
    uint32_t size;
    gpu::Buffer frameConstants;
    GBuffer gbuffer;
    gpu::Image radiance;  // emission + albedo/π · E_direct; none for the overhead view, given as depth only
  };

  uint32_t sizeOf(Kind kind) const;
  // Whether a source's view is a reflective shadow map this frame (ssvgi::ExtraView::isReflectiveShadowMap): a
  // light's view where that light alone lights the scene and nothing emits.
  bool isReflectiveShadowMap(const Source& source, const shader::FrameConstants& frame) const;
  // The view and (unjittered) projection a source is seen through this frame.
  void viewOf(const Source& source, const shader::FrameConstants& frame, glm::mat4& view, glm::mat4& projection) const;
  // An orthographic view of `size` pixels looking along −toward over the voxel volume around `cameraPosition`, its
  // texels at most `maxTexel` wide, centred on whole texels, and holding the whole scene and volume in depth.
  void orthographicOverVolume(glm::vec3 toward, glm::vec3 cameraPosition, uint32_t size, float maxTexel,
                              glm::mat4& view, glm::mat4& projection) const;

  ExtraViewSettings settings_;
  bool sceneEmits_;  // a material emits light
  float voxelSize_;
  glm::vec3 volumeHalfExtent_;  // half the voxel volume's size, metres
  Bounds sceneBounds_;
  std::vector<Camera> lightCameras_;
  std::vector<Source> sources_;  // in the order they take turns
  uint32_t nextSource_ = 0;
  std::vector<Target> targets_;  // per kind, as many as can be rendered in one frame
  GBufferPass gbufferPass_;
  DirectLighting directLighting_;
  Composite composite_;
  gpu::Image directIrradiance_;  // scratch, shared by the views (the largest view's size)
  gpu::Image viewDistance_;
  gpu::Image noIndirect_;        // black: the composite adds no indirect light
  gpu::Buffer noFallback_;       // zero: the composite blends to no fallback (shader::CompositeFallback)
  gpu::Image indirectUsed_;
  gpu::Image finalRadiance_;     // with no indirect light, the direct radiance again: the views give that (radiance)
  bool cleared_ = false;
};

}  // namespace ssvgi::renderer
