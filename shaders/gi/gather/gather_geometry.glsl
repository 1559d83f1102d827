#ifndef SSVGI_GATHER_GEOMETRY_GLSL
#define SSVGI_GATHER_GEOMETRY_GLSL
// TemporalUpsample's geometry: the frame's inputs, the geometry test (how much a neighbouring sample belongs to a
// pixel's surface) and the tile samples around a pixel.
#include "gi/gi_frame.glsl"
#include "shared/gather_interface.h"
#include "ssvgi/resolve.glsl"

layout(binding = kBindGatherConstants, std140) readonly buffer GatherConstantsBlock { GatherConstants gather; };
layout(binding = kBindGatherDepth) uniform sampler2D depthBuffer;
layout(binding = kBindGatherNormal) uniform sampler2D normalBuffer;
layout(binding = kBindGatherTileIrradiance, rgba16f) readonly uniform image2D tileIrradiance;
layout(binding = kBindGatherTileProbeBlend, r8) readonly uniform image2D tileProbeBlend;

// A G-buffer sample as the filters compare it.
struct Surface {
  vec3 position;  // world, m
  vec3 normal;
  float viewDistance;
};

Surface surfaceAt(mat4 inverseViewProjection, vec3 cameraPosition, ivec2 pixel, vec2 size, float depth, vec3 normal) {
  vec3 position = reconstructPosition(inverseViewProjection, vec2(pixel), size, depth);
  return Surface(position, normal, distance(position, cameraPosition));
}

// The surface at a pixel of this frame (depth > 0: something was drawn there).
Surface currentSurface(ivec2 pixel, float depth) {
  return surfaceAt(frame.inverseViewProjection, frame.cameraPosition, pixel, vec2(frame.size), depth,
                   normalize(texelFetch(normalBuffer, pixel, 0).xyz));
}

// How much a neighbour belongs to the pixel's surface, as the host's resolve weighs it (ssvgi/resolve.glsl): a
// neighbour across a depth edge or a crease lies far off the pixel's tangent plane, one on the same tilted floor does
// not.
float planeWeight(Surface pixel, vec3 neighbourPosition) {
  return ssvgiPlaneWeight(pixel.position, pixel.normal, pixel.viewDistance, neighbourPosition);
}

float normalWeight(Surface pixel, vec3 neighbourNormal) { return ssvgiNormalWeight(pixel.normal, neighbourNormal); }

// The floor of a tap's tent weight, which the taps beyond the bilinear 2×2 weigh by. They are read only where the 2×2
// all lie on other surfaces (a thin object, a silhouette), so that such a pixel borrows from its own surface a tile
// further away instead of going dark; everywhere else a pixel reads four tiles, not sixteen.
const float kOuterTapWeight = 1e-3;
// A tap whose geometry weight reaches this lies on the pixel's surface for the temporal filter's neighbourhood clamp.
const float kSameSurfaceWeight = 0.5;

// This frame's tile samples around a surface pixel (FinalGather sampled pixel t·4 + offset of each tile t of the
// frame's half).
struct TileNeighbourhood {
  vec3 blended;  // the upsampled light: bilinear in the sample grid × geometry weights (joint bilateral)
  float confidence;  // the tiles' confidence blended with the same weights (0 where no tile's sample is on the surface)
  vec3 lowest;   // the range of the bilinear taps on the pixel's surface (none: lowest > highest)
  vec3 highest;
  // Their probe blend (GatheredLight::probeBlend), weighted as `blended` weighs them; 1 (start afresh) when none is on
  // the surface. Only the temporal filter reads it, with the range.
  float probeBlend;
  // Some tap's sample lies on the pixel's surface. A sliver a few pixels wide (the top of a block seen edge-on) can
  // miss all sixteen samples of a frame; its light is then unknown this frame, not zero.
  bool sampled;
};

// One tile's sample as it bears on a pixel's surface: its light and confidence (a), its geometry weight (0 where the
// tile is outside the image, its sample saw nothing or its gather found no probe) and its probe blend.
struct TileTap {
  vec4 irradiance;
  float geometry;
  float probeBlend;
};

// The lattice points around the bilinear four, in the 4×4 block from (-1, -1) to (2, 2).
const ivec2 kOuterLatticeOffsets[12] = ivec2[](ivec2(-1, -1), ivec2(0, -1), ivec2(1, -1), ivec2(2, -1), ivec2(-1, 0),
                                            ivec2(2, 0), ivec2(-1, 1), ivec2(2, 1), ivec2(-1, 2), ivec2(0, 2),
                                            ivec2(1, 2), ivec2(2, 2));

// What the taps read of the frame's constants, read once for a pixel rather than in its loop over the taps
// (gi/voxels/voxel_access.glsl's VolumeLayout says why).
struct TapFrame {
  mat4 inverseViewProjection;  // GiFrame
  ivec2 size;
  ivec2 tiles;                 // GatherConstants
  ivec2 sampleOffset;          // the pixel each tile sampled this frame, in its tile
  uint parity;                 // which half of the tiles FinalGather sampled this frame (gatherTileParity)
};

TapFrame tapFrame() {
  return TapFrame(frame.inverseViewProjection, ivec2(frame.size), ivec2(gather.tiles),
                  ivec2(gatherSampleOffset(gather.frameIndex)), gatherTileParity(gather.frameIndex));
}

TileTap tileTap(Surface surface, ivec2 tile, TapFrame frameOfTaps) {
  TileTap none = TileTap(vec4(0.0), 0.0, 0.0);
  if (any(lessThan(tile, ivec2(0))) || any(greaterThanEqual(tile, frameOfTaps.tiles))) return none;
  // The tile's geometry is that of the pixel it sampled.
  ivec2 samplePixel = min(tile * int(kGatherTileSize) + frameOfTaps.sampleOffset, frameOfTaps.size - 1);
  float sampleDepth = texelFetch(depthBuffer, samplePixel, 0).r;
  if (sampleDepth <= 0.0) return none;  // the tile's sample saw nothing
  // No probe lit the sample (a corner whose probes all stand in its walls): its 0 is not light. Taken for light, with
  // the blend of probes that start afresh, it replaced the history of the pixels around it whenever the corner was
  // sampled (docs/QUALITY.md, "A tile without probes").
  float probeBlend = imageLoad(tileProbeBlend, tile).r;
  if (probeBlend == kTileFoundNoProbe) return none;
  vec3 samplePosition =
      reconstructPosition(frameOfTaps.inverseViewProjection, vec2(samplePixel), vec2(frameOfTaps.size), sampleDepth);
  float geometry = planeWeight(surface, samplePosition) *
                   normalWeight(surface, normalize(texelFetch(normalBuffer, samplePixel, 0).xyz));
  return TileTap(geometry > 0.0 ? imageLoad(tileIrradiance, tile) : vec4(0.0), geometry, probeBlend);
}

TileNeighbourhood tileNeighbourhood(Surface surface, ivec2 pixel) {
  TapFrame frameOfTaps = tapFrame();
  vec2 tileCoordinate = vec2(pixel - frameOfTaps.sampleOffset) / float(kGatherTileSize);
  vec2 latticeCoordinate = sampledLatticeCoordinate(tileCoordinate, frameOfTaps.parity);
  ivec2 firstPoint = ivec2(floor(latticeCoordinate));
  TileNeighbourhood result = TileNeighbourhood(vec3(0.0), 0.0, vec3(1e30), vec3(0.0), 0.0, false);
  vec4 weightedSum = vec4(0.0);  // rgb E, a confidence
  float totalWeight = 0.0;
  float sameSurfaceWeight = 0.0;
  // The bilinear four first (taps 0–3); the twelve around them only where none of the four is on the surface. The
  // count is not a constant, so that the loop stays a loop: unrolled, lavapipe would run all sixteen taps for every
  // pixel (it runs both sides of a branch); as a loop it stops once no pixel of a group needs more.
  int taps = 4;
  for (int tap = 0; tap < taps; ++tap) {
    ivec2 point = firstPoint + (tap < 4 ? ivec2(tap & 1, tap >> 1) : kOuterLatticeOffsets[tap - 4]);
    TileTap tileSample = tileTap(surface, tileAtLatticePoint(point, frameOfTaps.parity), frameOfTaps);
    vec2 tent = max(vec2(1.0) - abs(vec2(point) - latticeCoordinate), vec2(kOuterTapWeight));
    float weight = tent.x * tent.y * tileSample.geometry;
    weightedSum += weight * tileSample.irradiance;
    totalWeight += weight;
    if (tap < 4 && tileSample.geometry >= kSameSurfaceWeight) {
      result.lowest = min(result.lowest, tileSample.irradiance.rgb);
      result.highest = max(result.highest, tileSample.irradiance.rgb);
      result.probeBlend += weight * tileSample.probeBlend;
      sameSurfaceWeight += weight;
    }
    if (tap == 3 && totalWeight == 0.0) taps = 16;
  }
  result.sampled = totalWeight > 0.0;
  result.blended = totalWeight > 0.0 ? weightedSum.rgb / totalWeight : vec3(0.0);
  result.confidence = totalWeight > 0.0 ? weightedSum.a / totalWeight : 0.0;
  result.probeBlend = sameSurfaceWeight > 0.0 ? result.probeBlend / sameSurfaceWeight : 1.0;
  return result;
}

#endif
