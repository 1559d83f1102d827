#version 450
// HiZBuild: the farthest depth (min reversed-Z) of each 2×2 block, level by level, into one buffer (SPEC §4, step 1).
// Level 0 is half the depth's resolution. A buffer rather than a mipmapped image: BrickCulling and SceneVoxelization
// pick the level per box (hiz_occlusion.glsl), and a buffer needs no descriptor arrays or min/max samplers, which
// mobile GPUs may lack (SPEC §2).
#include "gi/gi_frame.glsl"
#include "shared/voxel_interface.h"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = kBindHiZDepth) uniform sampler2D depthBuffer;
layout(binding = kBindHiZPyramid) buffer HiZ { float hiz[]; };
layout(push_constant) uniform Push { uint level; } push;
// Level 0 reads the depth, the others the level before: two pipelines rather than a branch on the level, whose both
// sides lavapipe would run for every texel (it masks lanes rather than jumping).
layout(constant_id = 0) const bool kFromDepth = true;

float source(ivec2 texel, HiZLevel sourceLevel) {
  texel = min(texel, ivec2(sourceLevel.size) - 1);
  if (kFromDepth) return texelFetch(depthBuffer, texel, 0).r;
  return hiz[sourceLevel.firstTexel + uint(texel.y) * sourceLevel.size.x + uint(texel.x)];
}

void main() {
  HiZLevel target = frame.hizLevels[push.level];
  uvec2 texel = gl_GlobalInvocationID.xy;
  if (any(greaterThanEqual(texel, target.size))) return;
  HiZLevel sourceLevel = HiZLevel(frame.size, 0u, 0u);  // level 0 reads the depth itself
  if (!kFromDepth) sourceLevel = frame.hizLevels[push.level - 1u];
  // Each level is half the one below rounded up: on an odd-sized source the last texel covers its last column (or
  // row) alone, the second being clamped onto the first.
  ivec2 first = ivec2(texel * 2u);
  ivec2 last = first + 1;
  float farthest = 1.0;
  for (int y = first.y; y <= last.y; ++y)
    for (int x = first.x; x <= last.x; ++x) farthest = min(farthest, source(ivec2(x, y), sourceLevel));
  hiz[target.firstTexel + texel.y * target.size.x + texel.x] = farthest;
}
