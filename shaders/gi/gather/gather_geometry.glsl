#ifndef SSVGI_GATHER_GEOMETRY_GLSL
#define SSVGI_GATHER_GEOMETRY_GLSL
// What Upsample and TemporalFilter share: the frame's inputs, the geometry test (how much a neighbouring sample belongs
// to a pixel's surface) and the tile samples around a pixel.
#include "gi/gi_frame.glsl"
#include "shared/gather_interface.h"
#include "ssvgi/resolve.glsl"

layout(binding = kBindGatherConstants) uniform GatherConstantsBlock { GatherConstants gather; };
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

// Taps beyond the bilinear 2×2 keep this spatial weight: they count only where the 2×2 are all on other surfaces (a
// thin object, a silhouette), so such a pixel borrows from its own surface a tile further away instead of going dark.
const float kOuterTapWeight = 1e-3;
// A tap whose geometry weight reaches this lies on the pixel's surface for TemporalFilter's neighbourhood clamp.
const float kSameSurfaceWeight = 0.5;

// This frame's tile samples around a surface pixel (FinalGather sampled pixel t·4 + offset of tile t).
struct TileNeighbourhood {
  vec3 blended;  // Upsample's result: bilinear in the sample grid × geometry weights (joint bilateral)
  float confidence;  // the tiles' confidence blended with the same weights (0 where no tile's sample is on the surface)
  vec3 lowest;   // the range of the bilinear taps on the pixel's surface (none: lowest > highest)
  vec3 highest;
  // Their probe blend (GatheredLight::probeBlend), weighted as `blended` weighs them; 1 (start afresh) when none is on
  // the surface. Only TemporalFilter reads it, and with the range: the outer taps, which count only where the bilinear
  // four miss the surface, are left out of both, and their loads with them.
  float probeBlend;
  // Some tap's sample lies on the pixel's surface. A sliver a few pixels wide (the top of a block seen edge-on) can
  // miss all sixteen samples of a frame; its light is then unknown this frame, not zero.
  bool sampled;
};

TileNeighbourhood tileNeighbourhood(Surface surface, ivec2 pixel) {
  ivec2 sampleOffset = ivec2(gatherSampleOffset(gather.frameIndex));
  vec2 tileCoordinate = vec2(pixel - sampleOffset) / float(kGatherTileSize);
  ivec2 firstTile = ivec2(floor(tileCoordinate));
  ivec2 lastTile = ivec2(gather.tiles) - 1;
  TileNeighbourhood result = TileNeighbourhood(vec3(0.0), 0.0, vec3(1e30), vec3(0.0), 0.0, false);
  float sameSurfaceWeight = 0.0;
  float totalWeight = 0.0;
  for (int y = -1; y <= 2; ++y)
    for (int x = -1; x <= 2; ++x) {
      ivec2 tile = firstTile + ivec2(x, y);
      if (any(lessThan(tile, ivec2(0))) || any(greaterThan(tile, lastTile))) continue;
      // The tile's geometry is that of the pixel it sampled.
      ivec2 samplePixel = min(tile * int(kGatherTileSize) + sampleOffset, ivec2(frame.size) - 1);
      float sampleDepth = texelFetch(depthBuffer, samplePixel, 0).r;
      if (sampleDepth <= 0.0) continue;  // the tile's sample saw nothing
      vec3 samplePosition = reconstructPosition(frame.inverseViewProjection, vec2(samplePixel), vec2(frame.size),
                                                sampleDepth);
      float geometry = planeWeight(surface, samplePosition) *
                       normalWeight(surface, normalize(texelFetch(normalBuffer, samplePixel, 0).xyz));
      vec4 tileSample = imageLoad(tileIrradiance, tile);  // rgb E; a: confidence
      vec3 irradiance = tileSample.rgb;
      vec2 tent = max(vec2(1.0) - abs(vec2(tile) - tileCoordinate), vec2(kOuterTapWeight));
      result.blended += tent.x * tent.y * geometry * irradiance;
      result.confidence += tent.x * tent.y * geometry * tileSample.a;
      totalWeight += tent.x * tent.y * geometry;
      if (x >= 0 && x <= 1 && y >= 0 && y <= 1 && geometry >= kSameSurfaceWeight) {
        result.lowest = min(result.lowest, irradiance);
        result.highest = max(result.highest, irradiance);
        result.probeBlend += tent.x * tent.y * geometry * imageLoad(tileProbeBlend, tile).r;
        sameSurfaceWeight += tent.x * tent.y * geometry;
      }
    }
  result.sampled = totalWeight > 0.0;
  result.blended = totalWeight > 0.0 ? result.blended / totalWeight : vec3(0.0);
  result.confidence = totalWeight > 0.0 ? result.confidence / totalWeight : 0.0;
  result.probeBlend = sameSurfaceWeight > 0.0 ? result.probeBlend / sameSurfaceWeight : 1.0;
  return result;
}

#endif
