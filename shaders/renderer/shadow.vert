#version 450
// Shadow: depth of the scene from the sun or a local light's view. Without a fragment shader, but for the materials
// whose texture cuts the surface out in places (shadow.frag).
#include "shared/renderer_interface.h"

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec2 inUv;

layout(binding = kBindDrawInstances) readonly buffer Instances { GpuInstance instances[]; };
layout(binding = kBindDrawShadowViews) readonly buffer ShadowViews { ShadowView shadowViews[]; };
layout(push_constant) uniform Push { DrawPush draw; };

layout(location = 0) out vec2 outUv;

void main() {
  outUv = inUv;
  gl_Position = shadowViews[draw.shadowView].viewProjection * (instances[draw.instance].model * vec4(inPosition, 1.0));
}
