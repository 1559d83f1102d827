// Pixels and normalised device coordinates (SPEC §2), written once for ssvgi's shaders, its C++ and a host's GLSL
// (ssvgi/resolve.glsl includes it): the same text compiles as GLSL and, with glm, as C++ (ssvgi::shader). Rows run
// top to bottom and NDC +y is up, as in the projection matrices: the renderer flips its viewport (negative height) to
// match. The names carry ssvgi's prefix, since in GLSL they share the host's one namespace.
#ifndef SSVGI_PIXEL_COORDINATES_H
#define SSVGI_PIXEL_COORDINATES_H

#ifdef __cplusplus
#include <glm/vec2.hpp>
#define SSVGI_PIXEL_INLINE inline
namespace ssvgi::shader {
using glm::vec2;
#else
#define SSVGI_PIXEL_INLINE
#endif

// NDC -> texture coordinates: 0–1 across the image, rows top to bottom.
SSVGI_PIXEL_INLINE vec2 ssvgiNdcToUv(vec2 ndc) { return vec2(0.5f + 0.5f * ndc.x, 0.5f - 0.5f * ndc.y); }

// Texture coordinates -> NDC.
SSVGI_PIXEL_INLINE vec2 ssvgiUvToNdc(vec2 uv) { return vec2(uv.x * 2.0f - 1.0f, 1.0f - uv.y * 2.0f); }

// The centre of a pixel of an image of `size` pixels -> NDC.
SSVGI_PIXEL_INLINE vec2 ssvgiPixelToNdc(vec2 pixel, vec2 size) { return ssvgiUvToNdc((pixel + vec2(0.5f)) / size); }

// NDC -> continuous pixel coordinates (pixel p covers [p, p + 1)): ssvgiPixelToNdc's inverse without the half pixel.
SSVGI_PIXEL_INLINE vec2 ssvgiNdcToPixel(vec2 ndc, vec2 size) { return ssvgiNdcToUv(ndc) * size; }

#ifdef __cplusplus
}  // namespace ssvgi::shader
#endif

#endif
