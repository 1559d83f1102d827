#version 450
// Test shader for the GPU layer: output[i] = input[i] * scale + offset, from a read-only and a written buffer.
layout(local_size_x = 64) in;

layout(binding = 0) readonly buffer Input { float inputValues[]; };
layout(binding = 1) writeonly buffer Output { float outputValues[]; };
layout(push_constant) uniform Push {
  float scale;
  float offset;
  uint count;
} push;

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i < push.count) outputValues[i] = inputValues[i] * push.scale + push.offset;
}
