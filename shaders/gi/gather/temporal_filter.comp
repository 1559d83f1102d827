#version 450
// TemporalFilter (SPEC §4.6; the talk's "Temporal Filter on the upsampled result"): each half-resolution pixel finds
// its surface in the last output through the last dispatch's camera, keeps that history where its geometry matches
// and blends the upsampled frame in. It filters the output image in place (each pixel reads only its own texel of it);
// the result is ssvgi's output: rgb E(n), alpha the depth the history test needs next frame.
//
// How much history to keep is the probes' call. Their change detection (probe_trace.comp) tells noise from a change
// of light, which a screen filter cannot: a probe's update moves every tile around it alike, so this frame's tile
// samples agree with each other however far the probes' noise moved them. The tiles carry the weight the probes'
// next updates give new light (GatheredLight::probeBlend). Where it is above kTemporalBlend — the probes are new or
// follow a change — the filter follows as fast, and clamps its history to the range of this frame's tile samples on
// the pixel's surface, fully where the probes start afresh; where the probes are settled, the difference between
// history and this frame is their noise, which the history is there to average, and nothing is clamped.
//
// The confidence (SPEC §6.4) is not filtered here; Upsample's is the output. What E gains from its history is the
// average of noisy probe estimates and of the 16 jittered sample pixels; the confidence is made of the probes' known
// fractions, which the probes already blend over their updates as they blend their SH (probe_interface.h), so it lacks
// the first noise and varies smoothly over a surface, where the second does not matter (near a probe level's
// boundary, where the gather dithers between two levels that know different amounts, it stays noisy). A history would
// also cost more than SPEC §5 leaves: 8 bits cannot hold a 1/16 blend (a change below 8/255 would never move the
// stored value), and two R16 images would take the gather's images from 9.98 MB to 11.5 MB at 1920×1080 (10 allowed).
#include "gather_geometry.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = kBindGatherHistory, rgba16f) readonly uniform image2D history;
layout(binding = kBindGatherOutput, rgba16f) uniform image2D outputIrradiance;

// The history at the surface point, bilinear over the taps whose stored surface lies on the pixel's tangent plane
// (a depth test; a crease fails it as a normal test would). a = 0: no usable history.
vec4 reprojectHistory(Surface surface, vec2 size) {
  vec4 clip = gather.historyViewProjection * vec4(surface.position, 1.0);
  if (clip.w <= 0.0) return vec4(0.0);
  // Half-resolution texel h holds full-resolution pixel 2h, centred at 2h + 0.5.
  vec2 texelCoordinate = (ssvgiNdcToPixel(clip.xy / clip.w, size) - 0.5) / 2.0;
  ivec2 firstTexel = ivec2(floor(texelCoordinate));
  vec2 fraction = texelCoordinate - vec2(firstTexel);
  vec3 sum = vec3(0.0);
  float totalWeight = 0.0;
  for (int corner = 0; corner < 4; ++corner) {
    ivec2 offset = ivec2(corner & 1, corner >> 1);
    ivec2 texel = firstTexel + offset;
    if (any(lessThan(texel, ivec2(0))) || any(greaterThanEqual(texel, ivec2(gather.halfSize)))) continue;
    vec4 stored = imageLoad(history, texel);
    if (stored.a <= 0.0) continue;
    vec3 storedPosition = reconstructPosition(gather.historyInverseViewProjection, vec2(2 * texel), size, stored.a);
    vec2 bilinear = mix(vec2(1.0) - fraction, fraction, vec2(offset));
    float weight = bilinear.x * bilinear.y * planeWeight(surface, storedPosition);
    sum += weight * stored.rgb;
    totalWeight += weight;
  }
  return totalWeight >= kTemporalMinimumHistoryWeight ? vec4(sum / totalWeight, 1.0) : vec4(0.0);
}

void main() {
  ivec2 halfPixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(halfPixel, ivec2(gather.halfSize))) || gather.historyUsable == 0u) return;
  ivec2 pixel = 2 * halfPixel;
  float depth = texelFetch(depthBuffer, pixel, 0).r;
  if (depth <= 0.0) return;
  vec4 current = imageLoad(outputIrradiance, halfPixel);  // Upsample's result
  Surface surface = currentSurface(pixel, depth);
  vec4 reprojected = reprojectHistory(surface, vec2(frame.size));
  if (reprojected.a <= 0.0) return;
  TileNeighbourhood neighbourhood = tileNeighbourhood(surface, pixel);
  vec3 lowest = min(neighbourhood.lowest, current.rgb), highest = max(neighbourhood.highest, current.rgb);
  // Where no sample of this frame lies on the surface, Upsample's 0 is not light: the history stays as it is (blend 0,
  // unclamped).
  float blend = neighbourhood.sampled ? max(kTemporalBlend, neighbourhood.probeBlend) : 0.0;
  // 1 where the probes are settled, kTemporalBlend where they start afresh.
  float unclamped = neighbourhood.sampled ? kTemporalBlend / blend : 1.0;
  vec3 history = mix(clamp(reprojected.rgb, lowest, highest), reprojected.rgb, unclamped);
  vec3 filtered = mix(history, current.rgb, blend);
  imageStore(outputIrradiance, halfPixel, vec4(nearestHalf(finiteHalf(filtered)), current.a));
}
