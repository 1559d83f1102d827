#version 450
// FinalGather (SPEC §4.6; the talk's "DownSample: Probe Volume sampling with custom weights, 1 sample per 4x4 pixels,
// temporal jitter; output indirect light + normal + depth"): one thread per 4×4 tile of the frame's half of them (a
// checkerboard, gatherSamplesTile) samples the probe volume at one pixel of its tile, a different one each time
// (gatherSampleOffset), with the talk's three leak remedies and a voxel visibility test. Half the tiles a frame: the
// visibility tests are most of the pass's cost, and the temporal filter averages the samples of many frames anyway.
// The tile's normal and depth are that pixel's in the host's G-buffer, where TemporalUpsample reads them.
// Beside E it stores the tile's confidence (SPEC §6.4): the known fraction of the probes it used, weighted as their
// light is; 0 where no probe contributed or nothing was drawn.
#include "gi/gi_frame.glsl"
#include "gi/gather/probe_irradiance.glsl"
#include "gi/work_counting.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = kBindGatherDepth) uniform sampler2D depthBuffer;
layout(binding = kBindGatherNormal) uniform sampler2D normalBuffer;
layout(binding = kBindGatherTileIrradiance, rgba16f) writeonly uniform image2D tileIrradiance;
layout(binding = kBindGatherTileProbeBlend, r8) writeonly uniform image2D tileProbeBlend;

// The workgroup's threads in 4×2 blocks: a lock-step group of 8 (lavapipe's) gathers tiles that lie close together,
// whose probes agree or disagree alike, rather than a row 16 tiles long; it traces for as long as its busiest tile.
uvec2 threadInBlocks() {
  uint index = gl_LocalInvocationIndex;
  uvec2 local = uvec2((index & 3u) | (((index >> 3u) & 1u) << 2u), ((index >> 2u) & 1u) | ((index >> 4u) << 1u));
  return gl_WorkGroupID.xy * gl_WorkGroupSize.xy + local;
}

void main() {
  uint frameIndex = gather.frameIndex;
  uvec2 tile = gatherTileOfThread(threadInBlocks(), frameIndex);
  if (any(greaterThanEqual(tile, gather.tiles))) return;
  ivec2 pixel = ivec2(min(tile * kGatherTileSize + gatherSampleOffset(frameIndex), frame.size - 1u));
  float depth = texelFetch(depthBuffer, pixel, 0).r;
  if (depth <= 0.0) {  // nothing drawn (TemporalUpsample skips the tile)
    imageStore(tileIrradiance, ivec2(tile), vec4(0.0));
    imageStore(tileProbeBlend, ivec2(tile), vec4(1.0));
    return;
  }
  vec3 normal = normalize(texelFetch(normalBuffer, pixel, 0).xyz);
  vec3 position = reconstructPosition(frame.inverseViewProjection, vec2(pixel), vec2(frame.size), depth);
  GatheredLight light = probeLight(gatherFrame(), position, normal, hashToUnitCube(uvec3(tile, frameIndex)).x,
                                   volume.skyOnlyThroughObservedSpace != 0u);
  if (countsWork()) {
    atomicAdd(work.gatherTiles, 1u);
    atomicAdd(work.gatherRays, tracedWork.rays);
    atomicAdd(work.gatherReads, tracedWork.reads);
  }
  // A host pixel whose depth or normal is not finite gives no light rather than a NaN, and no confidence.
  float confidence = light.confidence >= 0.0 ? min(light.confidence, 1.0) : 0.0;  // a NaN fails the test
  imageStore(tileIrradiance, ivec2(tile), vec4(finiteHalf(light.irradiance), confidence));
  // At least the r8's least step where a probe was found, so that no rounding makes it read as kTileFoundNoProbe
  // (the blend of a history cap of 255 is 1/256).
  float probeBlend = max(light.probeBlend >= 0.0 ? light.probeBlend : 1.0, 1.0 / 255.0);
  imageStore(tileProbeBlend, ivec2(tile), vec4(light.found ? probeBlend : kTileFoundNoProbe));
}
