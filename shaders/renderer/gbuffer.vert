#version 450
#include "shared/renderer_interface.h"

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;
layout(location = 3) in vec3 inColor;

layout(binding = kBindDrawFrame, std140) readonly buffer Frame { FrameConstants frame; };
layout(binding = kBindDrawInstances) readonly buffer Instances { GpuInstance instances[]; };
layout(push_constant) uniform Push { DrawPush draw; };

layout(location = 0) out vec3 outNormal;
layout(location = 1) out vec2 outUv;
layout(location = 2) out vec4 outClip;
layout(location = 3) out vec4 outPreviousClip;
layout(location = 4) out vec3 outColor;

void main() {
  GpuInstance instance = instances[draw.instance];
  vec4 world = instance.model * vec4(inPosition, 1.0);
  outNormal = mat3(instance.normalMatrix) * inNormal;
  outUv = inUv;
  outColor = inColor;
  outClip = frame.viewProjection * world;
  outPreviousClip = frame.previousViewProjection * (instance.previousModel * vec4(inPosition, 1.0));
  gl_Position = outClip;
}
