// GPU structs, binding slots and small functions of the reference path tracer (reference/, shaders/reference/),
// shared by its shaders, its BVH builder and the CPU tests, so that the layouts, the ray tests and the sampling are
// written once. The scene's materials and lights use the renderer's own GpuMaterial and GpuLight.
#ifndef SSVGI_SHARED_PATH_TRACER_INTERFACE_H
#define SSVGI_SHARED_PATH_TRACER_INTERFACE_H

#include "shared/glsl_cpp.h"
#include "shared/ray_box.h"
#include "shared/sh.h"

SSVGI_SHARED_BEGIN

// The builder never makes a tree deeper than this, so a traversal stack of this many entries cannot overflow.
SSVGI_CONSTANT(uint, kBvhMaxDepth, 64u);
SSVGI_CONSTANT(uint, kBvhMaxLeafTriangles, 4u);

// One node of the flat BVH array; nodes[0] is the root. The two children of an inner node are adjacent in the array,
// so one index finds both. Index and count are uint bits stored in the float w members (floatBitsToUint).
struct BvhNode {
  vec4 boundsMinAndFirst;  // xyz: min corner; w: inner node: index of its first child; leaf: its first triangle
  vec4 boundsMaxAndCount;  // xyz: max corner; w: leaf: its triangle count (1..kBvhMaxLeafTriangles); inner node: 0
};
SSVGI_CHECK_SIZE(BvhNode, 32);

// A world-space triangle as the ray test reads it (Möller–Trumbore: a vertex and two edges), in BVH leaf order.
struct TraceTriangle {
  vec3 vertex0;
  uint cutsOut;   // 1 where its material's texture cuts it out in places (Material::alphaCutoff): a hit looks there
  vec3 edge1;     // vertex1 - vertex0
  uint padding1;
  vec3 edge2;     // vertex2 - vertex0
  uint padding2;
};
SSVGI_CHECK_SIZE(TraceTriangle, 48);

// What shading a hit needs, in the same order as the TraceTriangles. The normals are what the G-buffer's vertex shader
// outputs (object normal × the instance's normal matrix, not normalised), so that interpolating and normalising them
// gives the renderer's normal exactly.
struct TriangleShading {
  vec4 normal0AndU0;    // xyz: vertex 0's normal; w: its texture u
  vec4 normal1AndU1;
  vec4 normal2AndU2;
  vec4 texcoordVAndMaterial;  // xyz: texture v of vertices 0, 1, 2; w: material index (uint bits)
  vec3 color0;          // the vertices' colours (renderer::Vertex::color)
  float padding0;
  vec3 color1;
  float padding1;
  vec3 color2;
  float padding2;
};
SSVGI_CHECK_SIZE(TriangleShading, 112);

// An 8-bit sRGB RGBA texture inside the packed texel buffer: one uint per texel (R in the low byte), rows top to
// bottom. The Vulkan layer binds no descriptor arrays, so all of a scene's textures share one storage buffer.
struct PackedTexture {
  uint firstTexel;
  uint width;
  uint height;
  uint padding;
};
SSVGI_CHECK_SIZE(PackedTexture, 16);

// One entry of the table of the scene's emissive triangles, from which the paths sample emitters directly
// (next-event estimation). The table lists every triangle of positive area whose material emits, in BVH triangle
// order, each chosen with probability proportional to its power: area × emissionLuminance of its emission.
struct EmissiveTriangle {
  uint triangle;                // index into TraceTriangle[] and TriangleShading[]
  float selectionProbability;   // its share of the emitted power
  float cumulativeProbability;  // selectionProbability summed over the table up to this entry; exactly 1 for the last
  uint padding;
};
SSVGI_CHECK_SIZE(EmissiveTriangle, 16);

// The luminance (Rec. 709) of an emission: a triangle's power is π × area × this (π, common to all, is left out), the
// measure by which next-event estimation chooses emitters. The table's builder (reference/traced_scene.cpp) and the
// paths, which need the density of a point on an emitter they hit (shaders/reference/path_radiance.glsl), both use it.
SSVGI_INLINE float emissionLuminance(vec3 emission) { return dot(emission, vec3(0.2126f, 0.7152f, 0.0722f)); }

// The power heuristic with exponent 2 (Veach 1997, §9.2.4): the weight of a sample drawn with density `chosen` by one
// technique that another would draw with density `other` (both in the same measure), chosen² / (chosen² + other²).
// The weights of one sample under the two techniques sum to 1. Written as a ratio so that neither square overflows;
// 0 where `chosen` is 0 (the technique cannot draw that sample).
SSVGI_INLINE float powerHeuristic(float chosen, float other) {
  if (!(chosen > 0.0f)) return 0.0f;
  float ratio = other / chosen;
  return 1.0f / (1.0f + ratio * ratio);
}

// PathTrace's push constants: which samples this dispatch adds to each pixel.
struct PathTracePush {
  uint firstSample;  // samples [firstSample, firstSample + sampleCount) of every pixel; the sums hold the earlier ones
  uint sampleCount;
  uint seed;
  uint maxBounces;   // reflections of light after it leaves its source and before it reaches the primary hit
  // Entries of the EmissiveTriangle table the paths sample directly; 0 with emitter sampling off (or no emitter in
  // the scene): then emission is found only where a path hits it.
  uint emitterCount;
  // Σ area × emissionLuminance over the table (m² · W/(m²·sr)): a point on an emitter of luminance Y is sampled with
  // density Y / emittedPower per m². Unused when emitterCount is 0.
  float emittedPower;
};
SSVGI_CHECK_SIZE(PathTracePush, 24);

// PointRadiance: incoming radiance over the whole sphere at free points (not on a surface), projected onto SH2. Each
// point has a workgroup of kPointRadianceLanes lanes; in every round each lane traces one antithetic pair of uniform
// directions, ω and -ω. The pair keeps the estimate unbiased and makes it exact for band 0 wherever the radiance is
// the same in opposite directions, and for band 1 wherever it is constant (a uniform sky, a furnace).
SSVGI_CONSTANT(uint, kPointRadianceLanes, 64u);
SSVGI_CONSTANT(uint, kPointRadianceDirectionsPerRound, 2u * kPointRadianceLanes);

struct PointRadiancePush {
  uint firstRound;  // rounds [firstRound, firstRound + roundCount) of every point; the sums hold the earlier ones
  uint roundCount;
  uint seed;
  uint maxBounces;  // reflections of light after it leaves its source and before it reaches the point
  uint emitterCount;   // as PathTracePush::emitterCount
  float emittedPower;  // as PathTracePush::emittedPower
};
SSVGI_CHECK_SIZE(PointRadiancePush, 24);

// The six axis normals in the order PointRadianceSums keeps them: +x, −x, +y, −y, +z, −z.
SSVGI_CONSTANT(uint, kPointAxisNormals, 6u);
SSVGI_INLINE vec3 pointAxisNormal(uint index) {
  vec3 normal = vec3(0.0f);
  normal[int(index / 2u)] = index % 2u == 0u ? 1.0f : -1.0f;
  return normal;
}

// What PointRadiance sums per point over its directions ω (the host scales each by 4π/N):
struct PointRadianceSums {
  Sh2Rgb radiance;                 // Σ L(ω)·Y(ω): the SH2 projection of the radiance arriving there
  // Σ L(ω)·max(0, ω·n) for the axis normals n (pointAxisNormal; rgb, w unused): the irradiance E(n) itself, which the
  // SH2 holds only to its first band — what any reading of SH2 is judged against
  vec4 axisIrradiance[kPointAxisNormals];
};
SSVGI_CHECK_SIZE(PointRadianceSums, 48 + 96);

// Binding slots (descriptor set 0). The scene, read by every pass:
SSVGI_CONSTANT(uint, kBindTraceFrame, 0u);         // FrameConstants (uniform): camera, sun, sky, light count
SSVGI_CONSTANT(uint, kBindTraceNodes, 1u);         // BvhNode[]
SSVGI_CONSTANT(uint, kBindTraceTriangles, 2u);     // TraceTriangle[]
SSVGI_CONSTANT(uint, kBindTraceShading, 3u);       // TriangleShading[]
SSVGI_CONSTANT(uint, kBindTraceMaterials, 4u);     // GpuMaterial[]
SSVGI_CONSTANT(uint, kBindTraceTextures, 5u);      // PackedTexture[]
SSVGI_CONSTANT(uint, kBindTraceTexels, 6u);        // uint[]: RGBA8 texels
SSVGI_CONSTANT(uint, kBindTraceLights, 7u);        // GpuLight[]; intensityAndShadow.w is kNoShadow for unshadowed lights
SSVGI_CONSTANT(uint, kBindTraceEmitters, 19u);     // EmissiveTriangle[]; at least one entry even when the scene has none
// The primary hit of each pixel, written by PrimaryHits and read by PathTrace (rgba32f unless noted):
SSVGI_CONSTANT(uint, kBindPrimaryRayOrigin, 8u);   // xyz: where the pixel's secondary rays start; w: 1 on a surface, 0 sky
SSVGI_CONSTANT(uint, kBindPrimaryNormal, 9u);      // xyz: shading normal facing the camera
SSVGI_CONSTANT(uint, kBindPrimaryAlbedo, 10u);
SSVGI_CONSTANT(uint, kBindPrimaryRadiance, 11u);   // rgb: emitted radiance of the surface, or the sky where none was hit
SSVGI_CONSTANT(uint, kBindPrimaryDirect, 12u);     // rgb: E_direct
SSVGI_CONSTANT(uint, kBindPrimaryDistance, 13u);   // r32f: metres from the camera, 0 where nothing was hit
// PathTrace's accumulation and its running results:
SSVGI_CONSTANT(uint, kBindTraceIndirectSum, 14u);  // rgb: sum of the E_indirect samples so far
SSVGI_CONSTANT(uint, kBindTraceIndirect, 15u);     // out: rgb: their mean, E_indirect
SSVGI_CONSTANT(uint, kBindTraceFinal, 16u);        // out: rgb: final radiance
// PointRadiance's points and its accumulation:
SSVGI_CONSTANT(uint, kBindPointPositions, 17u);    // vec4[]: xyz: world position of each point
SSVGI_CONSTANT(uint, kBindPointRadianceSums, 18u); // PointRadianceSums[]: per point, over its directions so far

// Where a ray meets a triangle: (t, u, v) with the hit at origin + t·direction = vertex0 + u·edge1 + v·edge2, or
// t = -1 when it misses (Möller & Trumbore 1997). t may be negative or beyond the ray's end: the caller checks it.
SSVGI_INLINE vec3 intersectTriangle(vec3 origin, vec3 direction, vec3 vertex0, vec3 edge1, vec3 edge2) {
  vec3 p = cross(direction, edge2);
  float determinant = dot(edge1, p);
  if (determinant == 0.0f) return vec3(-1.0f, 0.0f, 0.0f);  // the ray lies in the triangle's plane
  float inverseDeterminant = 1.0f / determinant;
  vec3 fromVertex0 = origin - vertex0;
  float u = dot(fromVertex0, p) * inverseDeterminant;
  vec3 q = cross(fromVertex0, edge1);
  float v = dot(direction, q) * inverseDeterminant;
  if (u < 0.0f || v < 0.0f || u + v > 1.0f) return vec3(-1.0f, 0.0f, 0.0f);
  return vec3(dot(edge2, q) * inverseDeterminant, u, v);
}

// The PCG hash (Jarzynski & Olano, "Hash Functions for GPU Rendering", JCGT 2020): one round of a PCG generator
// with its output permutation; well mixed in every bit.
SSVGI_INLINE uint pcgHash(uint value) {
  uint state = value * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

// The random state of one sample of one pixel: a function of (pixel, sample, seed) only, so an image is the same
// whatever batches its samples were traced in, and differs for another seed.
SSVGI_INLINE uint sampleRandomState(uint pixelIndex, uint sampleIndex, uint seed) {
  return pcgHash(pixelIndex ^ pcgHash(sampleIndex ^ pcgHash(seed)));
}

// The next uniform number in [0, 1) of a random state (24 bits: exactly representable in float).
SSVGI_INLINE float nextRandom(SSVGI_INOUT(uint) state) {
  state = pcgHash(state);
  return float(state >> 8u) * (1.0f / 16777216.0f);
}

// A direction around a unit normal with density cos θ / π (Malley's method: a uniform point on the unit disc lifted
// onto the hemisphere), in the orthonormal basis of Duff et al., "Building an Orthonormal Basis, Revisited" (JCGT 2017).
SSVGI_INLINE vec3 cosineSampleHemisphere(vec2 unitSquarePoint, vec3 normal) {
  float radius = sqrt(unitSquarePoint.x);
  float phi = 2.0f * kPi * unitSquarePoint.y;
  float zSign = normal.z >= 0.0f ? 1.0f : -1.0f;
  float a = -1.0f / (zSign + normal.z);
  float b = normal.x * normal.y * a;
  vec3 tangent = vec3(1.0f + zSign * normal.x * normal.x * a, zSign * b, -zSign * normal.x);
  vec3 bitangent = vec3(b, zSign + normal.y * normal.y * a, -normal.y);
  float height = sqrt(max(0.0f, 1.0f - unitSquarePoint.x));
  return radius * cos(phi) * tangent + radius * sin(phi) * bitangent + height * normal;
}

SSVGI_SHARED_END

#endif
