// The host's sky radiance map (ssvgi::FrameDesc::skyRadianceMap), shared by the probes that read it and a host that
// writes it: an equirectangular image, u the azimuth from +Z towards +X (u = 1/2 along +Z, increasing towards +X),
// v from the zenith (0) to the nadir (1).
#ifndef SSVGI_SHARED_SKY_MAP_H
#define SSVGI_SHARED_SKY_MAP_H

#include "shared/glsl_cpp.h"
#include "shared/sh.h"

SSVGI_SHARED_BEGIN

// Where a unit direction lies in the map, texture coordinates in [0, 1]².
SSVGI_INLINE vec2 skyMapCoordinates(vec3 direction) {
  // atan(0, 0) is undefined in GLSL: the poles take azimuth 0 (any is right there).
  bool pole = direction.x == 0.0f && direction.z == 0.0f;
  float azimuth = pole ? 0.0f : atan(direction.x, direction.z);
  return vec2(0.5f + azimuth / (2.0f * kPi), acos(clamp(direction.y, -1.0f, 1.0f)) / kPi);
}

// The unit direction at texture coordinates `uv` of the map.
SSVGI_INLINE vec3 skyMapDirection(vec2 uv) {
  float azimuth = (uv.x - 0.5f) * 2.0f * kPi, polar = uv.y * kPi;
  return vec3(sin(polar) * sin(azimuth), cos(polar), sin(polar) * cos(azimuth));
}

SSVGI_SHARED_END

#endif
