// The radiance arriving at a point along one direction, found by a path: the part of the reference path tracer that
// PathTrace (E_indirect at each pixel's primary hit) and PointRadiance (radiance over the sphere at free points) share.
// Lambertian cosine sampling at every vertex, next-event estimation to the delta lights, emission picked up where the
// path hits it, the sky where it escapes. Emissive surfaces are found only by the paths themselves (there is no
// area-light sampling), so no multiple importance sampling is needed.
#include "reference/scene_tracing.glsl"

// Russian roulette from this path vertex on: a path continues with probability equal to its throughput (at most
// kMaxSurvival), and its throughput is divided by that probability, which keeps the estimate unbiased.
const uint kRouletteFirstVertex = 4u;
const float kMaxSurvival = 0.95;

vec2 nextRandom2(inout uint state) {
  float first = nextRandom(state);
  return vec2(first, nextRandom(state));
}

// One path in flight: it leaves the point where radiance is wanted (a primary hit, a probe) along `direction`, and its
// vertex k is the k-th surface after that point. Light emitted at vertex k, or arriving from the sky past it, has been
// reflected k - 1 times on its way; delta light reflected there, k times.
struct Path {
  uint random;
  uint vertex;
  vec3 origin;
  vec3 direction;
  vec3 throughput;
  vec3 radiance;  // arriving at the point along the first direction, so far
};

Path startPath(vec3 origin, vec3 direction, uint random) {
  Path path;
  path.random = random;
  path.vertex = 1u;
  path.origin = origin;
  path.direction = direction;
  path.throughput = vec3(1.0);
  path.radiance = vec3(0.0);
  return path;
}

// Traces the path's next segment and adds what it finds; false when the path has ended. Light reflected more than
// `maxBounces` times on its way to the point is left out.
bool extendPath(inout Path path, uint maxBounces) {
  RayHit hit;
  if (!traceNearest(path.origin, path.direction, hit)) {
    path.radiance += path.throughput * evaluateSky(frame.sky, path.direction);
    return false;
  }
  Surface surface = surfaceAt(path.direction, hit);
  path.radiance += path.throughput * surface.emission;
  if (path.vertex > maxBounces) return false;
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
