#ifndef SSVGI_GATHER_GEOMETRY_GLSL
#define SSVGI_GATHER_GEOMETRY_GLSL
// The geometry test of Upsample and TemporalFilter: how much a neighbouring sample belongs to a pixel's surface.
#include "gi/gi_frame.glsl"
#include "shared/gather_interface.h"

// A G-buffer sample as the filters compare it.
struct Surface {
  vec3 position;  // world, m
  vec3 normal;
  float viewDistance;
};

Surface surfaceAt(mat4 inverseViewProjection, vec3 cameraPosition, ivec2 pixel, vec2 size, float depth, vec3 normal) {
  vec3 position = reconstructPosition(inverseViewProjection, vec2(pixel), size, depth);
  return Surface(position, normal, distance(position, cameraPosition));
}

// 1 on the pixel's tangent plane, falling to 0 at kGatherPlaneTolerance of its view distance off it: a neighbour
// across a depth edge or a crease lies far off the plane, one on the same tilted floor does not.
float planeWeight(Surface pixel, vec3 neighbourPosition) {
  float planeDistance = abs(dot(neighbourPosition - pixel.position, pixel.normal));
  return clamp(1.0 - planeDistance / (kGatherPlaneTolerance * pixel.viewDistance), 0.0, 1.0);
}

float normalWeight(Surface pixel, vec3 neighbourNormal) {
  return pow(max(dot(pixel.normal, neighbourNormal), 0.0), kGatherNormalPower);
}

#endif
