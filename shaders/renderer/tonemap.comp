#version 450
// Tonemap: exposure, the ACES filmic curve (Narkowicz's fit of the ACES RRT+ODT), then the sRGB transfer function.
#include "shared/renderer_interface.h"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = kBindTonemapFrame, std140) readonly buffer Frame { FrameConstants frame; };
layout(binding = kBindTonemapInput, rgba32f) readonly uniform image2D hdr;
layout(binding = kBindTonemapOutput, rgba8) writeonly uniform image2D ldr;

vec3 acesFitted(vec3 x) {
  return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

vec3 linearToSrgb(vec3 linear) {
  return mix(linear * 12.92, 1.055 * pow(linear, vec3(1.0 / 2.4)) - 0.055, greaterThan(linear, vec3(0.0031308)));
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, ivec2(frame.viewportSize.xy)))) return;
  vec3 radiance = imageLoad(hdr, pixel).rgb * frame.exposure;
  imageStore(ldr, pixel, vec4(linearToSrgb(acesFitted(radiance)), 1.0));
}
