// Pixels and normalised device coordinates, for the shaders and the host alike (SPEC §2). Rows run top to bottom and
// NDC +y is up, as in the projection matrices: the renderer flips its viewport (negative height) to match.
#ifndef SSVGI_SHARED_NDC_H
#define SSVGI_SHARED_NDC_H

#include "shared/glsl_cpp.h"

SSVGI_SHARED_BEGIN

// NDC -> texture coordinates: 0–1 across the image, rows top to bottom.
SSVGI_INLINE vec2 ndcToUv(vec2 ndc) { return vec2(0.5f + 0.5f * ndc.x, 0.5f - 0.5f * ndc.y); }

// Texture coordinates -> NDC.
SSVGI_INLINE vec2 uvToNdc(vec2 uv) { return vec2(uv.x * 2.0f - 1.0f, 1.0f - uv.y * 2.0f); }

// The centre of a pixel of an image of `size` pixels -> NDC.
SSVGI_INLINE vec2 pixelToNdc(vec2 pixel, vec2 size) { return uvToNdc((pixel + vec2(0.5f)) / size); }

// NDC -> continuous pixel coordinates (pixel p covers [p, p + 1)): pixelToNdc's inverse without the half pixel.
SSVGI_INLINE vec2 ndcToPixel(vec2 ndc, vec2 size) { return ndcToUv(ndc) * size; }

SSVGI_SHARED_END

#endif
