#version 450
// PathTrace: adds a batch of E_indirect samples to each pixel's sum and writes the running results. E_indirect at the
// primary hit is everything but the delta lights' direct light: the sky (sky light reaching the surface directly
// counts as indirect, because in ssvgi it comes through the GI), emissive surfaces and all light reflected on the way.
// One sample is π × the radiance arriving along a cosine-distributed direction (pdf cos θ/π, so the estimate of
// E = ∫ L cos θ dω is π·L), that radiance being found by a path (reference/path_radiance.glsl).
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

// A path from the primary hit along a cosine-distributed direction around its normal.
Path startCosinePath(vec3 origin, vec3 normal, uint random) {
  vec2 square = nextRandom2(random);
  return startPath(origin, cosineSampleHemisphere(square, normal), random);
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
    Path path = startCosinePath(origin.xyz, normal, sampleRandomState(pixelIndex, sampleIndex, push.seed));
    while (true) {
      if (extendPath(path, push.maxBounces)) continue;
      sum += kPi * path.radiance;  // E = π × the radiance along a direction of density cos θ/π
      if (++sampleIndex == sampleEnd) break;
      path = startCosinePath(origin.xyz, normal, sampleRandomState(pixelIndex, sampleIndex, push.seed));
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
