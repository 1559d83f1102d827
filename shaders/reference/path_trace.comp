#version 450
// PathTrace: adds a batch of E_indirect samples to each pixel's sum and writes the running results. E_indirect at the
// primary hit is everything but the delta lights' direct light: the sky (sky light reaching the surface directly
// counts as indirect, because in ssvgi it comes through the GI), emissive surfaces and all light reflected on the way.
// One sample is the emitters' irradiance estimated from one point on them (next-event estimation at the primary hit,
// reference/path_radiance.glsl) plus π × the radiance arriving along a cosine-distributed direction (pdf cos θ/π, so
// the estimate of E = ∫ L cos θ dω is π·L), that radiance being found by a path. The emitters seen directly from the
// primary hit are thus found twice, and the two are weighted by multiple importance sampling (the power heuristic),
// as at every later vertex. With emitter sampling off, the path alone finds the emitters, as everything else.
#include "reference/path_radiance.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(push_constant) uniform Push { PathTracePush push; };

layout(binding = kBindPrimaryRayOrigin, rgba32f) readonly uniform image2D rayOrigins;
layout(binding = kBindPrimaryNormal, rgba32f) readonly uniform image2D normals;
layout(binding = kBindPrimaryAlbedo, rgba32f) readonly uniform image2D albedos;
layout(binding = kBindPrimaryRadiance, rgba32f) readonly uniform image2D primaryRadiance;
layout(binding = kBindPrimaryDirect, rgba32f) readonly uniform image2D directIrradiances;
layout(binding = kBindTraceIndirectSum, rgba32f) uniform image2D indirectSums;
layout(binding = kBindTraceIndirect, rgba32f) writeonly uniform image2D indirectIrradiances;
layout(binding = kBindTraceFinal, rgba32f) writeonly uniform image2D finalRadiance;

// One E_indirect sample in flight: the emitters' light reaching the primary hit directly, estimated at the start, and
// the path that finds the rest.
struct IndirectSample {
  vec3 emitterIrradiance;
  Path path;
};

// A sample at the primary hit: NEE of the emitters there (from its ray origin, which stands in for the surface point:
// 10⁻⁴ m off it, more for coordinates beyond 1 m), then a path along a cosine-distributed direction around its normal.
IndirectSample startSample(vec3 origin, vec3 normal, uint random) {
  IndirectSample indirectSample;
  bool sampleEmitters = push.emitterCount > 0u;
  indirectSample.emitterIrradiance =
      sampleEmitters ? emitterIrradiance(origin, normal, origin, push.emitterCount, push.emittedPower, random)
                     : vec3(0.0);
  vec3 direction = cosineSampleHemisphere(nextRandom2(random), normal);
  indirectSample.path =
      startPath(origin, direction, sampleEmitters, cosineDirectionDensity(normal, direction), random);
  return indirectSample;
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, ivec2(frame.viewportSize.xy)))) return;

  vec4 origin = imageLoad(rayOrigins, pixel);
  vec3 indirect = vec3(0.0);
  if (origin.w > 0.0) {
    vec3 normal = imageLoad(normals, pixel).xyz;
    uint pixelIndex = uint(pixel.y) * uint(frame.viewportSize.x) + uint(pixel.x);
    // One loop iteration per path segment rather than per path: invocations run in lockstep groups (SIMD lanes on
    // a CPU, warps on a GPU) and path lengths vary, so a lane whose path ends starts its next sample at once instead
    // of idling until the longest path of its group is done. Sums are still added in sample order, one sample at a
    // time, so they are bit-identical whatever the batches were.
    vec3 sum = imageLoad(indirectSums, pixel).rgb;
    uint sampleIndex = push.firstSample;
    uint sampleEnd = push.firstSample + push.sampleCount;
    IndirectSample current = startSample(origin.xyz, normal, sampleRandomState(pixelIndex, sampleIndex, push.seed));
    while (true) {
      if (extendPath(current.path, push.maxBounces, push.emitterCount, push.emittedPower)) continue;
      // E = π × the radiance along a direction of density cos θ/π, and what NEE found at the primary hit.
      sum += current.emitterIrradiance + kPi * current.path.radiance;
      if (++sampleIndex == sampleEnd) break;
      current = startSample(origin.xyz, normal, sampleRandomState(pixelIndex, sampleIndex, push.seed));
    }
    imageStore(indirectSums, pixel, vec4(sum, 0.0));
    indirect = sum / float(push.firstSample + push.sampleCount);
  }
  // The renderer's composite (SPEC §3): final = emission + albedo/π · (E_direct + E_indirect); where the primary ray
  // escaped, albedo is 0 and the primary radiance is the sky's.
  vec3 irradiance = imageLoad(directIrradiances, pixel).rgb + indirect;
  vec3 radiance = imageLoad(primaryRadiance, pixel).rgb + imageLoad(albedos, pixel).rgb * (1.0 / kPi) * irradiance;
  imageStore(indirectIrradiances, pixel, vec4(indirect, 1.0));
  imageStore(finalRadiance, pixel, vec4(radiance, 1.0));
}
