#version 450
// Shadow: depth of the scene from the sun or a local light's view (no fragment shader).
#include "shared/renderer_interface.h"

layout(location = 0) in vec3 inPosition;

layout(binding = kBindDrawInstances) readonly buffer Instances { GpuInstance instances[]; };
layout(binding = kBindDrawShadowViews) readonly buffer ShadowViews { ShadowView shadowViews[]; };
layout(push_constant) uniform Push { DrawPush draw; };

void main() {
  gl_Position = shadowViews[draw.shadowView].viewProjection * (instances[draw.instance].model * vec4(inPosition, 1.0));
}
