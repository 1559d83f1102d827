// Lets one header be compiled both as GLSL and as C++, so that struct layouts, binding slots, constants and small
// functions (sky radiance, SH, packing) are written once and shared by the shaders and the host (SPEC §2).
//
// Rules for shared headers: std430/std140-safe members only (scalars, vec2, vec4, mat4; a vec3 or ivec3, whose
// alignment differs, only on a 16-byte boundary and followed by a 4-byte scalar, the two filling 16 bytes in both
// languages), every struct followed by SSVGI_CHECK_SIZE, functions written in the common subset of GLSL and
// glm (no swizzle assignment, no `inout`: use SSVGI_INOUT).
#ifndef SSVGI_GLSL_CPP_H
#define SSVGI_GLSL_CPP_H

#ifdef __cplusplus
#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/packing.hpp>
#include <cstdint>

#define SSVGI_SHARED_BEGIN        \
  namespace ssvgi::shader {       \
  using namespace glm;            \
  using uint = uint32_t;
#define SSVGI_SHARED_END }
#define SSVGI_CONSTANT(type, name, value) inline constexpr type name = value
#define SSVGI_CHECK_SIZE(type, bytes) static_assert(sizeof(type) == (bytes), #type " layout changed: update the GLSL users")
#define SSVGI_INOUT(type) type&
#define SSVGI_INLINE inline
#define SSVGI_HALF_BITS(x) uint(glm::packHalf1x16(x))
#define SSVGI_HALF_FLOAT(bits) glm::unpackHalf1x16(uint16_t(bits))
#else
#define SSVGI_SHARED_BEGIN
#define SSVGI_SHARED_END
#define SSVGI_CONSTANT(type, name, value) const type name = value
// GLSL has no static_assert; declaring the expected size keeps the trailing semicolon legal.
#define SSVGI_CHECK_SIZE(type, bytes) const uint type##ExpectedBytes = bytes
#define SSVGI_INOUT(type) inout type
#define SSVGI_INLINE
#define SSVGI_HALF_BITS(x) (packHalf2x16(vec2(x, 0.0f)) & 0xffffu)
#define SSVGI_HALF_FLOAT(bits) unpackHalf2x16(uint(bits)).x
#endif

SSVGI_SHARED_BEGIN
SSVGI_CONSTANT(float, kPi, 3.14159265358979f);
SSVGI_SHARED_END

#endif
