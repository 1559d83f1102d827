// The radiance arriving at a point along one direction, found by a path: the part of the reference path tracer that
// PathTrace (E_indirect at each pixel's primary hit) and PointRadiance (radiance over the sphere at free points) share.
// Lambertian cosine sampling at every vertex, next-event estimation (NEE) to the delta lights and, unless it is off, to
// the emissive triangles, the sky where the path escapes. Where a vertex samples the emitters, the light they send it
// is found by two techniques, NEE and the cosine-sampled direction that hits an emitter, and the two are combined by
// multiple importance sampling with the power heuristic (Veach 1997, ch. 9): each counts the emission with its weight,
// the weights of any one point on an emitter summing to 1. NEE alone has unbounded variance where an emitter touches
// another surface (its estimate goes as 1/d² there), paths alone where the emitters are small; the weights hand each
// region to the technique that samples it well. Where the vertex did not sample the emitters (the free point
// PointRadiance starts from, or emitter sampling off) the hit counts the emission it finds fully.
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

// The density, in solid angle at a path vertex, with which emitterIrradiance chooses a point of luminance Y (its
// emission's emissionLuminance) seen at distance² d² under the emitter cosine |cos θ_e|: the table chooses a triangle
// with probability area·Y/emittedPower and then a uniform point on it, Y/emittedPower per m², and dA = d²/|cos θ_e| dω.
float emitterPointDensity(float luminance, float distanceSquared, float emitterCosine, float emittedPower) {
  return luminance * distanceSquared / (emittedPower * emitterCosine);
}

// The density with which a vertex of shading normal `normal` chooses its next direction: cos θ/π (Lambert, cosine
// sampling), 0 below the horizon.
float cosineDirectionDensity(vec3 normal, vec3 direction) { return max(dot(normal, direction), 0.0) * (1.0 / kPi); }

// Irradiance from the emissive triangles at a surface point facing `normal`, estimated from one point on them
// (next-event estimation) and weighted for multiple importance sampling against the cosine-sampled direction the
// vertex goes on with: a triangle chosen by power, a uniform point y on it (the square-root mapping, Shirley 1990:
// barycentrics 1 − √u₁, √u₁(1 − u₂), √u₁·u₂), and a shadow ray from `shadowOrigin`. With the point's density
// selectionProbability / area, Le · cos θ · |cos θ_e| / d² over that density estimates E = ∫ Le cos θ cos θ_e / d² dA
// without bias; the power heuristic's weight then leaves the part the cosine-sampled ray finds to it. |cos θ_e|:
// emission is two-sided, as surfaceAt shades it.
vec3 emitterIrradiance(vec3 position, vec3 normal, vec3 shadowOrigin, uint emitterCount, float emittedPower,
                       inout uint random) {
  EmissiveTriangle emitter = emitters[selectEmitter(nextRandom(random), emitterCount)];
  TraceTriangle triangle = triangles[emitter.triangle];
  vec2 square = nextRandom2(random);
  float root = sqrt(square.x);
  vec3 weights = vec3(1.0 - root, root * (1.0 - square.y), root * square.y);
  // A point its material's texture cuts out is no emitter (a path never hits it either).
  if (kSceneCutsOut && triangle.cutsOut != 0u && cutOut(emitter.triangle, weights)) return vec3(0.0);
  vec3 point = triangle.vertex0 + weights.y * triangle.edge1 + weights.z * triangle.edge2;
  vec3 toEmitter = point - position;
  float distanceSquared = dot(toEmitter, toEmitter);
  vec3 direction = toEmitter * inversesqrt(distanceSquared);
  float cosine = dot(normal, direction);
  vec3 doubleAreaNormal = cross(triangle.edge1, triangle.edge2);
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
  TriangleShading attributes = shading[emitter.triangle];
  GpuMaterial material = materials[floatBitsToUint(attributes.texcoordVAndMaterial.w)];
  vec3 emission = material.emission;
  if (material.emissionTexture != kNoTexture)
    emission *= sampleTexture(material.emissionTexture, triangleTexcoord(attributes, weights)).rgb;
  // The two densities of y as the vertex's cosine-sampled ray would meet it: from the ray origin (`shadowOrigin`),
  // which extendPath uses for the point it hits, so that the two weights of one point sum to 1.
  vec3 fromOrigin = point - shadowOrigin;
  float originDistanceSquared = dot(fromOrigin, fromOrigin);
  vec3 originDirection = fromOrigin * inversesqrt(originDistanceSquared);
  float weight = powerHeuristic(
      emitterPointDensity(emissionLuminance(material.emission), originDistanceSquared,
                          abs(dot(emitterNormal, originDirection)), emittedPower),
      cosineDirectionDensity(normal, originDirection));
  float area = 0.5 * doubleArea;
  return emission * (weight * cosine * emitterCosine * area / (distanceSquared * emitter.selectionProbability));
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
  // Whether the point this segment starts from sampled the emitters (NEE): then the emission of the next hit counts
  // with its multiple importance sampling weight, else fully.
  bool originSampledEmitters;
  float directionDensity;  // of `direction` at that point (cos θ/π), when it sampled the emitters
};

Path startPath(vec3 origin, vec3 direction, bool originSampledEmitters, float directionDensity, uint random) {
  Path path;
  path.random = random;
  path.vertex = 1u;
  path.origin = origin;
  path.direction = direction;
  path.throughput = vec3(1.0);
  path.radiance = vec3(0.0);
  path.originSampledEmitters = originSampledEmitters;
  path.directionDensity = directionDensity;
  return path;
}

// Traces the path's next segment and adds what it finds; false when the path has ended. Light reflected more than
// `maxBounces` times on its way to the point is left out: NEE at vertex k (k ≤ maxBounces) and the emission hit at
// vertex k + 1 both carry light reflected k times, so the two techniques of every MIS pair are kept or left out
// together. With `emitterCount` > 0 every vertex samples the emitters (emittedPower: the push constants').
bool extendPath(inout Path path, uint maxBounces, uint emitterCount, float emittedPower) {
  RayHit hit;
  if (!traceNearest(path.origin, path.direction, hit)) {
    path.radiance += path.throughput * evaluateSky(frame.sky, path.direction);
    return false;
  }
  Surface surface = surfaceAt(path.direction, hit);
  if (!path.originSampledEmitters) {
    path.radiance += path.throughput * surface.emission;
  } else if (any(greaterThan(surface.emission, vec3(0.0)))) {
    // The emission NEE could have sampled from the segment's origin: the cosine-sampled share of the power heuristic.
    float lightDensity = emitterPointDensity(surface.emitterLuminance, hit.distance * hit.distance,
                                             abs(dot(surface.geometricNormal, path.direction)), emittedPower);
    path.radiance += path.throughput * surface.emission * powerHeuristic(path.directionDensity, lightDensity);
  }
  if (path.vertex > maxBounces) return false;
  // Lambert with cosine sampling: BRDF × cos / pdf = albedo/π × cos / (cos/π) = albedo.
  path.throughput *= surface.albedo;
  path.origin = offsetRayOrigin(surface.position, surface.geometricNormal);
  vec3 irradiance = directIrradiance(surface.position, surface.normal, path.origin);
  if (emitterCount > 0u) {
    irradiance +=
        emitterIrradiance(surface.position, surface.normal, path.origin, emitterCount, emittedPower, path.random);
  }
  path.radiance += path.throughput * (1.0 / kPi) * irradiance;
  if (path.vertex >= kRouletteFirstVertex) {
    float survival = min(max(max(path.throughput.r, path.throughput.g), path.throughput.b), kMaxSurvival);
    if (nextRandom(path.random) >= survival) return false;
    path.throughput /= survival;
  }
  path.direction = cosineSampleHemisphere(nextRandom2(path.random), surface.normal);
  path.originSampledEmitters = emitterCount > 0u;
  path.directionDensity = cosineDirectionDensity(surface.normal, path.direction);
  ++path.vertex;
  return true;
}
