#version 450
// Upsample (SPEC §4.6; the talk's "UpSample to 1/2 render resolution, bilateral filter with depth and normal
// weights"): each half-resolution pixel blends the tile samples around it, bilinear in the jittered sample grid,
// weighted by how well each sample's depth and normal match its own (joint bilateral upsampling, Kopf et al. 2007).
// It writes the output image, which TemporalFilter then filters in place, and the confidence (SPEC §6.4), blended
// with the same weights from the tiles' confidence: 0 where nothing was drawn or no tile sample lies on the surface.
#include "gather_geometry.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = kBindGatherOutput, rgba16f) writeonly uniform image2D outputIrradiance;
layout(binding = kBindGatherConfidence, r8) writeonly uniform image2D confidence;

void main() {
  ivec2 halfPixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(halfPixel, ivec2(gather.halfSize)))) return;
  ivec2 pixel = 2 * halfPixel;
  float depth = texelFetch(depthBuffer, pixel, 0).r;
  TileNeighbourhood tiles = TileNeighbourhood(vec3(0.0), 0.0, vec3(1e30), vec3(0.0), 1.0, false);
  if (depth > 0.0) tiles = tileNeighbourhood(currentSurface(pixel, depth), pixel);
  imageStore(outputIrradiance, halfPixel, vec4(finiteHalf(tiles.blended), depth > 0.0 ? finiteHalf(depth) : 0.0));
  imageStore(confidence, halfPixel, vec4(tiles.confidence));
}
