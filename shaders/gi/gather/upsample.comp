#version 450
// Upsample (SPEC §4.6; the talk's "UpSample to 1/2 render resolution, bilateral filter with depth and normal
// weights"): each half-resolution pixel blends the tile samples around it, bilinear in the jittered sample grid,
// weighted by how well each sample's depth and normal match its own (joint bilateral upsampling, Kopf et al. 2007).
#include "gather_geometry.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = kBindGatherConstants) uniform GatherConstantsBlock { GatherConstants gather; };
layout(binding = kBindGatherDepth) uniform sampler2D depthBuffer;
layout(binding = kBindGatherNormal) uniform sampler2D normalBuffer;
layout(binding = kBindGatherTileIrradiance, rgba16f) readonly uniform image2D tileIrradiance;
layout(binding = kBindGatherTileGeometry, rgba16f) readonly uniform image2D tileGeometry;
layout(binding = kBindGatherUpsampled, r32ui) writeonly uniform uimage2D upsampled;

// Taps beyond the bilinear 2×2 keep this spatial weight: they count only where the 2×2 are all on other surfaces (a
// thin object, a silhouette), so such a pixel borrows from its own surface a tile further away instead of going dark.
const float kOuterTapWeight = 1e-3;

void main() {
  ivec2 halfPixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(halfPixel, ivec2(gather.sizes.zw)))) return;
  ivec2 pixel = 2 * halfPixel;
  vec2 size = vec2(frame.sizes.xy);
  float depth = texelFetch(depthBuffer, pixel, 0).r;
  vec3 irradiance = vec3(0.0);
  if (depth > 0.0) {
    Surface surface = surfaceAt(frame.inverseViewProjection, frame.cameraPosition.xyz, pixel, size, depth,
                                normalize(texelFetch(normalBuffer, pixel, 0).xyz));
    ivec2 sampleOffset = ivec2(gatherSampleOffset(gather.frame.x));
    // The pixel in the grid of this frame's samples (tile t sampled pixel t·4 + offset).
    vec2 tileCoordinate = vec2(pixel - sampleOffset) / float(kGatherTileSize);
    ivec2 firstTile = ivec2(floor(tileCoordinate));
    ivec2 lastTile = ivec2(gather.sizes.xy) - 1;
    float totalWeight = 0.0;
    for (int y = -1; y <= 2; ++y)
      for (int x = -1; x <= 2; ++x) {
        ivec2 tile = firstTile + ivec2(x, y);
        if (any(lessThan(tile, ivec2(0))) || any(greaterThan(tile, lastTile))) continue;
        vec4 geometry = imageLoad(tileGeometry, tile);
        if (geometry.w <= 0.0) continue;  // the tile's sample saw nothing
        vec2 tent = max(vec2(1.0) - abs(vec2(tile) - tileCoordinate), vec2(kOuterTapWeight));
        ivec2 samplePixel = min(tile * int(kGatherTileSize) + sampleOffset, ivec2(frame.sizes.xy) - 1);
        vec3 samplePosition = reconstructPosition(frame.inverseViewProjection, vec2(samplePixel), size, geometry.w);
        float weight = tent.x * tent.y * planeWeight(surface, samplePosition) *
                       normalWeight(surface, normalize(geometry.xyz));
        irradiance += weight * imageLoad(tileIrradiance, tile).rgb;
        totalWeight += weight;
      }
    irradiance = totalWeight > 0.0 ? irradiance / totalWeight : vec3(0.0);
  }
  imageStore(upsampled, halfPixel, uvec4(packR11G11B10F(irradiance)));
}
