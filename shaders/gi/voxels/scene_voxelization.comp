#version 450
// SceneVoxelization: injects a view into the listed bricks, one thread per voxel, by gather (SPEC §4.3). The view is
// the latest lit frame, or one of the host's extra views (SPEC §6.3), injected before it. Each voxel picks a random
// point inside itself (new every frame and view), projects it into the view and compares:
//   Valid   the surface seen at that pixel — or, failing that, at a random texel of the voxel's footprint in the view
//           (where a view grazes a surface, the point's own pixel shows it a voxel or more further on) — lies inside
//           this voxel: store its colour and normal, reset the counter;
//   Invalid the point is clearly in front of the surface seen there (the view looks through this voxel) and the
//           voxel lies wholly off that surface's tangent plane: count a frame; past the threshold the voxel is
//           cleared;
//   Skip    behind the surface or off-screen: nothing is known, nothing changes.
// A brick left empty for emptyFramesToRelease injections returns to the pool the same frame.
#include "gi/gi_frame.glsl"
#include "gi/voxels/brick_pool.glsl"
#include "gi/voxels/hiz_occlusion.glsl"
#include "gi/voxels/voxel_access.glsl"
#include "gi/work_counting.glsl"
#include "shared/sampling.h"
#include "shared/ray_box.h"

layout(local_size_x = 8 * kInjectionBricksPerGroup) in;
// Whether the view is a reflective shadow map (kViewIsReflectiveShadowMap; SceneVoxelization::record picks the
// pipeline): a pipeline of its own, since lavapipe would run litShareOfPlane's lattice for every voxel of every view,
// taken or not.
layout(constant_id = 0) const bool kReflectiveShadowMap = false;

layout(binding = kBindInjectionColor) uniform sampler2D litColor;
layout(binding = kBindInjectionDepth) uniform sampler2D litDepth;
layout(binding = kBindInjectionNormal) uniform sampler2D litNormal;
layout(binding = kBindInjectionAlbedo) uniform sampler2D litAlbedo;
layout(binding = kBindInjectionIrradiance) uniform sampler2D lastOutput;
layout(binding = kBindInjectionBricks) readonly buffer VisibleBricks {
  IndirectList visible;
  uint visibleBricks[];
};

// The view's and the volume's constants that the helpers below use, read once at the start of main rather than at
// each use: on lavapipe a read of a buffer is made lane by lane, and the loop over a brick's blocks would make each
// read once a block, and litShareOfPlane's lattice, unrolled, nine times over, taken or not (lavapipe runs both sides
// of a branch).
mat4 litViewProjection;
mat4 litInverseViewProjection;
vec2 litSize;
uint viewKind;
uint frameIndex;
float voxelSize;
vec3 viewpoint;
uint invalidFramesToClear;
bool countsVoxelWork;

// What a voxel the view writes takes from its pixel: for a view whose colour is all of its light, that light, an extra
// view's averaged with what the voxel held (kVoxelExtraViewRadianceBlend); for a view lit by direct light only, that
// light and the albedo (an extra view's averaged alike). The light after the first bounce: for the camera's lit
// frame, the host's own — albedo/π · E of ssvgi's last output at that pixel, with which the host lit it (the gather's
// light, tested for visibility and filtered); for an extra view, VoxelRelight's to add, with the probes' visibility
// trace, which this pass cannot make: it writes the voxels it would trace, and without it the lit room's probes lit
// the dark side of `two-rooms`' wall (QUALITY.md, "Voxels follow the light"). Until it is relit, a voxel keeps the part
// of its radiance the probes added (Settings::voxelRelightPeriod), and a new one has none.
void injectLight(inout Voxel voxel, bool occupied, bool blendsWithHeld, ivec2 texel, float litShare) {
  vec3 colour = texelFetch(litColor, texel, 0).rgb;
  if ((viewKind & kViewIsDirectOnly) == 0u) {
    voxel.radiance = packR11G11B10F(blendsWithHeld ? mix(unpackR11G11B10F(voxel.radiance), colour,
                                                         kVoxelExtraViewRadianceBlend)
                                                   : colour);
    voxel.directRadiance = 0u;
    voxel.albedo = 0u;
    return;
  }
  vec3 direct = colour * litShare;
  vec3 albedo = texelFetch(litAlbedo, texel, 0).rgb;
  bool wasRelit = occupied && (voxel.albedo & kVoxelRelit) != 0u;
  vec3 heldDirect = unpackR11G11B10F(voxel.directRadiance);
  vec3 probesLight = wasRelit ? max(unpackR11G11B10F(voxel.radiance) - heldDirect, vec3(0.0)) : vec3(0.0);
  if ((viewKind & kViewIsLitWithOutput) != 0u)  // half-resolution texel h holds full-resolution pixel 2h
    probesLight = albedo * (1.0 / kPi) * texelFetch(lastOutput, texel / 2, 0).rgb;
  if (blendsWithHeld && wasRelit) {
    direct = mix(heldDirect, direct, kVoxelExtraViewRadianceBlend);
    albedo = mix(unpackVoxelAlbedo(voxel.albedo), albedo, kVoxelExtraViewRadianceBlend);
  }
  voxel.radiance = packR11G11B10F(direct + probesLight);
  voxel.directRadiance = packR11G11B10F(direct);
  voxel.albedo = packVoxelAlbedo(albedo);
}

// A reflective shadow map's sample of a voxel's surface in its light's shadow (ontoVoxelPlane): no direct light
// there, averaged in as a lit sample is (kVoxelExtraViewRadianceBlend), so that a voxel keeps the lit share of its
// surface's light. Its albedo and the probes' part of its light stay.
void injectShadow(inout Voxel voxel) {
  vec3 heldDirect = unpackR11G11B10F(voxel.directRadiance);
  vec3 probesLight = max(unpackR11G11B10F(voxel.radiance) - heldDirect, vec3(0.0));
  vec3 direct = mix(heldDirect, vec3(0.0), kVoxelExtraViewRadianceBlend);
  voxel.radiance = packR11G11B10F(direct + probesLight);
  voxel.directRadiance = packR11G11B10F(direct);
}

// What the view shows at one of its texels: the surface reconstructed from its depth (depth 0: nothing, and the
// other fields zero), its normal, and the point a voxel holding that surface holds (heldSurfacePoint).
struct ViewSample {
  ivec2 texel;
  float depth;
  vec3 surface;
  vec3 normal;
  vec3 held;
};

ViewSample viewSampleAt(ivec2 texel) {
  ViewSample seen = ViewSample(texel, texelFetch(litDepth, texel, 0).r, vec3(0.0), vec3(0.0), vec3(0.0));
  if (seen.depth <= 0.0) return seen;
  seen.surface = reconstructPosition(litInverseViewProjection, vec2(texel), litSize, seen.depth);
  seen.normal = normalize(texelFetch(litNormal, texel, 0).xyz);
  seen.held = heldSurfacePoint(seen.surface, seen.normal, viewpoint, voxelSize);
  return seen;
}

// Whether the tangent plane of the surface a texel shows cuts the voxel's box.
bool surfacePlaneCutsVoxel(ViewSample seen, vec3 voxelMin) {
  float halfExtent = 0.5 * voxelSize * dot(abs(seen.normal), vec3(1.0));
  return abs(dot(voxelMin + 0.5 * voxelSize - seen.held, seen.normal)) < halfExtent;
}

// Whether a texel may show the voxel's surface: the tangent plane of what it shows cuts the voxel and the point it
// shows lies within a voxel of it (a texel's centre lies up to a texel's slope off the depth of a point in it). With
// normals that agree (kOwnSurfaceFacing) it is taken for the voxel's own surface.
const float kOwnSurfaceFacing = 0.9;
bool showsSurfaceAt(ViewSample seen, vec3 voxelMin) {
  return seen.depth > 0.0 && surfacePlaneCutsVoxel(seen, voxelMin) &&
         distance(seen.held, clamp(seen.held, voxelMin, voxelMin + voxelSize)) <= voxelSize;
}

// Whether the line of sight through the centre of the sample's texel — the line along which the view measured its
// depth — crosses the voxel's box and leaves it more than `margin` before the surface the texel shows (or crosses it
// at all, where the texel shows none). A texel is as wide as a voxel or wider, and its depth says nothing of the space
// beside that line: a random point of a voxel that projects into the texel may lie off it, hidden behind an edge the
// line passes (a wall's top under a roof's rim, seen from above past the rim).
bool sightCrossesVoxel(ViewSample seen, vec3 voxelMin, float margin) {
  vec2 centre = vec2(seen.texel);
  vec3 nearPoint = reconstructPosition(litInverseViewProjection, centre, litSize, 1.0);
  vec3 direction = viewRayDirection(litInverseViewProjection, ssvgiPixelToNdc(centre, litSize));
  vec2 span = intersectBounds(nearPoint, safeInverseDirection(direction), voxelMin, voxelMin + voxelSize);
  float surfaceDistance = seen.depth <= 0.0 ? 1e30 : dot(seen.surface - nearPoint, direction);
  return span.y > max(span.x, 0.0) && span.y < surfaceDistance - margin;
}

// Valid (SPEC §4.3): the surface seen lies inside the voxel. A wall one voxel thick, seen from inside by the camera and
// from outside by the sun, puts two opposite faces in the same voxels. A voxel holds one: the face towards the camera's
// viewpoint (volumeViewpoint) — the side its surroundings see — rather than flipping between the two with
// the views (the dark room's walls turned black from inside, and flickered: QUALITY.md, "Views beyond the camera").
bool holdsSeenSurface(ViewSample seen, vec3 voxelMin, bool occupied, vec3 storedNormal) {
  bool turnsSurfaceAround = occupied && dot(storedNormal, seen.normal) < 0.0 &&
                            dot(seen.normal, viewpoint - (voxelMin + 0.5 * voxelSize)) <= 0.0;
  return seen.depth > 0.0 && !turnsSurfaceAround && all(greaterThanEqual(seen.held, voxelMin)) &&
         all(lessThan(seen.held, voxelMin + voxelSize));
}

// A random texel (new every frame and view) of the voxel's footprint in the view: the bounding rectangle of its
// corners' projections, clipped to the image. (-1, -1) where the footprint lies off the image or a corner lies behind
// a perspective view's eye.
ivec2 footprintTexel(vec3 voxelMin, uvec3 worldVoxel) {
  // The projection is linear in clip space: one product for the minimum corner, the matrix's columns for the edges.
  vec4 minimumClip = litViewProjection * vec4(voxelMin, 1.0);
  mat3x4 edges = mat3x4(litViewProjection[0], litViewProjection[1], litViewProjection[2]) * voxelSize;
  vec2 lowest = vec2(3.0e38), highest = vec2(-3.0e38);
  for (int corner = 0; corner < 8; ++corner) {
    vec4 clip = minimumClip + edges * vec3(corner & 1, (corner >> 1) & 1, corner >> 2);
    if (clip.w <= 0.0) return ivec2(-1);
    vec2 pixel = ssvgiNdcToPixel(clip.xy / clip.w, litSize);
    lowest = min(lowest, pixel);
    highest = max(highest, pixel);
  }
  lowest = max(lowest, vec2(0.0));
  highest = min(highest, litSize - 1.0);
  if (any(greaterThan(lowest, highest))) return ivec2(-1);
  vec2 pick = hashToUnitCube(voxelFootprintSeed(worldVoxel, frameIndex)).xy;
  return ivec2(mix(lowest, highest, pick));
}

// The texel `corner` (0–3) of the 2×2 texels from `firstTexel`, clamped to the image.
ivec2 aroundTexel(ivec2 firstTexel, int corner) {
  return clamp(firstTexel + ivec2(corner & 1, corner >> 1), ivec2(0), ivec2(litSize) - 1);
}

// The depths of the 2×2 texels from `firstTexel` (corner 0–3 in x, y order), read once for the tests below.
vec4 depthsAround(ivec2 firstTexel) {
  return vec4(texelFetch(litDepth, aroundTexel(firstTexel, 0), 0).r,
              texelFetch(litDepth, aroundTexel(firstTexel, 1), 0).r,
              texelFetch(litDepth, aroundTexel(firstTexel, 2), 0).r,
              texelFetch(litDepth, aroundTexel(firstTexel, 3), 0).r);
}

// Whether a texel, whose depth is `depth`, shows a surface inside the voxel (the point it holds, heldSurfacePoint).
bool showsSurfaceInside(ivec2 texel, float depth, vec3 voxelMin) {
  vec3 surface = reconstructPosition(litInverseViewProjection, vec2(texel), litSize, depth);
  vec3 held = heldSurfacePoint(surface, normalize(texelFetch(litNormal, texel, 0).xyz), viewpoint, voxelSize);
  return depth > 0.0 && all(greaterThanEqual(held, voxelMin)) && all(lessThan(held, voxelMin + voxelSize));
}

// Whether one of the 2×2 texels from `firstTexel` (their depths `depths`) shows a surface inside the voxel.
bool surfaceAround(ivec2 firstTexel, vec4 depths, vec3 voxelMin) {
  return showsSurfaceInside(aroundTexel(firstTexel, 0), depths.x, voxelMin) ||
         showsSurfaceInside(aroundTexel(firstTexel, 1), depths.y, voxelMin) ||
         showsSurfaceInside(aroundTexel(firstTexel, 2), depths.z, voxelMin) ||
         showsSurfaceInside(aroundTexel(firstTexel, 3), depths.w, voxelMin);
}

// A reflective shadow map (kViewIsReflectiveShadowMap) looks at an occupied voxel where its surface is: the random
// point moved onto the voxel's plane. A surface it shows in front of that point hides it from the view's light, so it
// lies in that light's shadow (litShareOfPlane).
vec3 ontoVoxelPlane(vec3 point, Voxel voxel, vec3 voxelMin) {
  vec3 normal = voxelNormal(voxel);
  vec3 planePoint = voxelMin + voxelSize * (0.5 + normal * unpackVoxelPlane(voxelPlaneCode(voxel)));
  return point - normal * dot(point - planePoint, normal);
}

// Where a point lands in the view: its pixel, its NDC, and whether the view sees it — inside the view and between its
// near and far planes (reversed-Z: NDC depth 1 to 0); what the near plane or an orthographic view's far plane clipped
// away is not known to be empty.
struct ViewPoint {
  vec2 pixel;
  vec2 ndc;
  bool inView;
};

ViewPoint projectIntoView(vec3 point) {
  vec4 clip = litViewProjection * vec4(point, 1.0);
  vec3 ndc = clip.xyz / clip.w;
  ViewPoint projected;
  projected.ndc = ndc.xy;
  projected.pixel = ssvgiNdcToPixel(ndc.xy, litSize);
  projected.inView = clip.w > 0.0 && ndc.z <= 1.0 && ndc.z >= 0.0 &&
                     all(greaterThanEqual(projected.pixel, vec2(0.0))) && all(lessThan(projected.pixel, litSize));
  return projected;
}

// How much of an occupied voxel's surface a reflective shadow map shows lit: a jittered kLitShareLattice² lattice of
// points on the voxel's plane (spread over the two axes its normal leans on least, the first the random point
// `firstPoint`), each looked at in the view. A point whose texel shows a surface in front of it (by more than
// `margin`) lies in the light's shadow, one whose texel shows the voxel's own face is lit, and one the view sees past
// (the plane does not reach there) or does not show counts for neither. One random point a view, averaged over views,
// kept a voxel a shadow's edge crosses flipping between lit and dark by about a fifth of its light, and a scene lit
// through such edges (the gallery) stopped converging; the lattice gives the share each view.
const int kLitShareLattice = 3;
struct LitShare {
  uint lit;
  uint shadowed;
  ivec2 litTexel;  // the texel of a lit point, whose colour is the surface's light where it is lit
};

LitShare litShareOfPlane(vec3 firstPoint, Voxel voxel, vec3 voxelMin, float margin) {
  LitShare share = LitShare(0u, 0u, ivec2(0));
  vec3 voxelFacing = voxelNormal(voxel);
  vec3 normal = abs(voxelFacing);
  int dropped = normal.x >= normal.y && normal.x >= normal.z ? 0 : (normal.y >= normal.z ? 1 : 2);
  int first = (dropped + 1) % 3, second = (dropped + 2) % 3;
  vec3 jitter = (firstPoint - voxelMin) / voxelSize;
  for (int i = 0; i < kLitShareLattice; ++i)
    for (int j = 0; j < kLitShareLattice; ++j) {
      vec3 lattice = jitter;
      lattice[first] = fract(jitter[first] + float(i) / float(kLitShareLattice));
      lattice[second] = fract(jitter[second] + float(j) / float(kLitShareLattice));
      vec3 point = ontoVoxelPlane(voxelMin + lattice * voxelSize, voxel, voxelMin);
      ViewPoint projected = projectIntoView(point);
      if (!projected.inView) continue;
      ViewSample seen = viewSampleAt(ivec2(projected.pixel));
      if (seen.depth <= 0.0) continue;
      // Lit where the texel shows the voxel's own face (as a colour refresh takes it, below). Hidden where it shows a
      // surface well in front of the point, or the back of the voxel's face (the other face of a wall one voxel
      // thick, which the light reaches and the voxel's face does not).
      bool atVoxel = showsSurfaceAt(seen, voxelMin);
      float facing = dot(seen.normal, voxelFacing);
      float beyond = dot(seen.surface - point, viewRayDirection(litInverseViewProjection, projected.ndc));
      if (atVoxel && facing > kOwnSurfaceFacing) {
        ++share.lit;
        share.litTexel = seen.texel;
      } else if (beyond < -margin || (atVoxel && facing < 0.0)) {
        ++share.shadowed;
      }
    }
  return share;
}

// Per brick of the workgroup: its blocks to inject, what they leave occupied and observed, and (on a frame that counts
// its work) its voxels whose point lies in the view.
shared uint injectedBlocks[kInjectionBricksPerGroup];
shared uint occupancyLow[kInjectionBricksPerGroup];
shared uint occupancyHigh[kInjectionBricksPerGroup];
shared uint observedLow[kInjectionBricksPerGroup];
shared uint observedHigh[kInjectionBricksPerGroup];
shared uint voxelsInView[kInjectionBricksPerGroup];

uint brickSlot() { return gl_LocalInvocationID.x / 8u; }

// What injecting a voxel left: whether it is occupied, and whether the view observed it empty now.
struct InjectedVoxel {
  bool occupied;
  bool observedNow;
};

// SPEC §4.3 for one voxel (the three outcomes above); it writes the voxel where its point lies in the view.
// `held`: the brick as it was before this injection.
InjectedVoxel injectVoxel(uint brick, Brick held, uvec3 voxelInBrick) {
  uint bit = voxelBit(voxelInBrick);
  uint voxelIndex = bit;  // a voxel's slot in its brick is its bit in the brick's masks
  ivec3 worldVoxel = held.coordinate * int(kBrickSizeVoxels) + ivec3(voxelInBrick);
  bool occupied = maskHasVoxel(held.occupancy, bit);
  bool wasObserved = maskHasVoxel(held.observed, bit);
  Voxel voxel = voxels[brick * kVoxelsPerBrick + voxelIndex];
  vec3 voxelMin = vec3(worldVoxel) * voxelSize;
  vec3 samplePoint =
      voxelMin + hashToUnitCube(uvec3(ivec3(worldVoxel)) ^ uvec3(0u, 0u, frameIndex * 0x9e3779b9u)) * voxelSize;
  bool samplesShadow = kReflectiveShadowMap && occupied &&
                       (voxel.albedo & kVoxelRelit) != 0u && voxelPlaneCode(voxel) != 0u;
  if (samplesShadow) samplePoint = ontoVoxelPlane(samplePoint, voxel, voxelMin);
  ViewPoint projected = projectIntoView(samplePoint);
  vec2 pixel = projected.pixel;
  bool seenThrough = false;
  bool observedNow = false;
  if (projected.inView) {
    if (countsVoxelWork) atomicAdd(voxelsInView[brickSlot()], 1u);
    ViewSample seen = viewSampleAt(ivec2(pixel));
    // "Clearly in front" along the view's ray (perspective or orthographic): by more than half a voxel, so that depth
    // quantisation and a surface point just outside this voxel do not count against it — and in front of the nearest
    // surface the view shows around the point (the 2×2 texels nearest it), so that at a depth edge (the rim of an
    // opening, a silhouette) a texel whose centre sees past the edge does not clear the edge's own voxels. Coarse views
    // (the sun's, a capture's) have texels as wide as a voxel: a skylight's rim was cleared every few frames.
    float clearMargin = voxelSize * 0.5;
    ivec2 firstTexel = ivec2(floor(pixel - 0.5));
    vec4 aroundDepths = depthsAround(firstTexel);
    // reversed-Z: the largest is the nearest; 0 where all four see nothing
    float nearestDepth = max(max(aroundDepths.x, aroundDepths.y), max(aroundDepths.z, aroundDepths.w));
    vec3 nearestSurface = reconstructPosition(litInverseViewProjection, pixel - 0.5, litSize, nearestDepth);
    vec3 viewDirection = viewRayDirection(litInverseViewProjection, projected.ndc);
    bool inFront = dot(nearestSurface - samplePoint, viewDirection) > clearMargin;
    // Seeing through one point of a voxel proves only that point empty. A voxel that the surface seen there passes
    // through (its tangent plane cuts the voxel's box) may hold that surface elsewhere: at a grazing view most of
    // the points of a voxel on a wall lie in front of the wall and see it further on, and would clear the voxel
    // (holes in walls, and light through them). Only a voxel wholly in front of that plane is seen through.
    bool cutBySurfacePlane = surfacePlaneCutsVoxel(seen, voxelMin);
    vec3 storedNormal = voxelNormal(voxel);
    bool holdsSurface = holdsSeenSurface(seen, voxelMin, occupied, storedNormal);
    // The point's own texel shows this voxel's surface only where the view meets it nearly head-on: seen at a grazing
    // angle, the surface behind a random point of the voxel lies a voxel or more further on. An empty voxel gets a
    // second look, at a random texel of its footprint in the view, so that a wall the view grazes (one beside the
    // camera, in a capture face) fills in fewer injections — its holes let the probes' rays see what lies behind it.
    // Only an empty one: an occupied voxel's light is refreshed from its own surface's pixels (below), and a look
    // anywhere in its footprint took the light of neighbouring surfaces into it (cornell's light panel grew; docs/
    // QUALITY.md, "Holes in walls a view grazes, and a wall's two faces").
    if (!holdsSurface && !occupied) {
      ivec2 footprint = footprintTexel(voxelMin, uvec3(worldVoxel));
      if (footprint.x >= 0) {
        ViewSample second = viewSampleAt(footprint);
        if (holdsSeenSurface(second, voxelMin, occupied, storedNormal)) {
          seen = second;
          holdsSurface = true;
        }
      }
    }
    // An occupied voxel also takes the colour of a pixel of its own surface (the seen surface's plane cuts it, the
    // normals agree) up to a voxel away: few random points of a voxel on a wall seen at a grazing angle land on its
    // own pixels, and its radiance would lag a change of light by many frames.
    bool refreshesColour =
        occupied && showsSurfaceAt(seen, voxelMin) && dot(storedNormal, seen.normal) > kOwnSurfaceFacing;
    // A voxel a reflective shadow map shows in part in its light's shadow takes the lit share of its light, or none.
    LitShare litShare = samplesShadow ? litShareOfPlane(samplePoint, voxel, voxelMin, clearMargin)
                                      : LitShare(0u, 0u, ivec2(0));
    bool crossesShadow = litShare.shadowed > 0u;
    bool inLightsShadow = crossesShadow && litShare.lit == 0u;
    if (holdsSurface || refreshesColour || crossesShadow) {
      // The lit frame's light stays where it keeps coming (kVoxelExtraViewsBeforeWrite): an extra view counts its
      // visit and writes only once there have been enough since the lit frame last wrote.
      bool fromCamera = (viewKind & kViewIsExtra) == 0u;
      uint extraViews = voxelExtraViewsSinceLitFrame(voxel);
      bool writes = fromCamera || !occupied || extraViews >= kVoxelExtraViewsBeforeWrite;
      uint surface = voxelSurface(voxel);
      if (writes && inLightsShadow) {
        injectShadow(voxel);
      } else if (writes) {
        // An extra view's light is averaged with what the voxel held only while the voxel keeps its surface's side. A
        // wall one voxel thick has both faces in its voxels; one that a view saw from outside while it was empty
        // holds the outer face until a view from inside turns it round (turnsSurfaceAround), and averaged, the inner
        // face would take three quarters of the outer one's sunlight into the room.
        bool seesOwnSurface = holdsSurface || refreshesColour;
        bool keepsSide = occupied && (crossesShadow || dot(storedNormal, seen.normal) > 0.0);
        float share = crossesShadow ? float(litShare.lit) / float(litShare.lit + litShare.shadowed) : 1.0;
        injectLight(voxel, occupied, !fromCamera && keepsSide, seesOwnSurface ? seen.texel : litShare.litTexel, share);
        // A valid sample sets the voxel's surface (normal and plane); a refresh keeps it.
        float planeOffset = dot(seen.surface - (voxelMin + 0.5 * voxelSize), seen.normal) / voxelSize;
        if (holdsSurface)
          surface = packVoxelSurface(seen.normal, packVoxelPlane(planeOffset));
      }
      extraViews = fromCamera ? 0u : (writes ? kVoxelExtraViewsBeforeWrite : extraViews + 1u);
      // Seeing its surface resets the seen-through counter; seeing it hidden does not.
      voxel.surfaceAndLastHit =
          packVoxelSurfaceAndCounters(surface, inLightsShadow ? voxelSeenThroughCount(voxel) : 0u, extraViews);
      occupied = true;
    }
    seenThrough = !holdsSurface && !refreshesColour && (nearestDepth <= 0.0 || (inFront && !cutBySurfacePlane));
    // Observed empty (Brick::observed) takes less: the line of sight of the point's own texel crosses the voxel and
    // leaves it before the surface it shows (sightCrossesVoxel), that surface does not cut the voxel, and none of the
    // four texels around shows a surface inside it. The rim of an opening, whose voxels lie wholly in the opening, is
    // then observed, and a rim's own voxels, the holes a view leaves in a wall it grazes, and a wall's voxels hidden
    // beside a line of sight that passes them are not.
    // Once observed, a voxel stays so (the mask is sticky): only one not yet observed is looked at again, and the
    // cheap tests come first.
    observedNow = !wasObserved && !holdsSurface && !refreshesColour && !cutBySurfacePlane &&
                  sightCrossesVoxel(seen, voxelMin, clearMargin) &&
                  !surfaceAround(firstTexel, aroundDepths, voxelMin);
    if (occupied && seenThrough) {
      uint lastHit = min(voxelSeenThroughCount(voxel) + 1u, kVoxelMaxLastHit);
      voxel.surfaceAndLastHit =
          packVoxelSurfaceAndCounters(voxelSurface(voxel), lastHit, voxelExtraViewsSinceLitFrame(voxel));
      if (lastHit >= invalidFramesToClear) occupied = false;
    }
    voxels[brick * kVoxelsPerBrick + voxelIndex] = occupied ? voxel : Voxel(0u, 0u, 0u, 0u);
  }

  return InjectedVoxel(occupied, observedNow);
}

// The corner of a 2×2×2 cube numbered 0–7: bit 0 x, 1 y, 2 z.
uvec3 octant(uint index) { return uvec3(index & 1u, (index >> 1u) & 1u, index >> 2u); }

// A brick's eight threads take its voxels by blocks of 2×2×2, thread t the voxel t of each block.
uvec3 blockVoxel(uint block, uint thread) { return 2u * octant(block) + octant(thread); }

// The bits of a brick's 64-bit voxel mask that a block holds.
uvec2 voxelMaskOfBlock(uint block) {
  uint bits = blockBitsInWord(octant(block));
  return octant(block).z == 0u ? uvec2(bits, 0u) : uvec2(0u, bits);
}

// The same for the blocks of `blocks` (a bit per block).
uvec2 voxelMaskOfBlocks(uint blocks) {
  uvec2 mask = uvec2(0u);
  for (uint block = 0u; block < 8u; ++block)
    if (((blocks >> block) & 1u) != 0u) mask |= voxelMaskOfBlock(block);
  return mask;
}

// Whether the view may change a block's voxels (hiddenFromInjection). The camera's Hi-Z is the current frame's depth,
// its lit frame the one before: as for BrickCulling's bricks, a block hidden now and seen then waits a frame.
bool blockMayChange(ivec3 worldBrick, uint block, uvec2 heldOccupancy) {
  bool holdsOccupied = any(notEqual(heldOccupancy & voxelMaskOfBlock(block), uvec2(0u)));
  vec3 lo = (vec3(worldBrick * int(kBrickSizeVoxels)) + vec3(blockVoxel(block, 0u))) * voxelSize;
  return !hiddenFromInjection(lo, lo + 2.0 * voxelSize, holdsOccupied, voxelSize);
}

// The brick's work (shared/work_counters.h), by its first thread once its voxels are done: the camera's lit frame's,
// or an extra view's.
void countBrickWork(uint injectedVoxels) {
  if ((viewKind & kViewIsExtra) == 0u) {
    atomicAdd(work.injectionVoxels, injectedVoxels);
    atomicAdd(work.injectionVoxelsInView, voxelsInView[brickSlot()]);
  } else {
    atomicAdd(work.extraViewInjectionVoxels, injectedVoxels);
    atomicAdd(work.extraViewInjectionVoxelsInView, voxelsInView[brickSlot()]);
  }
}

// Eight threads a brick, each testing one of its blocks and then injecting its voxel of every block that may change:
// on a CPU (lavapipe) or a GPU's lock-step threads alike, the work follows the blocks a view can change, not the
// brick's 64 voxels.
void main() {
  litViewProjection = frame.litViewProjection;
  litInverseViewProjection = frame.litInverseViewProjection;
  litSize = vec2(frame.litSize);
  viewKind = frame.viewKind;
  frameIndex = frame.frameIndex;
  voxelSize = volume.voxelSize;
  viewpoint = volumeViewpoint();
  invalidFramesToClear = volume.invalidFramesToClear;
  countsVoxelWork = countsWork();
  uint slot = brickSlot();
  uint thread = gl_LocalInvocationID.x % 8u;
  uint listIndex = gl_WorkGroupID.x * kInjectionBricksPerGroup + slot;
  bool listed = listIndex < visible.count;
  uint brick = listed ? visibleBricks[listIndex] : 0u;
  Brick heldBrick = bricks[brick];
  ivec3 worldBrick = heldBrick.coordinate;

  if (thread == 0u) {
    injectedBlocks[slot] = 0u;
    occupancyLow[slot] = 0u;
    occupancyHigh[slot] = 0u;
    observedLow[slot] = 0u;
    observedHigh[slot] = 0u;
    voxelsInView[slot] = 0u;
  }
  barrier();
  if (listed && blockMayChange(worldBrick, thread, heldBrick.occupancy)) atomicOr(injectedBlocks[slot], 1u << thread);
  barrier();

  uint blocks = injectedBlocks[slot];
  uvec2 occupiedBits = uvec2(0u), observedBits = uvec2(0u);
  for (uint remaining = blocks; remaining != 0u; remaining &= remaining - 1u) {
    uvec3 voxelInBrick = blockVoxel(uint(findLSB(remaining)), thread);
    InjectedVoxel injected = injectVoxel(brick, heldBrick, voxelInBrick);
    uint bit = voxelBit(voxelInBrick);
    uvec2 voxelMask = bit < 32u ? uvec2(1u << bit, 0u) : uvec2(0u, 1u << (bit - 32u));
    if (injected.occupied) occupiedBits |= voxelMask;
    // Observed (SPEC §6.4, voxel_interface.h): a voxel seen holding a surface or seen through. An empty voxel the seen
    // surface's plane cuts is neither: it may hold that surface where the view did not look (a hole in a wall).
    if (injected.occupied || injected.observedNow) observedBits |= voxelMask;
  }
  atomicOr(occupancyLow[slot], occupiedBits.x);
  atomicOr(occupancyHigh[slot], occupiedBits.y);
  atomicOr(observedLow[slot], observedBits.x);
  atomicOr(observedHigh[slot], observedBits.y);
  barrier();

  if (listed && thread == 0u) {
    if (countsVoxelWork) countBrickWork(8u * uint(bitCount(blocks)));
    // The blocks not injected keep their voxels as they were.
    uvec2 mask = (heldBrick.occupancy & ~voxelMaskOfBlocks(blocks)) | uvec2(occupancyLow[slot], occupancyHigh[slot]);
    bool empty = mask == uvec2(0u);
    uint emptyInjections = empty ? heldBrick.emptyInjections + 1u : 0u;
    uint cell = brickCellIndex(worldBrick, volumeDimensions());
    // BuildOctree's brick level records whether a brick's mask is empty: only a change of that needs the cell listed,
    // and once a frame is enough (BuildOctree runs after every view's injection).
    uint listedStamp = frameIndex + 1u;
    bool cellListed = empty != (heldBrick.occupancy == uvec2(0u)) && heldBrick.changeListedStamp != listedStamp;
    bricks[brick].occupancy = mask;
    bricks[brick].observed = heldBrick.observed | uvec2(observedLow[slot], observedHigh[slot]);
    bricks[brick].emptyInjections = emptyInjections;
    if (cellListed) bricks[brick].changeListedStamp = listedStamp;
    if (emptyInjections >= volume.emptyFramesToRelease) {
      releaseBrick(brick, cell);
    } else if (cellListed) {
      markCellChanged(cell);
    }
  }
}
