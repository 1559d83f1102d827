#version 450
// SkyMap: the sky's radiance at the middle of each texel of an equirectangular map (shared/sky_map.h), for ssvgi's
// probe rays that leave its voxels (ssvgi::FrameDesc::skyRadianceMap): the same evaluateSky the path tracer and the
// background see, in detail SH2 cannot hold.
#include "shared/renderer_interface.h"
#include "shared/sky_map.h"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = kBindSkyMapFrame, std140) readonly buffer Frame { FrameConstants frame; };
layout(binding = kBindSkyMapOutput, rgba16f) writeonly uniform image2D skyMap;

void main() {
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = imageSize(skyMap);
  if (any(greaterThanEqual(texel, size))) return;
  vec3 direction = skyMapDirection((vec2(texel) + 0.5) / vec2(size));
  imageStore(skyMap, texel, vec4(evaluateSky(frame.sky, direction), 1.0));
}
