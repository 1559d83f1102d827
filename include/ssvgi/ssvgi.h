#pragma once
// ssvgi: dynamic diffuse global illumination from screen-space voxels (see README.md and SPEC.md).
//
// Integration in four calls, in the spirit of the FidelityFX and RTXGI SDKs:
//   auto context = ssvgi::Context::create(desc);          // once, with the host's Vulkan device
//   context->dispatch(frame, commandBuffer);               // every frame, recorded into the host's command buffer
//   context->stats();                                      // memory, counters, per-pass GPU times
//   context.reset();                                       // destroy (after the GPU is done with it)
// ssvgi records commands; it never submits, waits, or owns a queue or the frame. No exception crosses this API.
#include <vulkan/vulkan.h>

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <variant>
#include <vector>

namespace ssvgi {

enum class Status {
  Ok,
  InvalidDescription,  // a field of a description is out of range; the message names it
  UnsupportedDevice,   // the device lacks something ssvgi needs; the message names it
  OutOfDeviceMemory,
  VulkanError,         // an unexpected Vulkan failure; the message names the call
};

// [[nodiscard]]: an Error or Result dropped unread is a failure nobody hears of.
struct [[nodiscard]] Error {
  Status status = Status::Ok;
  std::string message;
  VkResult vkResult = VK_SUCCESS;  // the failed Vulkan call's result (VulkanError, OutOfDeviceMemory); VK_SUCCESS when
                                   // no Vulkan call failed
  explicit operator bool() const { return status != Status::Ok; }
};

template <typename T>
class [[nodiscard]] Result {
 public:
  Result(T value) : value_(std::move(value)) {}
  Result(Error error) : value_(std::move(error)) {}
  bool ok() const { return std::holds_alternative<T>(value_); }
  T& value() { return std::get<T>(value_); }
  const Error& error() const { return std::get<Error>(value_); }

 private:
  std::variant<T, Error> value_;
};

enum class QualityTier { Low, Medium, High };

// Every knob of the GI, with its default (high tier). Tiers are presets over these (SPEC §4.7).
struct Settings {
  float voxelSize = 0.25f;                            // metres, at least 0.001; a brick is 4×4×4 voxels
  std::array<uint32_t, 3> volumeBricks{128, 48, 128};  // the voxel volume around the camera in bricks (X, Y, Z);
                                                      // each a multiple of 8 (where it stands: Stats::voxelVolume);
                                                      // at most 2,000,000 m across with voxelSize
  uint32_t brickPoolCapacity = 11776;                 // bricks that can hold voxels at once
  uint32_t invalidFramesToClear = 8;                  // frames a voxel may be seen through before it is cleared, ≤ 63
  uint32_t emptyFramesToRelease = 8;                  // frames a brick may stay empty before it returns to the pool
  uint32_t allocationPixelStride = 2;                 // BrickAllocate reads every Nth pixel in X and Y
  // The injection leaves out the bricks, and the blocks of 2×2×2 voxels, that lie wholly behind what a view drew over
  // them (its Hi-Z pyramid, SPEC §4.2), where injecting could change none of their voxels. Off, every brick in a view's
  // frustum is injected whole: the same voxels, but from the camera's lit frame a frame sooner where a brick hidden now
  // was seen in it, and an empty brick hidden from a view counts that view's injections towards its release
  // (emptyFramesToRelease); a check of the culling and a debugging aid, at the injection's full cost
  // (docs/PERFORMANCE.md, "What the occlusion culling saves").
  bool occlusionCulling = true;
  // The probe radiance cache (SPEC §4.5): three levels of probeGrid probes around the camera, level l spaced
  // probeSpacing · 2^l; one level updated per frame.
  std::array<uint32_t, 3> probeGrid{48, 24, 48};  // probes per level (X, Y, Z); each a multiple of 4, at most 4096
  float probeSpacing = 1.0f;                      // metres between the probes of level 0, at least 0.001; the
                                                  // coarsest level at most 2,000,000 m across
  uint32_t probeBudget = 4096;                    // probes traced per frame at most (the talk updates 2000–4000)
  // Blocks of 4×4×4 probes outside the frustum offered to the placement per update, in turn, after those in view,
  // which keep the budget first: voxels off screen are relit from their probes (SPEC §6.1), and a probe nobody
  // traces gives them no light after the first bounce. 0: only probes in view are traced, as in the talk.
  uint32_t probeBlocksBeyondView = 32;
  uint32_t raysPerProbe = 32;                     // rays per probe update: a power of two, 1..32; a probe has seen
                                                  // all 1024 directions of its fixed set after 1024 / raysPerProbe
  uint32_t probeHistoryCap = 32;                  // cap of the history count m, 1..255: α = 1/(m+1) averages the
                                                  // first cap+1 updates, then keeps a window of about that many
  // Stability (SPEC §4.5; the talk's ReSTIR part): level 0's probes keep one reservoir per stratum of the sphere (8)
  // and trace their rays through them; unbiased where the light holds still. Level 0 only, for memory: 8 × 4 bytes per probe
  // (1.77 MB at high tier), paid for by 8-bit distance and normal-dot SH (docs/ARCHITECTURE.md, "Probe memory").
  // Off: every probe traces the next raysPerProbe of the 1024 fixed directions, as levels 1 and 2 always do.
  // With them the dark room's probes vary less from update to update and keep their mean. Off by default: their
  // temporal reuse adds lag after a light is switched on, and cornell's probes lie further from the reference
  // (docs/QUALITY.md, "Probe stability", has the figures).
  bool probeReservoirs = false;                   // needs raysPerProbe ≥ 16 (per stratum ≥ 1 new candidate + its
                                                  // reservoir's ray)
  uint32_t probeReservoirHistoryCap = 48;         // cap of a reservoir's M (candidates it stands for), 1..252: with 3
                                                  // new candidates per update it remembers about 16 updates
  float probeSampleClamp = 0.0f;                  // with reservoirs: a new sample's luminance is clamped to this ×
                                                  // the brightest direction the probe's reservoirs hold (the talk's
                                                  // "history maximum"); 0: no clamp, else ≥ 1. Off by default: it
                                                  // does not lower the dark room's variation and darkens cornell's
                                                  // probes (a small emitter is often in no reservoir, so its rays
                                                  // stay clamped; docs/QUALITY.md, "Probe stability")
  // Less lag (SPEC §6.2): an update of a probe that differs from its history by more than this many standard
  // deviations of its usual difference shortens the probe's history in proportion (shared/probe_interface.h), so a
  // light switched on or off is followed in a few updates. 0: off (plain α = 1/(m+1)).
  float probeChangeThreshold = 2.0f;
  // A change many probes see at once is not their noise (shared/probe_interface.h, ProbeChangeTally): where at least
  // this share of the probes a frame traces with some history had it cut by a change (a light switched on or off),
  // every probe updated in the next three frames starts a recovery, so that the bounces after the first, whose steps
  // no single probe can tell from its noise, come round the loop quickly too. By chance a still scene's cuts reach
  // about one probe in a hundred. A drift they share alike: where the probes' updates lean toward more light by many
  // standard errors of their mean — light still coming round the loop, bounce after bounce, as in a hall lit through
  // its roof — the next three frames blend with a history cap of at most 16. 0: off (each probe on its own). Needs
  // probeChangeThreshold.
  float probeSharedChangeShare = 0.125f;
  // The ray budget goes to the probes that change (SPEC §6.2): a probe whose history has reached probeHistoryCap and
  // that follows no change (no recovery under way, no drift in its last updates) is traced on one in this many updates
  // of its level, its turn set by its place in the world; every probe is traced on the frames that start a shared
  // recovery. 1: every update. It lightens the frames of a still view once its probes have settled (what it saves:
  // docs/PERFORMANCE.md, "Settled probes sit out").
  uint32_t settledProbeInterval = 2;
  // Unknown is not sky (SPEC §6.4): ssvgi keeps which brick cells of its volume the camera and the extra views have
  // seen through or into. A probe ray that meets no voxel after crossing one no view has observed has found neither
  // a surface nor the sky: it stands for the mean of what the update's other rays found — the surfaces' light less
  // its direct part (no light's view saw a surface lit there), and the sky as often as the rays of its half of the
  // sphere, above or below the horizon, found it — (for what the probe already holds, where none found anything), and
  // the probe's confidence falls. Off: every ray that meets no voxel sees the sky, also through a roof that was never
  // on screen.
  // Turn it on with views beyond the camera that observe the space around it (FrameDesc::extraViews: a view from the
  // sun or from above, a capture around the camera): with the camera alone, open space behind it is unknown
  // (docs/QUALITY.md, "Unknown is not sky").
  bool skyOnlyThroughObservedSpace = false;
  // Voxels follow the light (SPEC §6.1): the voxels whose view gave them direct light and albedo
  // (FrameDesc::litAlbedo, ExtraView::albedo) have their radiance recomputed as direct + albedo/π · E of the probes,
  // a 1/voxelRelightPeriod share of the bricks a frame (1..64), each on the frames its place in the world gives it,
  // wherever they are: the bounces after the first follow the probes also off screen, and go round the voxel → probe
  // → voxel loop once per probe update. Until it is relit, a voxel such a view wrote for the first time carries only
  // that view's direct light. 3 by default: each probe level is updated every third frame, and relighting every frame
  // gave the same lag for three times the work (docs/QUALITY.md, "Air the views saw only askew").
  uint32_t voxelRelightPeriod = 3;
};

Settings settingsForTier(QualityTier tier);

// A field of Settings by name, with the values Context::create accepts for it: a value lies in [minimum, maximum]
// (above minimum where minimumExcluded; each axis of an array alike), is a multiple of multipleOf, and a power of two
// where powerOfTwo — or is 0 where zeroTurnsOff; a float is also finite. Settings that depend on one another
// (probeReservoirs needs raysPerProbe ≥ 16) are checked beside this.
struct SettingInfo {
  const char* name;
  std::variant<float Settings::*, uint32_t Settings::*, bool Settings::*, std::array<uint32_t, 3> Settings::*> member;
  double minimum = 0.0;
  double maximum = std::numeric_limits<double>::infinity();
  bool minimumExcluded = false;
  uint32_t multipleOf = 1;
  bool powerOfTwo = false;
  bool zeroTurnsOff = false;
};

// Every field of Settings: the one list that Context::create validates by and that a host's tools can show, parse and
// save settings by (a settings panel, a command line, a saved file).
std::span<const SettingInfo> settingInfos();

struct ContextDesc {
  VkInstance instance = VK_NULL_HANDLE;  // the host's, Vulkan 1.1 or later
  VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;  // must store R8_UNORM images from shaders (Context::confidence());
                                                     // create() returns UnsupportedDevice if it cannot
  VkDevice device = VK_NULL_HANDLE;
  // For a host that loads Vulkan itself (volk, its own dlopen): every Vulkan function ssvgi calls for the context is
  // looked up through these, the device's through vkGetDeviceProcAddr (itself found through vkGetInstanceProcAddr when
  // null here). Null: the Vulkan loader's, which ssvgi links (docs/INTEGRATION.md, "Loading Vulkan").
  PFN_vkGetInstanceProcAddr vkGetInstanceProcAddr = nullptr;
  PFN_vkGetDeviceProcAddr vkGetDeviceProcAddr = nullptr;
  bool debugUtilsEnabled = false;  // the host enabled VK_EXT_debug_utils: ssvgi names its objects and labels its
                                   // passes "ssvgi: <PassName>" for RenderDoc / Nsight
  Settings settings;
  uint32_t maxWidth = 1920;   // the largest frame dispatch() will be given, pixels (sizes the Hi-Z pyramid)
  uint32_t maxHeight = 1080;
  uint32_t maxExtraViewSize = 1024;  // the largest side of an extra view (FrameDesc::extraViews), pixels, ≤ 16384;
                                     // the Hi-Z pyramid is sized for the larger of this square and the frame
  uint32_t framesInFlight = 2;  // dispatches the host may have in flight; ssvgi recycles its descriptors after these
  // A hard limit on every byte of GPU memory the context allocates (all that Stats::memory lists; SPEC §6.5), or 0: no
  // limit, `settings` as given. With a limit, create() shrinks `settings` until everything fits, least harmful first:
  // brickPoolCapacity (down to a quarter of the volume's X × Z footprint in bricks), then probeGrid (probes per
  // level, the spacing kept, down to the fewest with which the coarsest level covers the voxel volume), then
  // volumeBricks (its proportions kept, the probe grid at the floor of the smaller volume); what a step of those two
  // leaves of the budget goes back to the pool. The gather's images and the Hi-Z pyramid, sized by
  // maxWidth/maxHeight/maxExtraViewSize, never shrink. A budget even the smallest settings exceed is
  // InvalidDescription, naming the minimum. Context::settings() and Stats::settings tell what was chosen
  // (docs/INTEGRATION.md, "A memory budget").
  uint64_t memoryBudgetBytes = 0;
};

// A column-major 4×4 matrix (glm's and GLSL's layout).
using Matrix4 = std::array<float, 16>;

// An axis-aligned box in world space, metres.
struct WorldBox {
  std::array<float, 3> min{};
  std::array<float, 3> max{};
};

// How a frame was seen: reversed-Z view-projection (SPEC §2) and its size in pixels. dispatch() refuses a matrix that
// is not finite or not invertible, and a position beyond ±1e6 m.
struct View {
  Matrix4 viewProjection{};
  std::array<float, 3> position{};  // camera position, metres: where the host's camera centres the GI volumes; for
                                    // an extra view, not used (its geometry comes from viewProjection)
  uint32_t width = 0;
  uint32_t height = 0;
};

// An image of the host's, read by ssvgi through a sampler. It must be in VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL and
// its writes made visible to compute shaders before the commands of dispatch() run.
struct SampledImage {
  VkImageView view = VK_NULL_HANDLE;
};

// A view beyond the camera (SPEC §6.3) — the sun's or a light's reflective shadow map, a cubemap face around the
// camera, a second camera — rendered by the host this frame. Its surfaces are injected into the voxels before the lit
// frame, so that voxels the camera has never seen hold their light too; where both see a surface, the lit frame's
// light is the one that stays. What lies nearer than its near plane (or beyond an orthographic view's far plane) is
// left as it was. Texels no larger than a voxel fill every voxel of the surfaces it sees; a host that jitters a view's
// projection by a fraction of a texel from frame to frame (as the renderer does) fills them with larger texels too.
struct ExtraView {
  View camera;            // any reversed-Z view-projection (SPEC §2): perspective, with a finite or infinite far
                          // plane, or orthographic; at most ContextDesc::maxExtraViewSize pixels on each side
  SampledImage depth;     // D32 reversed-Z
  // The radiance leaving its surfaces, linear HDR, and their unit world normal in rgb. Without a colour the view
  // only observes space (Settings::skyOnlyThroughObservedSpace; otherwise it is not used): the space in front of the
  // surfaces it shows counts as seen through, and it writes no voxels. A coarse view from above over the whole voxel
  // volume, for instance, lets the probes' rays that leave through an opening in a roof find the sky beyond what the
  // views that write voxels cover.
  SampledImage color;
  SampledImage normal;
  // Optional. Given, `color` holds direct and emitted light only (what a light's reflective shadow map knows) and
  // ssvgi adds albedo/π · E from its probes, so that these voxels also carry the bounces after the first. Without it,
  // `color` must hold all of the view's light, as the lit frame does.
  SampledImage albedo;
  // Optional, with `albedo`. The view is a reflective shadow map: its eye is the light whose direct light `color`
  // holds, and no other light reaches, and nothing emits, where the view cannot see. A surface hidden behind what it
  // shows is then in that light's shadow, with no direct light, and ssvgi counts it so: a voxel half in the light's
  // shadow keeps half the light, and one the light no longer reaches loses it when the view next sees it hidden. Left
  // false, what a view cannot see is unknown to it, and such a voxel keeps the light of its part the view sees.
  bool isReflectiveShadowMap = false;
};
constexpr uint32_t kMaxExtraViews = 8;  // per frame; a host with more cycles through them over frames

struct FrameDesc {
  uint32_t frameIndex = 0;
  View camera;                // the frame being rendered
  SampledImage depth;         // its depth, D32 reversed-Z (1 near, 0 infinitely far)
  SampledImage normal;        // its unit world normal in rgb (any float format); the gather shades with it and the
                              // filters compare it (SPEC §4.6)
  // The latest lit frame (SPEC §3): the previous frame's HDR scene colour (direct + emissive + the GI it composited)
  // with the depth and camera it was rendered with. Injecting it closes the multi-bounce loop.
  bool hasLitFrame = false;   // false on the first frame
  View litCamera;
  SampledImage litColor;      // linear HDR radiance
  SampledImage litDepth;      // D32 reversed-Z
  SampledImage litNormal;     // world normal in rgb
  // Optional, as ExtraView::albedo: given, `litColor` holds the lit frame's direct and emitted light only (no GI) and
  // this its albedo; ssvgi adds albedo/π · E of its probes, and keeps both in the voxels to relight them as the probes'
  // light changes (Settings::voxelRelightPeriod). Without it, `litColor` holds all of the frame's light.
  SampledImage litAlbedo;
  // The sky's radiance as SH2 (SPEC §2), W/(sr·m²): coefficients 0–3 red, 4–7 green, 8–11 blue, each in the order
  // Y00, Y1,-1, Y1,0, Y1,1. Probe rays that leave the voxel volume see it (clamped at 0), and the gather reads the
  // sky a probe sees with it, apart from the light of its surfaces. All zero: a black sky.
  std::array<float, 12> skyRadianceSh{};
  // Optional. The sky's radiance in finer detail, linear HDR, W/(sr·m²): an equirectangular image (a float format the
  // device filters linearly, R16G16B16A16_SFLOAT say; a few degrees a texel is enough), u the azimuth from +Z towards
  // +X (1/2 along +Z), v from the zenith (0) to the nadir (1); shaders/shared/sky_map.h maps directions to it. Probe
  // rays that leave the voxel volume see it instead of skyRadianceSh, which SH2 smooths: a clear sky's glow around the
  // sun, spread over half the sky, lit the surfaces it hides from too. The gather still reads the sky that probes see
  // through their openings with skyRadianceSh, which should be this map's projection.
  SampledImage skyRadianceMap;
  std::vector<ExtraView> extraViews;  // at most kMaxExtraViews; their images as the lit frame's (SampledImage)
  // The passes count their work this frame (Stats::work): what each did, which the device's speed does not change,
  // beside the GPU times, which it does. It costs an atomic add per thread of each counted pass and counter: leave it
  // off except to measure (`ssvgi bench` counts one frame after its timed ones). Off, the passes skip it on a uniform.
  bool countWork = false;
};

struct ResourceMemory {
  std::string name;
  uint64_t bytes = 0;
};

struct PassTime {
  std::string name;  // "ssvgi: <PassName>", as labelled in RenderDoc / Nsight
  double milliseconds = 0.0;
};

// Voxel rays a pass traced (SPEC §4.4) and what they cost on any device: the buffer words they read — brick lookups,
// occupancy masks and grid words, the voxel they met. 32-bit counts of one frame.
struct VoxelRays {
  uint32_t rays = 0;
  uint32_t reads = 0;
};

// What the passes of a frame did (FrameDesc::countWork): counted on the GPU where it depends on the data, from the
// dispatch sizes where it does not. Pass names as in Stats::passes, without "ssvgi: ".
struct WorkCounts {
  bool counted = false;  // the frame counted its work; every count below is 0 otherwise
  // HiZBuild, for the camera: the texels of every level of its pyramid.
  struct { uint32_t texels = 0; } hizBuild;
  // ObservedSpace (with Settings::skyOnlyThroughObservedSpace), summed over the views: pixels whose ray enters the
  // voxel volume, and the brick cells those rays mark observed.
  struct { uint32_t rays = 0; uint32_t cells = 0; } observedSpace;
  // SceneVoxelization of the camera's lit frame, and of the extra views (timed as "ssvgi: ExtraViews"): a voxel for
  // every voxel of each brick in view, and of those the voxels whose random point lay in the view (they read its
  // texels).
  struct Injection {
    uint32_t voxels = 0;
    uint32_t voxelsInView = 0;
  };
  Injection sceneVoxelization;
  Injection extraViewVoxelization;
  // VoxelRelight: the voxels whose light it gathered from the probes, and its visibility rays from them.
  struct { uint32_t voxels = 0; VoxelRays visibility; } voxelRelight;
  // ProbePlacement: the probes whose range it searched for voxels, and the occupancy grid words it read.
  struct { uint32_t probes = 0; uint32_t reads = 0; } probePlacement;
  // ProbeTrace: the probes traced and their rays (Settings::raysPerProbe each); and, for the probes that start
  // afresh, the visibility rays to the coarser level's probes they start from.
  struct { uint32_t probes = 0; VoxelRays rays; VoxelRays seedVisibility; } probeTrace;
  // ProbeRelocate: the rays traced back to the surface a probe inside geometry moves past.
  VoxelRays probeRelocate;
  // FinalGather: the tiles of 4×4 pixels it gathered (half of them a frame, a checkerboard) whose sample shows a
  // surface (those showing nothing gather nothing), and its visibility rays.
  struct { uint32_t tiles = 0; VoxelRays visibility; } finalGather;
  // TemporalUpsample: the pixels of the half-resolution output.
  struct { uint32_t pixels = 0; } temporalUpsample;
};

struct Stats {
  std::vector<ResourceMemory> memory;  // every GPU allocation of the context
  uint64_t totalBytes = 0;
  uint64_t memoryBudgetBytes = 0;      // ContextDesc::memoryBudgetBytes (0: none); totalBytes never exceeds it
  Settings settings;                   // what the context runs with: ContextDesc::settings within the budget
  uint32_t brickPoolCapacity = 0;
  uint32_t bricksLive = 0;             // allocated and holding voxels
  uint32_t bricksFree = 0;             // on the free list
  uint32_t bricksNeverUsed = 0;        // capacity − bump count
  uint32_t bricksDroppedLastFrame = 0;  // allocations refused because the pool was full
  uint32_t bricksDroppedTotal = 0;
  uint32_t bricksAllocatedLastFrame = 0;
  uint32_t bricksReleasedLastFrame = 0;
  uint32_t bricksVisibleLastFrame = 0;  // bricks updated by injection, summed over the camera and the extra views
  uint32_t voxelsValid = 0;            // counted before the last frame's lit-frame injection (after its extra views')
  uint32_t probeLevelUpdatedLastFrame = 0;  // the clipmap level the last frame updated (frame index % 3)
  uint32_t probesUpdatedLastFrame = 0;      // probes it traced: in view, near voxels, within the budget
  // Less lag (Settings::probeSharedChangeShare), as the last frame's preparation saw it: the probes that frame
  // framesInFlight before it traced with a history to tell a change by, those whose history a change cut, and whether
  // it started a recovery in every probe it updated.
  uint32_t probesWatchedForChange = 0;
  uint32_t probesCutByChange = 0;
  bool sharedChangeRecovery = false;
  // A drift many probes share (Settings::probeSharedChangeShare), pooled over the frames read back since the last drift
  // followed (up to nine): how far those watched probes' updates T leaned from their histories H, the mean of
  // (T − H) / 2H, and its standard error; the gap this tells, the share by which their histories fall short of where
  // light coming round the loop leads them (2 · lean / the share of their light that is direct or sky; infinite where
  // none is); and whether the last frame's update held the probes' history short because of it.
  float probesLeaning = 0.0f;
  float probesLeaningError = 0.0f;
  float probesLoopGap = 0.0f;
  bool sharedDrift = false;
  // Where the last dispatch() placed the voxel volume (SPEC §4.1), the space the GI knows of: centred across on the
  // 4-brick step under FrameDesc::camera's position, and as high as holds the most of the surfaces the camera saw (a
  // camera high above the ground, looking down, has it stand lower, even wholly below the camera); all zero before
  // the first dispatch(). Surfaces outside it get no voxels, nor probes that stand among them; Context::confidence()
  // tells a host where that leaves the GI knowing little.
  WorldBox voxelVolume;
  std::vector<PassTime> passes;        // the last completed frame's GPU times
  WorkCounts work;                     // what its passes did, where it counted (FrameDesc::countWork)
};

// Debug images of what ssvgi knows, ray-traced through its voxel volume from a camera.
enum class DebugView {
  Voxels,  // the voxels' stored radiance (black where a ray leaves the volume)
  Bricks,  // brick occupancy: each live brick in a colour of its own
  Probes,  // the finest probe level as small spheres in front of the voxels: white balls lit by each probe's SH
           // irradiance; magenta: invalid (inside geometry); yellow: just moved by its virtual offset, not yet traced
  Confidence,  // the confidence (Context::confidence()) the gather gives each surface a ray meets in the voxels, in
               // grey from black (0) to white (1); dark blue where the ray meets no voxel
  ObservedSpace,  // the voxels' stored radiance, watching observed space as the probes' rays do (SPEC §6.4;
                  // Settings::skyOnlyThroughObservedSpace): magenta where a ray crossed space no view has observed and
                  // met nothing (for a probe: neither a surface nor the sky), half magenta on a voxel beyond it;
                  // with the setting off no space is marked observed, and every such ray is magenta
};

// An image of ssvgi's results (SPEC §3), owned by the context, at half resolution: texel h stands for full-resolution
// pixel 2h (its depth and normal), ready to sample at full resolution as E is.
//   - After the commands of dispatch() it is in `layout` with its writes visible to compute shaders. A host that
//     samples it in another stage adds its own barrier; the host never writes it, and its reads must be complete or
//     ordered before the next dispatch() (which writes it, or the other of two images that alternate).
//   - Query it after each dispatch(): the image may change from frame to frame. The frame's result covers the top-left
//     width × height texels of an image of ceil(maxWidth/2) × ceil(maxHeight/2).
struct OutputImage {
  VkImage image = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;
  VkImageLayout layout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
  VkFormat format = VK_FORMAT_R16G16B16A16_SFLOAT;
  uint32_t width = 0;   // ceil(camera.width / 2) of the last dispatch
  uint32_t height = 0;  // ceil(camera.height / 2)
};

class Context {
 public:
  static Result<std::unique_ptr<Context>> create(const ContextDesc& desc);
  virtual ~Context() = default;

  // The settings the context runs with: ContextDesc::settings, shrunk to fit ContextDesc::memoryBudgetBytes if set.
  virtual const Settings& settings() const = 0;

  // Records the GI of one frame into `commandBuffer` (SPEC §4 order).
  virtual Error dispatch(const FrameDesc& frame, VkCommandBuffer commandBuffer) = 0;

  // ssvgi's result: the indirect irradiance E(n) of the last dispatch(), filtered (see OutputImage); nothing (null
  // handles) before the first. The host composites albedo/π · E. R16G16B16A16_SFLOAT: rgb E, W/m²; a: the depth of
  // the texel's pixel (0 where nothing was drawn; E is 0 there too).
  virtual OutputImage output() const = 0;

  // How much ssvgi knows where it lit each texel of output() (SPEC §6.4), for a host that blends to a fallback —
  // baked or ambient light — where ssvgi knows little: e.g. E_used = mix(E_fallback, E, confidence) beyond
  // voxelVolume(), where ssvgi has nothing. Inside the volume a low confidence means space no view has observed,
  // which ssvgi does not take for sky: a sky fallback there lights a roof no view has seen (docs/INTEGRATION.md).
  // R8_UNORM, the same size, texels and contract as output() (see OutputImage); nothing before the first dispatch().
  //   - 1: every ray of the probes that lit the texel met a surface or the sky through space some view has observed
  //     (the camera's frames, FrameDesc::extraViews); 0: the probes know nothing of their surroundings — their rays
  //     met only space no view has observed, where unknown is not sky — or no probe lit the texel. Where nothing was
  //     drawn it is 0.
  //   - It is the known fraction of the probes the gather used for E, weighted as their light is, each probe's
  //     fraction blended over its updates as its light is, and upsampled with E's weights. It is not temporally
  //     filtered as E is: near a probe level's boundary it flickers a little from frame to frame.
  virtual OutputImage confidence() const = 0;

  // Where the last dispatch() placed the voxel volume, as Stats::voxelVolume, known as soon as dispatch() returns: a
  // host that blends to a fallback beyond ssvgi's reach can tell, while it records the frame, which surfaces lie
  // outside it (ssvgi has no voxels and no probes there). All zero before the first dispatch().
  virtual WorldBox voxelVolume() const = 0;

  // Records a debug view into `target`, an rgba32f storage image of the view's size that ssvgi leaves in
  // VK_IMAGE_LAYOUT_GENERAL (it must be in GENERAL or UNDEFINED before).
  virtual Error debugView(DebugView view, const View& camera, VkImage target, VkImageView targetView,
                          VkCommandBuffer commandBuffer) = 0;

  // Counters and GPU times of the last frame whose commands have completed: call after the host has waited for it.
  virtual Stats stats() = 0;
};

}  // namespace ssvgi
