// The reference path tracer's view of the scene, included by its passes: the scene's buffers (with the table of its
// emissive triangles, which reference/path_radiance.glsl samples), BVH traversal, the surface at a hit (two-sided,
// textured, as the G-buffer shades it) and the direct light from the delta lights with shadow rays. Exact visibility
// replaces the renderer's shadow maps; everything else is the renderer's own light model.
#include "shared/path_tracer_interface.h"
#include "shared/renderer_interface.h"

layout(binding = kBindTraceFrame, std140) readonly buffer Frame { FrameConstants frame; };
layout(binding = kBindTraceNodes) readonly buffer Nodes { BvhNode nodes[]; };
layout(binding = kBindTraceTriangles) readonly buffer Triangles { TraceTriangle triangles[]; };
layout(binding = kBindTraceShading) readonly buffer Shading { TriangleShading shading[]; };
layout(binding = kBindTraceMaterials) readonly buffer Materials { GpuMaterial materials[]; };
layout(binding = kBindTraceTextures) readonly buffer Textures { PackedTexture textures[]; };
layout(binding = kBindTraceTexels) readonly buffer Texels { uint texels[]; };
layout(binding = kBindTraceLights) readonly buffer Lights { GpuLight lights[]; };
layout(binding = kBindTraceEmitters) readonly buffer Emitters { EmissiveTriangle emitters[]; };

const float kInfiniteDistance = 3.0e38;
// Whether any of the scene's materials cuts its surfaces out (sceneTracingConstants): a pipeline of its own for a scene
// none of whose do, since lavapipe would run cutOut's reads for every triangle a ray meets, taken or not.
layout(constant_id = 0) const bool kSceneCutsOut = true;

vec3 srgbToLinear(vec3 srgb) {
  return mix(srgb / 12.92, pow((srgb + 0.055) / 1.055, vec3(2.4)), greaterThan(srgb, vec3(0.04045)));
}

// A texel, its colour decoded to linear (its alpha is linear).
vec4 texelColour(PackedTexture image, ivec2 texel) {
  ivec2 size = ivec2(image.width, image.height);
  ivec2 wrapped = ((texel % size) + size) % size;  // repeat, also for negative coordinates
  vec4 packedTexel = unpackUnorm4x8(texels[image.firstTexel + uint(wrapped.y) * image.width + uint(wrapped.x)]);
  return vec4(srgbToLinear(packedTexel.rgb), packedTexel.a);
}

// What the renderer's sampler returns for an sRGB texture: texels decoded to linear first, then filtered bilinearly
// with repeat addressing (the scene textures have a single mip level).
vec4 sampleTexture(uint textureIndex, vec2 uv) {
  PackedTexture image = textures[textureIndex];
  vec2 position = uv * vec2(image.width, image.height) - 0.5;
  vec2 cell = floor(position);
  vec2 weight = position - cell;
  ivec2 texel = ivec2(cell);
  vec4 top = mix(texelColour(image, texel), texelColour(image, texel + ivec2(1, 0)), weight.x);
  vec4 bottom = mix(texelColour(image, texel + ivec2(0, 1)), texelColour(image, texel + ivec2(1, 1)), weight.x);
  return mix(top, bottom, weight.y);
}

// The texture coordinates of a point of a triangle, at barycentric weights of its three vertices.
vec2 triangleTexcoord(TriangleShading attributes, vec3 weights) {
  return weights.x * vec2(attributes.normal0AndU0.w, attributes.texcoordVAndMaterial.x) +
         weights.y * vec2(attributes.normal1AndU1.w, attributes.texcoordVAndMaterial.y) +
         weights.z * vec2(attributes.normal2AndU2.w, attributes.texcoordVAndMaterial.z);
}

// Whether the point of a triangle at barycentric weights of its three vertices is cut out of its surface, as the
// G-buffer leaves it out: the alpha of its texture (1 without one) below Material::alphaCutoff. TraceTriangle::cutsOut
// tells which triangles to ask.
bool cutOut(uint triangle, vec3 weights) {
  TriangleShading attributes = shading[triangle];
  GpuMaterial material = materials[floatBitsToUint(attributes.texcoordVAndMaterial.w)];
  float alpha = material.baseColorTexture != kNoTexture
                    ? sampleTexture(material.baseColorTexture, triangleTexcoord(attributes, weights)).a
                    : 1.0;
  return alpha < material.alphaCutoff;
}

struct RayHit {
  float distance;      // along the (unit) ray direction
  uint triangle;
  vec2 barycentrics;   // weights of vertices 1 and 2
};

// Nearest hit in (0, maxDistance), or with `anyHit` the first one found (shadow rays only ask whether there is one).
// Stack-based traversal of the flat BVH, nearer child first, so that a near hit prunes the far subtrees early.
bool traceRay(vec3 origin, vec3 direction, float maxDistance, bool anyHit, out RayHit hit) {
  hit.distance = maxDistance;
  hit.triangle = 0u;
  hit.barycentrics = vec2(0.0);
  bool found = false;
  vec3 inverseDirection = safeInverseDirection(direction);
  vec2 rootSpan = intersectBounds(origin, inverseDirection, nodes[0].boundsMinAndFirst.xyz,
                                  nodes[0].boundsMaxAndCount.xyz);
  if (rootSpan.x > rootSpan.y || rootSpan.y < 0.0 || rootSpan.x >= maxDistance) return false;

  // The subtrees still to visit, with the distance at which the ray enters each: a subtree is skipped without
  // reloading its node when a hit nearer than that has been found since it was pushed.
  uint stackNodes[kBvhMaxDepth];
  float stackEntries[kBvhMaxDepth];
  uint stackSize = 0u;
  BvhNode current = nodes[0];
  while (true) {
    // Descend through inner nodes until a leaf is reached or no child is entered; a separate loop (Aila & Laine,
    // "Understanding the Efficiency of Ray Traversal on GPUs", 2009) keeps lanes that are still descending together
    // instead of alternating between inner-node and leaf work.
    uint count = floatBitsToUint(current.boundsMaxAndCount.w);
    while (count == 0u) {
      uint first = floatBitsToUint(current.boundsMinAndFirst.w);
      BvhNode left = nodes[first];
      BvhNode right = nodes[first + 1u];
      vec2 leftSpan = intersectBounds(origin, inverseDirection, left.boundsMinAndFirst.xyz, left.boundsMaxAndCount.xyz);
      vec2 rightSpan =
          intersectBounds(origin, inverseDirection, right.boundsMinAndFirst.xyz, right.boundsMaxAndCount.xyz);
      bool enterLeft = leftSpan.x <= leftSpan.y && leftSpan.y >= 0.0 && leftSpan.x < hit.distance;
      bool enterRight = rightSpan.x <= rightSpan.y && rightSpan.y >= 0.0 && rightSpan.x < hit.distance;
      if (!enterLeft && !enterRight) break;
      // Into the nearer child entered, keeping its node (already loaded); the other waits on the stack if entered.
      bool leftFirst = enterLeft && (!enterRight || leftSpan.x <= rightSpan.x);
      if (enterLeft && enterRight) {
        stackNodes[stackSize] = leftFirst ? first + 1u : first;
        stackEntries[stackSize] = leftFirst ? rightSpan.x : leftSpan.x;
        ++stackSize;
      }
      current = leftFirst ? left : right;
      count = floatBitsToUint(current.boundsMaxAndCount.w);
    }
    uint first = floatBitsToUint(current.boundsMinAndFirst.w);
    for (uint i = first; i < first + count; ++i) {
      TraceTriangle triangle = triangles[i];
      vec3 tuv = intersectTriangle(origin, direction, triangle.vertex0, triangle.edge1, triangle.edge2);
      // A cut-out point is looked up only for a hit nearer than the one found.
      if (tuv.x > 0.0 && tuv.x < hit.distance &&
          !(kSceneCutsOut && triangle.cutsOut != 0u && cutOut(i, vec3(1.0 - tuv.y - tuv.z, tuv.yz)))) {
        hit.distance = tuv.x;
        hit.triangle = i;
        hit.barycentrics = tuv.yz;
        found = true;
        if (anyHit) return true;
      }
    }
    // Pop the next subtree that may still hold a nearer hit than the one found so far.
    bool next = false;
    while (stackSize > 0u && !next) {
      --stackSize;
      next = stackEntries[stackSize] < hit.distance;
    }
    if (!next) return found;
    current = nodes[stackNodes[stackSize]];
  }
}

bool traceNearest(vec3 origin, vec3 direction, out RayHit hit) {
  return traceRay(origin, direction, kInfiniteDistance, false, hit);
}

bool occluded(vec3 origin, vec3 direction, float maxDistance) {
  RayHit hit;
  return traceRay(origin, direction, maxDistance, true, hit);
}

// A secondary ray's origin: the surface point moved off the surface, to the side the ray leaves from, so that it does
// not hit its own triangle again through rounding. The offset grows with the coordinates' magnitude (their ulp).
vec3 offsetRayOrigin(vec3 position, vec3 geometricNormal) {
  vec3 magnitude = abs(position);
  return position + geometricNormal * (1e-4 * max(1.0, max(max(magnitude.x, magnitude.y), magnitude.z)));
}

struct Surface {
  vec3 position;
  vec3 geometricNormal;  // both normals face the side the ray came from (two-sided surfaces)
  vec3 normal;           // shading normal: interpolated vertex normals
  vec3 albedo;
  vec3 emission;         // emitted radiance
  // The luminance the emitter table weighs the triangle's power by: its material's emission without the texture.
  float emitterLuminance;
};

Surface surfaceAt(vec3 direction, RayHit hit) {
  TraceTriangle triangle = triangles[hit.triangle];
  TriangleShading attributes = shading[hit.triangle];
  vec3 weights = vec3(1.0 - hit.barycentrics.x - hit.barycentrics.y, hit.barycentrics);
  Surface surface;
  // On the triangle's plane exactly, rather than origin + t·direction, which rounding can put on either side.
  surface.position = triangle.vertex0 + hit.barycentrics.x * triangle.edge1 + hit.barycentrics.y * triangle.edge2;
  surface.geometricNormal = normalize(cross(triangle.edge1, triangle.edge2));
  surface.normal = normalize(weights.x * attributes.normal0AndU0.xyz + weights.y * attributes.normal1AndU1.xyz +
                             weights.z * attributes.normal2AndU2.xyz);
  // A counter-clockwise triangle faces the ray when its geometric normal opposes it; otherwise it is seen from behind
  // and, like the G-buffer's !gl_FrontFacing case, shades with the flipped normal.
  if (dot(surface.geometricNormal, direction) > 0.0) {
    surface.geometricNormal = -surface.geometricNormal;
    surface.normal = -surface.normal;
  }
  GpuMaterial material = materials[floatBitsToUint(attributes.texcoordVAndMaterial.w)];
  vec2 uv = triangleTexcoord(attributes, weights);
  surface.albedo = material.baseColor *
                   (weights.x * attributes.color0 + weights.y * attributes.color1 + weights.z * attributes.color2);
  if (material.baseColorTexture != kNoTexture) surface.albedo *= sampleTexture(material.baseColorTexture, uv).rgb;
  surface.emission = material.emission;
  if (material.emissionTexture != kNoTexture) surface.emission *= sampleTexture(material.emissionTexture, uv).rgb;
  surface.emitterLuminance = emissionLuminance(material.emission);
  return surface;
}

// Irradiance from the sun and the local lights at a surface point, each times its visibility by a shadow ray from
// `shadowOrigin` (exact hard shadows): the renderer's DirectLighting with ray-traced visibility.
vec3 directIrradiance(vec3 position, vec3 normal, vec3 shadowOrigin) {
  vec3 irradiance = vec3(0.0);
  if (frame.sunDirectionAndEnabled.w > 0.0) {
    vec3 toSun = frame.sunDirectionAndEnabled.xyz;
    float cosine = dot(normal, toSun);
    if (cosine > 0.0 && !occluded(shadowOrigin, toSun, kInfiniteDistance)) irradiance += frame.sunIlluminance * cosine;
  }
  uint lightCount = frame.localLightCount;
  for (uint i = 0u; i < lightCount; ++i) {
    GpuLight light = lights[i];
    vec3 toLight = light.positionAndType.xyz - position;
    float distanceSquared = dot(toLight, toLight);
    vec3 direction = toLight * inversesqrt(distanceSquared);
    float cosine = dot(normal, direction);
    if (cosine <= 0.0) continue;
    vec3 scale = localLightIrradianceScale(light, direction, distanceSquared);
    if (all(equal(scale, vec3(0.0)))) continue;  // outside the spot cone or the range: no shadow ray needed
    if (floatBitsToUint(light.intensityAndShadow.w) != kNoShadow) {
      vec3 shadowRay = light.positionAndType.xyz - shadowOrigin;
      float shadowDistance = length(shadowRay);
      if (occluded(shadowOrigin, shadowRay / shadowDistance, shadowDistance)) continue;
    }
    irradiance += scale * cosine;
  }
  return irradiance;
}
