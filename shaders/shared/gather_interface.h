// Final gather, upsample and temporal filter (SPEC §4.6; the talk's "Part3 Shading"): layouts, binding slots, constants
// and the sample pattern shared by the gather shaders and the host.
//
// Resolutions: the gather takes one sample per kGatherTileSize² pixel tile ("1/4 resolution") every other frame
// (gatherSamplesTile), TemporalUpsample works at half resolution. A half-resolution pixel p stands for full-resolution
// pixel 2p: it takes that pixel's depth and normal, so every filter weight compares real G-buffer samples. A tile's
// geometry is likewise that of the pixel it sampled, read from the host's depth and normal rather than stored (SPEC
// §5's 10 MB for the gather's images: at 1920×1080 the tile irradiance and probe blend, the two half-resolution images,
// output and history, and the half-resolution confidence take 9.98 MB, 9.52 MiB).
//
// Confidence (SPEC §6.4): beside E, the gather carries how much the probes it used know of their surroundings — their
// known fraction (probeKnownFraction), weighted exactly as their light is. FinalGather writes it into the tile
// irradiance's alpha, and TemporalUpsample blends it with E's joint-bilateral weights into an R8 half-resolution image,
// with no history (see temporal_upsample.comp).
#ifndef SSVGI_SHARED_GATHER_INTERFACE_H
#define SSVGI_SHARED_GATHER_INTERFACE_H

#include "shared/probe_interface.h"

SSVGI_SHARED_BEGIN

SSVGI_CONSTANT(uint, kGatherTileSize, 4u);  // SPEC §4.6: 1 sample per 4×4 pixels

// FinalGather's leak weights (the talk's "Light Leaking" slides), in units of the chosen level's probe spacing where
// they are lengths.
SSVGI_CONSTANT(float, kGatherNormalBiasSpacings, 0.25f);  // "Normal Bias": the sample point moves off the surface
// "Normal Weight": a probe behind the surface (direction to it against the normal) keeps this much of its weight, so a
// point whose probes all lie behind it still gets their light rather than none.
SSVGI_CONSTANT(float, kGatherBackfacingProbeWeight, 0.02f);
// "Distance Weight": a probe whose traced distance toward the point is shorter than the point's distance probably sees a
// surface in between; its weight falls with the cube of the ratio, down to this floor.
SSVGI_CONSTANT(float, kGatherOccludedProbeWeight, 0.02f);
// A probe whose weight before the visibility test is at most this share of the 8 probes' is left out untraced.
SSVGI_CONSTANT(float, kGatherNegligibleProbeShare, 0.03f);
// Kept probes whose readings at the normal all lie within this share of their weighted mean (of its largest channel)
// are not traced for visibility: leaving any of them out would change E by less than that. The share trades traces for
// that bound on E; what it does to the figures and the cost: docs/QUALITY.md, "The gather's agreement at 20 %".
SSVGI_CONSTANT(float, kGatherAgreement, 0.2f);
// Levels blend over the last this-many probe spacings inside a level's boundary: the gather picks the coarser level
// with a probability that grows toward the boundary ("Noise + Light Gather Temporal Filter", the talk), so the seam
// becomes noise that the temporal filter averages.
SSVGI_CONSTANT(float, kGatherLevelBlendSpacings, 2.0f);

// TemporalUpsample's temporal filter: the weight of the new frame. 1/16 spans the 16 frames the gather's jitter needs to visit a tile's
// every pixel.
SSVGI_CONSTANT(float, kTemporalBlend, 1.0f / 16.0f);
// History whose geometry weight (summed over its bilinear taps) falls below this is rejected.
SSVGI_CONSTANT(float, kTemporalMinimumHistoryWeight, 0.25f);

// Binding slots of the gather passes (after GiFrame, kBindGiFrame, and the voxel scene's shared slots, which
// FinalGather binds for its visibility test).
SSVGI_CONSTANT(uint, kBindGatherConstants, kBindFirstPassSlot);            // GatherConstants (uniform)
SSVGI_CONSTANT(uint, kBindGatherDepth, kBindFirstPassSlot + 1u);           // the host's current depth (sampled)
SSVGI_CONSTANT(uint, kBindGatherNormal, kBindFirstPassSlot + 2u);          // the host's current world normal (sampled)
SSVGI_CONSTANT(uint, kBindGatherProbes, kBindFirstPassSlot + 3u);          // Probe[] (probe_interface.h)
SSVGI_CONSTANT(uint, kBindGatherTileIrradiance, kBindFirstPassSlot + 4u);  // rgba16f, 1/4: rgb E; a: confidence
SSVGI_CONSTANT(uint, kBindGatherHistory, kBindFirstPassSlot + 5u);         // rgba16f, 1/2: last output
SSVGI_CONSTANT(uint, kBindGatherOutput, kBindFirstPassSlot + 6u);          // rgba16f, 1/2: rgb E; a: depth
SSVGI_CONSTANT(uint, kBindGatherConfidence, kBindFirstPassSlot + 7u);      // r8, 1/2: confidence 0–1
SSVGI_CONSTANT(uint, kBindGatherDebugTarget, kBindFirstPassSlot + 8u);     // rgba32f: ConfidenceDebugView's image
SSVGI_CONSTANT(uint, kBindGatherTileProbeBlend, kBindFirstPassSlot + 9u);  // r8, 1/4: GatheredLight::probeBlend
// A tile's probe blend where its gather found no probe (GatheredLight::found false; FinalGather stores at least 1/255
// otherwise): the tile holds no light, and TemporalUpsample takes it as a tile whose sample saw nothing, not as light
// 0 from probes that start afresh.
SSVGI_CONSTANT(float, kTileFoundNoProbe, 0.0f);

// Where a probe level lies this frame.
struct GatherProbeLevel {
  ivec3 origin;   // world probe coordinate of the level's minimum corner
  float spacing;  // metres between its probes
};
SSVGI_CHECK_SIZE(GatherProbeLevel, 16);

// What the gather passes know of this frame beyond GiFrame (uniform buffer, one per frame in flight).
struct GatherConstants {
  mat4 historyViewProjection;  // the camera of the last dispatch, whose output is this frame's history
  mat4 historyInverseViewProjection;
  GatherProbeLevel probeLevels[kProbeLevels];
  ivec3 probesPerAxis;         // of every level
  int probesPerLevel;
  uvec2 tiles;                 // the tile irradiance's size (1/4 resolution)
  uvec2 halfSize;              // the half-resolution images' size
  uint frameIndex;
  uint historyUsable;          // 1 when the history is usable (same size, dispatched before)
  uint padding0;
  uint padding1;
  Sh2Rgb skyRadiance;          // FrameDesc::skyRadianceSh, for the sky part of the probes' light (readProbeIrradiance)
};
SSVGI_CHECK_SIZE(GatherConstants, 2 * 64 + 3 * 16 + 16 + 16 + 16 + 48);

// The tiles FinalGather samples in frame `frameIndex`: a checkerboard, the tiles whose x + y has the frame's parity,
// so that a frame gathers half the tiles (one sample per 32 pixels) and each tile is gathered every other frame. The
// temporal filter, which averages the jittered samples of many frames anyway, puts the two halves together; the
// upsampling of a frame reads that frame's half alone (gather_geometry.glsl).
SSVGI_INLINE uint gatherTileParity(uint frameIndex) { return frameIndex & 1u; }

SSVGI_INLINE bool gatherSamplesTile(uvec2 tile, uint frameIndex) {
  return ((tile.x + tile.y + gatherTileParity(frameIndex)) & 1u) == 0u;
}

// The tile FinalGather's thread `thread` gathers in frame `frameIndex`: thread x covers the sampled tile of columns
// 2x and 2x + 1 (FinalGather runs half as many threads across as there are tiles).
SSVGI_INLINE uvec2 gatherTileOfThread(uvec2 thread, uint frameIndex) {
  return uvec2(2u * thread.x + ((thread.y + gatherTileParity(frameIndex)) & 1u), thread.y);
}

// The tiles a frame samples lie on a square lattice turned by 45°, √2 tiles apart. In its own coordinates,
// (u, v) = ((x + y − p) / 2, (x − y − p) / 2) for tile (x, y) and the frame's parity p, they are the integer points,
// and TemporalUpsample's upsampling is bilinear there (gather_geometry.glsl).
SSVGI_INLINE vec2 sampledLatticeCoordinate(vec2 tileCoordinate, uint parity) {
  vec2 turned = vec2(tileCoordinate.x + tileCoordinate.y, tileCoordinate.x - tileCoordinate.y);
  return 0.5f * (turned - float(parity));
}

SSVGI_INLINE ivec2 tileAtLatticePoint(ivec2 point, uint parity) {
  return ivec2(point.x + point.y + int(parity), point.x - point.y);
}

// The pixel a tile samples in frame `frameIndex`, the same for every tile the frame gathers: the 4×4 Bayer order over
// the frame pairs, so that a tile's consecutive samples lie far apart and all 16 of its pixels are sampled in any 32
// consecutive frames (SPEC §4.6).
SSVGI_INLINE uvec2 gatherSampleOffset(uint frameIndex) {
  uint i = (frameIndex >> 1u) % 16u;
  // With i = b3 b2 b1 b0 in bits, this is the inverse of the index matrix [0 8 2 10; 12 4 14 6; 3 11 1 9; 15 7 13 5]:
  // 0→(0,0), 1→(2,2), 2→(2,0), 3→(0,2), 4→(1,1), …
  uint b0 = i & 1u, b1 = (i >> 1u) & 1u, b2 = (i >> 2u) & 1u, b3 = (i >> 3u) & 1u;
  return uvec2(2u * (b0 ^ b1) + (b2 ^ b3), 2u * b0 + b2);
}

SSVGI_SHARED_END

#endif
