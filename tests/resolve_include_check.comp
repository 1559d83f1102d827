#version 450
// A host's composite as little as it can be: ssvgi's results resolved at each pixel with the installed
// ssvgi/resolve.glsl and nothing else of ssvgi (tests/installed_package_test.cmake compiles it against the prefix).
#include "ssvgi/resolve.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = 0) uniform sampler2D irradiance;
layout(binding = 1) uniform sampler2D confidence;
layout(binding = 2) uniform sampler2D depth;
layout(binding = 3) uniform sampler2D normal;
layout(binding = 4, rgba16f) writeonly uniform image2D resolved;
layout(push_constant) uniform Frame {
  mat4 inverseViewProjection;
  vec3 cameraPosition;
  float width;
  float height;
};

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  SsvgiResolveView view = SsvgiResolveView(inverseViewProjection, cameraPosition, vec2(width, height));
  SsvgiResolved light = ssvgiResolve(irradiance, confidence, depth, normal, view, pixel);
  imageStore(resolved, pixel, vec4(light.irradiance, light.confidence));
}
