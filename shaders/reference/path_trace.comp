#version 450
// PathTrace: adds a batch of E_indirect samples to each pixel's sum and writes the running results. E_indirect at the
// primary hit is everything but the delta lights' direct light: the sky (sky light reaching the surface directly
// counts as indirect, because in ssvgi it comes through the GI), emissive surfaces and all light reflected on the way.
// One sample is π × the radiance arriving along a cosine-distributed direction (pdf cos θ/π, so the estimate of
// E = ∫ L cos θ dω is π·L), that radiance being found by a path: Lambertian cosine sampling at every vertex, next-event
// estimation to the delta lights, emission picked up where the path hits it. Emissive surfaces are found only by the
// paths themselves (there is no area-light sampling), so no multiple importance sampling is needed.
#include "reference/scene_tracing.glsl"

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

// Russian roulette from this path vertex on: a path continues with probability equal to its throughput (at most
// kMaxSurvival), and its throughput is divided by that probability, which keeps the estimate unbiased.
const uint kRouletteFirstVertex = 4u;
const float kMaxSurvival = 0.95;

vec2 nextRandom2(inout uint state) {
  float first = nextRandom(state);
  return vec2(first, nextRandom(state));
}

// One path in flight: it starts at the primary hit along a cosine-distributed direction, and its vertex k is the
// k-th surface after the primary hit. Light emitted at vertex k, or arriving from the sky past it, has been reflected
// k - 1 times on its way; delta light reflected there, k times.
struct Path {
  uint random;
  uint vertex;
  vec3 origin;
  vec3 direction;
  vec3 throughput;
  vec3 radiance;  // arriving at the primary hit along the first direction, so far
};

Path startPath(vec3 origin, vec3 normal, uint random) {
  Path path;
  path.random = random;
  path.vertex = 1u;
  path.origin = origin;
  path.direction = cosineSampleHemisphere(nextRandom2(path.random), normal);
  path.throughput = vec3(1.0);
  path.radiance = vec3(0.0);
  return path;
}

// Traces the path's next segment and adds what it finds; false when the path has ended.
bool extendPath(inout Path path) {
  RayHit hit;
  if (!traceNearest(path.origin, path.direction, hit)) {
    path.radiance += path.throughput * evaluateSky(frame.sky, path.direction);
    return false;
  }
  Surface surface = surfaceAt(path.direction, hit);
  path.radiance += path.throughput * surface.emission;
  if (path.vertex > push.maxBounces) return false;
  // Lambert with cosine sampling: BRDF × cos / pdf = albedo/π × cos / (cos/π) = albedo.
  path.throughput *= surface.albedo;
  path.origin = offsetRayOrigin(surface.position, surface.geometricNormal);
  path.radiance += path.throughput * (1.0 / kPi) * directIrradiance(surface.position, surface.normal, path.origin);
  if (path.vertex >= kRouletteFirstVertex) {
    float survival = min(max(max(path.throughput.r, path.throughput.g), path.throughput.b), kMaxSurvival);
    if (nextRandom(path.random) >= survival) return false;
    path.throughput /= survival;
  }
  path.direction = cosineSampleHemisphere(nextRandom2(path.random), surface.normal);
  ++path.vertex;
  return true;
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
    Path path = startPath(origin.xyz, normal, sampleRandomState(pixelIndex, sampleIndex, push.seed));
    while (true) {
      if (extendPath(path)) continue;
      sum += kPi * path.radiance;  // E = π × the radiance along a direction of density cos θ/π
      if (++sampleIndex == sampleEnd) break;
      path = startPath(origin.xyz, normal, sampleRandomState(pixelIndex, sampleIndex, push.seed));
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
