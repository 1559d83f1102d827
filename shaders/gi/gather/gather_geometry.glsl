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

// A tile's sample as the taps read it: the position and normal of the pixel it sampled, its light and confidence (a)
// and its probe blend. Not usable where the tile is outside the image, its sample saw nothing or its gather found no
// probe.
struct TileSample {
  vec3 position;
  vec3 normal;
  vec4 irradiance;
  float probeBlend;
  bool usable;
};

// One tile's sample as it bears on a pixel's surface: its light and confidence (a), its geometry weight (0 where the
// sample is not usable) and its probe blend.
struct TileTap {
  vec4 irradiance;
  float geometry;
  float probeBlend;
};

// The lattice points around the bilinear four, in the 4×4 block from (-1, -1) to (2, 2).
const ivec2 kOuterLatticeOffsets[12] = ivec2[](ivec2(-1, -1), ivec2(0, -1), ivec2(1, -1), ivec2(2, -1), ivec2(-1, 0),
                                            ivec2(2, 0), ivec2(-1, 1), ivec2(2, 1), ivec2(-1, 2), ivec2(0, 2),
                                            ivec2(1, 2), ivec2(2, 2));

// What the pixels and their taps read of the frame's constants, read once for an invocation rather than by each of
// its pixels or in the loops over their taps (gi/voxels/voxel_access.glsl's VolumeLayout says why).
struct TapFrame {
  mat4 inverseViewProjection;  // GiFrame
  vec3 cameraPosition;
  ivec2 size;
  ivec2 halfSize;              // GatherConstants
  ivec2 tiles;
  ivec2 sampleOffset;          // the pixel each tile sampled this frame, in its tile
  uint parity;                 // which half of the tiles FinalGather sampled this frame (gatherTileParity)
};

TapFrame tapFrame() {
  return TapFrame(frame.inverseViewProjection, frame.cameraPosition, ivec2(frame.size), ivec2(gather.halfSize),
                  ivec2(gather.tiles), ivec2(gatherSampleOffset(gather.frameIndex)),
                  gatherTileParity(gather.frameIndex));
}

// The surface at a pixel of this frame (depth > 0: something was drawn there).
Surface currentSurface(TapFrame frameOfTaps, ivec2 pixel, float depth) {
  return surfaceAt(frameOfTaps.inverseViewProjection, frameOfTaps.cameraPosition, pixel, vec2(frameOfTaps.size),
                   depth, normalize(texelFetch(normalBuffer, pixel, 0).xyz));
}

// The sample of the tile at a point of this frame's lattice (tileAtLatticePoint).
TileSample tileSampleAt(ivec2 point, TapFrame frameOfTaps) {
  TileSample result = TileSample(vec3(0.0), vec3(0.0), vec4(0.0), 0.0, false);
  ivec2 tile = tileAtLatticePoint(point, frameOfTaps.parity);
  if (any(lessThan(tile, ivec2(0))) || any(greaterThanEqual(tile, frameOfTaps.tiles))) return result;
  // The tile's geometry is that of the pixel it sampled.
  ivec2 samplePixel = min(tile * int(kGatherTileSize) + frameOfTaps.sampleOffset, frameOfTaps.size - 1);
  float sampleDepth = texelFetch(depthBuffer, samplePixel, 0).r;
  if (sampleDepth <= 0.0) return result;  // the tile's sample saw nothing
  // No probe lit the sample (a corner whose probes all stand in its walls): its 0 is not light. Taken for light, with
  // the blend of probes that start afresh, it replaced the history of the pixels around it whenever the corner was
  // sampled (docs/QUALITY.md, "A tile without probes").
  result.probeBlend = imageLoad(tileProbeBlend, tile).r;
  if (result.probeBlend == kTileFoundNoProbe) return result;
  result.position =
      reconstructPosition(frameOfTaps.inverseViewProjection, vec2(samplePixel), vec2(frameOfTaps.size), sampleDepth);
  result.normal = normalize(texelFetch(normalBuffer, samplePixel, 0).xyz);
  result.irradiance = imageLoad(tileIrradiance, tile);
  result.usable = true;
  return result;
}

TileTap tileTap(Surface surface, TileSample tileSample) {
  if (!tileSample.usable) return TileTap(vec4(0.0), 0.0, 0.0);
  float geometry = planeWeight(surface, tileSample.position) * normalWeight(surface, tileSample.normal);
  return TileTap(geometry > 0.0 ? tileSample.irradiance : vec4(0.0), geometry, tileSample.probeBlend);
}

// A pixel's taps as they are summed, and where on the lattice it lies.
struct PixelTaps {
  vec2 latticeCoordinate;  // sampledLatticeCoordinate
  ivec2 firstPoint;        // the first of its bilinear four lattice points
  vec4 weightedSum;        // rgb E, a confidence
  float totalWeight;
  float sameSurfaceWeight;
  vec3 lowest;
  vec3 highest;
  float probeBlend;
};

PixelTaps pixelTaps(ivec2 pixel, TapFrame frameOfTaps) {
  vec2 latticeCoordinate = sampledLatticeCoordinate(vec2(pixel - frameOfTaps.sampleOffset) / float(kGatherTileSize),
                                                    frameOfTaps.parity);
  return PixelTaps(latticeCoordinate, ivec2(floor(latticeCoordinate)), vec4(0.0), 0.0, 0.0, vec3(1e30), vec3(0.0), 0.0);
}

// Adds the tap at lattice point `point`; one of the bilinear four that lies on the pixel's surface also widens the
// range the temporal filter clamps to.
void addTap(inout PixelTaps taps, Surface surface, ivec2 point, TileSample tileSample, bool bilinear) {
  TileTap tileTapped = tileTap(surface, tileSample);
  vec2 tent = max(vec2(1.0) - abs(vec2(point) - taps.latticeCoordinate), vec2(kOuterTapWeight));
  float weight = tent.x * tent.y * tileTapped.geometry;
  taps.weightedSum += weight * tileTapped.irradiance;
  taps.totalWeight += weight;
  if (bilinear && tileTapped.geometry >= kSameSurfaceWeight) {
    taps.lowest = min(taps.lowest, tileTapped.irradiance.rgb);
    taps.highest = max(taps.highest, tileTapped.irradiance.rgb);
    taps.probeBlend += weight * tileTapped.probeBlend;
    taps.sameSurfaceWeight += weight;
  }
}

TileNeighbourhood tileNeighbourhood(PixelTaps taps) {
  TileNeighbourhood result;
  result.sampled = taps.totalWeight > 0.0;
  result.blended = taps.totalWeight > 0.0 ? taps.weightedSum.rgb / taps.totalWeight : vec3(0.0);
  result.confidence = taps.totalWeight > 0.0 ? taps.weightedSum.a / taps.totalWeight : 0.0;
  result.lowest = taps.lowest;
  result.highest = taps.highest;
  result.probeBlend = taps.sameSurfaceWeight > 0.0 ? taps.probeBlend / taps.sameSurfaceWeight : 1.0;
  return result;
}

// A pixel's bilinear tap at lattice point `point`, where it is one of the pixel's four.
void addBilinearTap(inout PixelTaps taps, Surface surface, ivec2 point, TileSample tileSample) {
  ivec2 offset = point - taps.firstPoint;
  if (all(greaterThanEqual(offset, ivec2(0))) && all(lessThanEqual(offset, ivec2(1))))
    addTap(taps, surface, point, tileSample, true);
}

// The twelve taps around a pixel's four, for a pixel none of whose four is on its surface (a thin object, a
// silhouette): it borrows from its own surface a tile further away instead of going dark.
bool needsOuterTaps(PixelTaps taps, bool drawn) { return drawn && taps.totalWeight == 0.0; }

// The tile samples around the four half-resolution pixels of a 2×2 quad, (0, 0), (1, 0), (0, 1) and (1, 1) from the
// first, whose full-resolution pixel is `firstPixel` (`drawn`: which show a surface). Neighbouring pixels share most
// of their taps: the quad's full-resolution pixels lie half a tile apart, a quarter of a lattice unit along each
// lattice axis, so their bilinear fours lie in one 3×3 block of lattice points, each read once — nine reads where the
// pixels one by one made sixteen. (Four variables, not arrays: lavapipe turns an array indexed in a loop into a
// chain of branches at every access.)
void quadTileNeighbourhoods(Surface surface0, Surface surface1, Surface surface2, Surface surface3, bvec4 drawn,
                            ivec2 firstPixel, TapFrame frameOfTaps, out TileNeighbourhood neighbourhood0,
                            out TileNeighbourhood neighbourhood1, out TileNeighbourhood neighbourhood2,
                            out TileNeighbourhood neighbourhood3) {
  PixelTaps taps0 = pixelTaps(firstPixel, frameOfTaps), taps1 = pixelTaps(firstPixel + ivec2(2, 0), frameOfTaps),
            taps2 = pixelTaps(firstPixel + ivec2(0, 2), frameOfTaps),
            taps3 = pixelTaps(firstPixel + ivec2(2, 2), frameOfTaps);
  // The lattice's u axis grows with x and y, its v axis with x and against y: the block starts at the first point of
  // pixel (0, 0) along u and at that of pixel (0, 1) along v. Each pixel's four come in the order they are summed in,
  // u fastest.
  ivec2 blockOrigin = ivec2(taps0.firstPoint.x, taps2.firstPoint.y);
  for (int v = 0; v < 3; ++v) {
    for (int u = 0; u < 3; ++u) {
      ivec2 point = blockOrigin + ivec2(u, v);
      TileSample tileSample = tileSampleAt(point, frameOfTaps);
      addBilinearTap(taps0, surface0, point, tileSample);
      addBilinearTap(taps1, surface1, point, tileSample);
      addBilinearTap(taps2, surface2, point, tileSample);
      addBilinearTap(taps3, surface3, point, tileSample);
    }
  }
  // The outer taps of every pixel that needs them in one loop: lavapipe runs a loop's body at least once, and for as
  // long as any invocation of a lock-step group is in it.
  bvec4 outer = bvec4(needsOuterTaps(taps0, drawn.x), needsOuterTaps(taps1, drawn.y), needsOuterTaps(taps2, drawn.z),
                      needsOuterTaps(taps3, drawn.w));
  uint outerPixels = uint(outer.x) | (uint(outer.y) << 1u) | (uint(outer.z) << 2u) | (uint(outer.w) << 3u);
  uint outerTaps = uint(bitCount(outerPixels)) * 12u;
  for (uint tap = 0u; tap < outerTaps; ++tap) {
    uint left = outerPixels;
    for (uint before = tap / 12u; before > 0u; --before) left &= left - 1u;
    int k = findLSB(left);
    ivec2 firstPoint =
        k == 0 ? taps0.firstPoint : (k == 1 ? taps1.firstPoint : (k == 2 ? taps2.firstPoint : taps3.firstPoint));
    ivec2 point = firstPoint + kOuterLatticeOffsets[tap % 12u];
    TileSample tileSample = tileSampleAt(point, frameOfTaps);
    if (k == 0) addTap(taps0, surface0, point, tileSample, false);
    if (k == 1) addTap(taps1, surface1, point, tileSample, false);
    if (k == 2) addTap(taps2, surface2, point, tileSample, false);
    if (k == 3) addTap(taps3, surface3, point, tileSample, false);
  }
  neighbourhood0 = tileNeighbourhood(taps0);
  neighbourhood1 = tileNeighbourhood(taps1);
  neighbourhood2 = tileNeighbourhood(taps2);
  neighbourhood3 = tileNeighbourhood(taps3);
}

#endif
