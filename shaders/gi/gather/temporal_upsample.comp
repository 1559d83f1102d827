#version 450
// TemporalUpsample (SPEC §4 steps 11 and 12 in one pass; the talk's "UpSample to 1/2 render resolution, bilateral
// filter with depth and normal weights" and "Temporal Filter on the upsampled result"). Each half-resolution pixel
//   - upsamples: blends the tile samples around it, bilinear in the jittered sample grid, weighted by how well each
//     sample's depth and normal match its own (joint bilateral upsampling, Kopf et al. 2007), and the tiles'
//     confidence (SPEC §6.4) with the same weights: 0 where nothing was drawn or no tile sample lies on the surface;
//   - filters: finds its surface in the last output through the last dispatch's camera, keeps that history where its
//     geometry matches, and blends the upsampled frame in.
// One pass, because the filter's neighbourhood clamp needs the same tile neighbourhood the upsampling has just found:
// as two passes the second recomputed it, and its geometry was most of the filter's cost (PERFORMANCE.md).
// The result is ssvgi's output: rgb E(n), alpha the depth the history test needs next frame.
//
// How much history to keep is the probes' call. Their change detection (probe_trace.comp) tells noise from a change
// of light, which a screen filter cannot: a probe's update moves every tile around it alike, so this frame's tile
// samples agree with each other however far the probes' noise moved them. The tiles carry the weight the probes'
// next updates give new light (GatheredLight::probeBlend). Where it is above kTemporalBlend — the probes are new or
// follow a change — the filter follows as fast, and clamps its history to the range of this frame's tile samples on
// the pixel's surface, fully where the probes start afresh; where the probes are settled, the difference between
// history and this frame is their noise, which the history is there to average, and nothing is clamped.
//
// The confidence is not filtered over time. What E gains from its history is the average of noisy probe estimates and
// of the 16 jittered sample pixels; the confidence is made of the probes' known fractions, which the probes already
// blend over their updates as they blend their SH (probe_interface.h), so it lacks the first noise and varies smoothly
// over a surface, where the second does not matter (near a probe level's boundary, where the gather dithers between
// two levels that know different amounts, it stays noisy). A history would also cost more than SPEC §5 leaves: 8 bits
// cannot hold a 1/16 blend (a change below 8/255 would never move the stored value), and two R16 images would take the
// gather's images from 9.98 MB to 11.5 MB at 1920×1080 (10 allowed).
#include "gather_geometry.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = kBindGatherHistory, rgba16f) readonly uniform image2D history;
layout(binding = kBindGatherOutput, rgba16f) writeonly uniform image2D outputIrradiance;
layout(binding = kBindGatherConfidence, r8) writeonly uniform image2D confidence;

// What the history test reads of the frame's constants beside TapFrame, read once for the quad rather than by each of
// its pixels.
struct HistoryFrame {
  bool usable;           // GatherConstants::historyUsable
  mat4 viewProjection;   // the last dispatch's camera
  mat4 inverseViewProjection;
};

HistoryFrame historyFrame() {
  return HistoryFrame(gather.historyUsable != 0u, gather.historyViewProjection, gather.historyInverseViewProjection);
}

// The history at the surface point, bilinear over the taps whose stored surface lies on the pixel's tangent plane
// (a depth test; a crease fails it as a normal test would). a = 0: no usable history.
vec4 reprojectHistory(Surface surface, HistoryFrame last, TapFrame current) {
  vec4 clip = last.viewProjection * vec4(surface.position, 1.0);
  if (clip.w <= 0.0) return vec4(0.0);
  // Half-resolution texel h holds full-resolution pixel 2h, centred at 2h + 0.5.
  vec2 texelCoordinate = (ssvgiNdcToPixel(clip.xy / clip.w, vec2(current.size)) - 0.5) / 2.0;
  ivec2 firstTexel = ivec2(floor(texelCoordinate));
  vec2 fraction = texelCoordinate - vec2(firstTexel);
  vec3 sum = vec3(0.0);
  float totalWeight = 0.0;
  for (int corner = 0; corner < 4; ++corner) {
    ivec2 offset = ivec2(corner & 1, corner >> 1);
    ivec2 texel = firstTexel + offset;
    if (any(lessThan(texel, ivec2(0))) || any(greaterThanEqual(texel, current.halfSize))) continue;
    vec4 stored = imageLoad(history, texel);
    if (stored.a <= 0.0) continue;
    vec3 storedPosition =
        reconstructPosition(last.inverseViewProjection, vec2(2 * texel), vec2(current.size), stored.a);
    vec2 bilinear = mix(vec2(1.0) - fraction, fraction, vec2(offset));
    float weight = bilinear.x * bilinear.y * planeWeight(surface, storedPosition);
    sum += weight * stored.rgb;
    totalWeight += weight;
  }
  return totalWeight >= kTemporalMinimumHistoryWeight ? vec4(sum / totalWeight, 1.0) : vec4(0.0);
}

// The upsampled frame blended into the surface's history, where it has one.
vec3 filtered(Surface surface, TileNeighbourhood tiles, HistoryFrame last, TapFrame current) {
  if (!last.usable) return tiles.blended;
  vec4 reprojected = reprojectHistory(surface, last, current);
  if (reprojected.a <= 0.0) return tiles.blended;
  vec3 lowest = min(tiles.lowest, tiles.blended), highest = max(tiles.highest, tiles.blended);
  // Where no sample of this frame lies on the surface, the upsampled 0 is not light: the history stays as it is
  // (blend 0, unclamped).
  float blend = tiles.sampled ? max(kTemporalBlend, tiles.probeBlend) : 0.0;
  // 1 where the probes are settled, kTemporalBlend where they start afresh.
  float unclamped = tiles.sampled ? kTemporalBlend / blend : 1.0;
  vec3 kept = mix(clamp(reprojected.rgb, lowest, highest), reprojected.rgb, unclamped);
  return mix(kept, tiles.blended, blend);
}

// The quad's pixel `halfPixel` (drawn: it shows a surface, at `depth`).
void filterPixel(ivec2 halfPixel, bool drawn, float depth, Surface surface, TileNeighbourhood tiles,
                 HistoryFrame last, TapFrame current) {
  if (any(greaterThanEqual(halfPixel, current.halfSize))) return;
  if (!drawn) {  // nothing drawn: no light, no depth for the next frame's history test
    imageStore(outputIrradiance, halfPixel, vec4(0.0));
    imageStore(confidence, halfPixel, vec4(0.0));
    return;
  }
  // Stored as the nearest half float: a conversion that rounds toward zero would sink the running average.
  vec3 irradiance = nearestHalf(finiteHalf(filtered(surface, tiles, last, current)));
  imageStore(outputIrradiance, halfPixel, vec4(irradiance, finiteHalf(depth)));
  imageStore(confidence, halfPixel, vec4(tiles.confidence));
}

// Where the half-resolution pixel's full-resolution pixel shows a surface, its depth; else 0.
float drawnDepth(ivec2 halfPixel, TapFrame current) {
  return all(lessThan(halfPixel, current.halfSize)) ? texelFetch(depthBuffer, 2 * halfPixel, 0).r : 0.0;
}

// The surface at a pixel of the quad. One that shows none, or lies past the image's edge, is never used: it is made
// at a finite depth, from a pixel inside the image.
Surface quadSurface(ivec2 halfPixel, float depth, TapFrame current) {
  return currentSurface(current, min(2 * halfPixel, current.size - 1), depth > 0.0 ? depth : 1.0);
}

// An invocation filters a 2×2 quad of half-resolution pixels: they share most of their tile samples
// (quadTileNeighbourhoods).
void main() {
  TapFrame current = tapFrame();
  HistoryFrame last = historyFrame();
  ivec2 first = 2 * ivec2(gl_GlobalInvocationID.xy);
  vec4 depths = vec4(drawnDepth(first, current), drawnDepth(first + ivec2(1, 0), current),
                     drawnDepth(first + ivec2(0, 1), current), drawnDepth(first + ivec2(1, 1), current));
  bvec4 drawn = greaterThan(depths, vec4(0.0));
  Surface surface0 = quadSurface(first, depths.x, current),
          surface1 = quadSurface(first + ivec2(1, 0), depths.y, current),
          surface2 = quadSurface(first + ivec2(0, 1), depths.z, current),
          surface3 = quadSurface(first + ivec2(1, 1), depths.w, current);
  TileNeighbourhood tiles0, tiles1, tiles2, tiles3;
  quadTileNeighbourhoods(surface0, surface1, surface2, surface3, drawn, 2 * first, current, tiles0, tiles1, tiles2,
                         tiles3);
  filterPixel(first, drawn.x, depths.x, surface0, tiles0, last, current);
  filterPixel(first + ivec2(1, 0), drawn.y, depths.y, surface1, tiles1, last, current);
  filterPixel(first + ivec2(0, 1), drawn.z, depths.z, surface2, tiles2, last, current);
  filterPixel(first + ivec2(1, 1), drawn.w, depths.w, surface3, tiles3, last, current);
}
