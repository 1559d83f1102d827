// The radiance arriving at a point along one direction, found by a path: the part of the reference path tracer that
// PathTrace (E_indirect at each pixel's primary hit) and PointRadiance (radiance over the sphere at free points) share.
// Lambertian cosine sampling at every vertex, next-event estimation (NEE) to the delta lights and, unless it is off, to
// the emissive triangles, the sky where the path escapes. Emission is counted one way only at each vertex, never both
// (so no multiple importance sampling is needed): where the vertex before sampled the emitters, their light has been
// counted there and a hit adds none; where it did not (the free point PointRadiance starts from, or with emitter
// sampling off), the hit adds the emission it finds.
#include "reference/scene_tracing.glsl"

// Russian roulette from this path vertex on: a path continues with probability equal to its throughput (at most
// kMaxSurvival), and its throughput is divided by that probability, which keeps the estimate unbiased.
const uint kRouletteFirstVertex = 4u;
const float kMaxSurvival = 0.95;

vec2 nextRandom2(inout uint state) {
  float first = nextRandom(state);
  return vec2(first, nextRandom(state));
}

// The table entry a uniform number in [0, 1) selects: the first whose cumulative probability exceeds it, so entry i
// is chosen with its selectionProbability. The last entry's cumulative probability is exactly 1.
uint selectEmitter(float uniformNumber, uint emitterCount) {
  uint low = 0u;
  uint high = emitterCount - 1u;
  while (low < high) {
    uint middle = (low + high) / 2u;
    if (emitters[middle].cumulativeProbability > uniformNumber) {
      high = middle;
    } else {
      low = middle + 1u;
    }
  }
  return low;
}

// Irradiance from the emissive triangles at a surface point facing `normal`, estimated from one point on them
// (next-event estimation): a triangle chosen by power, a uniform point y on it (the square-root mapping, Shirley 1990:
// barycentrics 1 − √u₁, √u₁(1 − u₂), √u₁·u₂), and a shadow ray from `shadowOrigin`. With the point's density
// selectionProbability / area, Le · cos θ · |cos θ_e| / d² over that density estimates E = ∫ Le cos θ cos θ_e / d² dA
// without bias. |cos θ_e|: emission is two-sided, as surfaceAt shades it.
vec3 emitterIrradiance(vec3 position, vec3 normal, vec3 shadowOrigin, uint emitterCount, inout uint random) {
  EmissiveTriangle emitter = emitters[selectEmitter(nextRandom(random), emitterCount)];
  TraceTriangle triangle = triangles[emitter.triangle];
  vec2 square = nextRandom2(random);
  float root = sqrt(square.x);
  vec3 point = triangle.vertex0.xyz + root * (1.0 - square.y) * triangle.edge1.xyz + root * square.y * triangle.edge2.xyz;
  vec3 toEmitter = point - position;
  float distanceSquared = dot(toEmitter, toEmitter);
  vec3 direction = toEmitter * inversesqrt(distanceSquared);
  float cosine = dot(normal, direction);
  vec3 doubleAreaNormal = cross(triangle.edge1.xyz, triangle.edge2.xyz);
  float doubleArea = length(doubleAreaNormal);
  vec3 emitterNormal = doubleAreaNormal / doubleArea;
  float emitterCosine = abs(dot(emitterNormal, direction));
  if (cosine <= 0.0 || emitterCosine <= 0.0) return vec3(0.0);
  // The shadow ray ends just off the emitter on the side it is seen from (as a ray origin is moved off its surface),
  // so that the emitter itself, or its neighbour across a shared edge, does not occlude it through rounding.
  vec3 shadowEnd = offsetRayOrigin(point, dot(emitterNormal, direction) > 0.0 ? -emitterNormal : emitterNormal);
  vec3 shadowRay = shadowEnd - shadowOrigin;
  float shadowDistance = length(shadowRay);
  if (occluded(shadowOrigin, shadowRay / shadowDistance, shadowDistance)) return vec3(0.0);
  vec3 emission = materials[floatBitsToUint(shading[emitter.triangle].texcoordVAndMaterial.w)].emission.rgb;
  float area = 0.5 * doubleArea;
  return emission * (cosine * emitterCosine * area / (distanceSquared * emitter.selectionProbability));
}

// One path in flight: it leaves the point where radiance is wanted (a primary hit, a probe) along `direction`, and its
// vertex k is the k-th surface after that point. Light emitted at vertex k, or arriving from the sky past it, has been
// reflected k - 1 times on its way; delta light, and emitted light sampled by NEE, reflected there, k times.
struct Path {
  uint random;
  uint vertex;
  vec3 origin;
  vec3 direction;
  vec3 throughput;
  vec3 radiance;  // arriving at the point along the first direction, so far
  // Whether the emission of the next hit is added: false when the emitters' light arriving along this segment has
  // already been estimated by NEE from where it starts.
  bool countsHitEmission;
};

Path startPath(vec3 origin, vec3 direction, bool countsHitEmission, uint random) {
  Path path;
  path.random = random;
  path.vertex = 1u;
  path.origin = origin;
  path.direction = direction;
  path.throughput = vec3(1.0);
  path.radiance = vec3(0.0);
  path.countsHitEmission = countsHitEmission;
  return path;
}

// Traces the path's next segment and adds what it finds; false when the path has ended. Light reflected more than
// `maxBounces` times on its way to the point is left out. With `emitterCount` > 0 every vertex samples the emitters.
bool extendPath(inout Path path, uint maxBounces, uint emitterCount) {
  RayHit hit;
  if (!traceNearest(path.origin, path.direction, hit)) {
    path.radiance += path.throughput * evaluateSky(frame.sky, path.direction);
    return false;
  }
  Surface surface = surfaceAt(path.direction, hit);
  if (path.countsHitEmission) path.radiance += path.throughput * surface.emission;
  if (path.vertex > maxBounces) return false;
  // Lambert with cosine sampling: BRDF × cos / pdf = albedo/π × cos / (cos/π) = albedo.
  path.throughput *= surface.albedo;
  path.origin = offsetRayOrigin(surface.position, surface.geometricNormal);
  vec3 irradiance = directIrradiance(surface.position, surface.normal, path.origin);
  if (emitterCount > 0u) {
    irradiance += emitterIrradiance(surface.position, surface.normal, path.origin, emitterCount, path.random);
  }
  path.radiance += path.throughput * (1.0 / kPi) * irradiance;
  path.countsHitEmission = emitterCount == 0u;
  if (path.vertex >= kRouletteFirstVertex) {
    float survival = min(max(max(path.throughput.r, path.throughput.g), path.throughput.b), kMaxSurvival);
    if (nextRandom(path.random) >= survival) return false;
    path.throughput /= survival;
  }
  path.direction = cosineSampleHemisphere(nextRandom2(path.random), surface.normal);
  ++path.vertex;
  return true;
}
