#version 450
// Upsample (SPEC §4.6; the talk's "UpSample to 1/2 render resolution, bilateral filter with depth and normal
// weights"): each half-resolution pixel blends the tile samples around it, bilinear in the jittered sample grid,
// weighted by how well each sample's depth and normal match its own (joint bilateral upsampling, Kopf et al. 2007).
// It writes the output image, which TemporalFilter then filters in place.
#include "gather_geometry.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = kBindGatherOutput, rgba16f) writeonly uniform image2D outputIrradiance;

void main() {
  ivec2 halfPixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(halfPixel, ivec2(gather.sizes.zw)))) return;
  ivec2 pixel = 2 * halfPixel;
  float depth = texelFetch(depthBuffer, pixel, 0).r;
  vec3 irradiance = depth > 0.0 ? tileNeighbourhood(currentSurface(pixel, depth), pixel).blended : vec3(0.0);
  imageStore(outputIrradiance, halfPixel, vec4(finiteHalf(irradiance), depth > 0.0 ? finiteHalf(depth) : 0.0));
}
