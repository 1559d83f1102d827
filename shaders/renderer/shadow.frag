#version 450
// Shadow for a material whose texture cuts the surface out in places (Material::alphaCutoff): no depth where it does,
// as the G-buffer draws none there.
#include "shared/renderer_interface.h"

layout(location = 0) in vec2 inUv;

layout(binding = kBindDrawMaterials) readonly buffer Materials { GpuMaterial materials[]; };
layout(binding = kBindDrawBaseColor) uniform sampler2D baseColorTexture;
layout(push_constant) uniform Push { DrawPush draw; };

void main() {
  if (texture(baseColorTexture, inUv).a < materials[draw.material].alphaCutoff) discard;
}
