// The probe radiance cache of SPEC §4.5 (the talk's "Part2 Indirect Light"): layouts, binding slots, constants and
// addressing shared by the probe shaders and the host.
//
// Three levels of probeGrid probes around the camera, spacing doubling per level. Probe (world probe coordinate) c of a
// level sits at c · spacing, so the levels nest (every probe of level l+1 coincides with one of level l) and the
// probes around a point are the corners of the grid cell holding it. Each level is addressed toroidally like the voxel
// volume (slot = c mod dimensions); a probe stores a tag of its world coordinate, so a slot that scrolled to another
// probe is recognised as stale and starts afresh (as bricks store their coordinate, SPEC §4.1).
#ifndef SSVGI_SHARED_PROBE_INTERFACE_H
#define SSVGI_SHARED_PROBE_INTERFACE_H

#include "shared/sampling.h"
#include "shared/sh.h"
#include "shared/voxel_interface.h"

SSVGI_SHARED_BEGIN

SSVGI_CONSTANT(uint, kProbeLevels, 3u);     // SPEC §4.5: 3 clipmap levels, one updated per frame
SSVGI_CONSTANT(uint, kProbeBlockSize, 4u);  // the CPU culls a level in blocks of 4×4×4 probes (one placement group)
SSVGI_CONSTANT(uint, kProbeTraceGroupSize, 32u);  // ProbeTrace: one workgroup per probe, one thread per ray
// ProbeRelocate, ProbeDilate: one thread per listed probe. Not a workgroup per probe, as ProbeTrace: on lavapipe a
// workgroup that meets a barrier costs more to start than these passes' work for most probes (docs/PERFORMANCE.md).
SSVGI_CONSTANT(uint, kProbeListGroupSize, 64u);
// The distance SH records hit distances up to this many spacings. The gather compares it with the distance from the
// probe to a point of one of the grid cells around it (at most √3 spacings); clamping keeps far hits and misses from
// swamping the low-order SH of a probe beside a wall.
SSVGI_CONSTANT(float, kProbeDistanceRangeSpacings, 2.0f);

// Binding slots of the probe passes (after the voxel scene's shared slots and the GiFrame uniform).
SSVGI_CONSTANT(uint, kBindProbeUpdate, kBindFirstPassSlot);         // ProbeUpdate (uniform)
SSVGI_CONSTANT(uint, kBindProbes, kBindFirstPassSlot + 1u);         // Probe[kProbeLevels · probes per level]
SSVGI_CONSTANT(uint, kBindProbeList, kBindFirstPassSlot + 2u);      // IndirectList of probe indices to trace
SSVGI_CONSTANT(uint, kBindProbeBlocks, kBindFirstPassSlot + 3u);    // the blocks offered, packed by packProbeBlock

// Probe::state, the probe's state word: bits 0–7 the history count m (SPEC §4.5, capped by
// Settings::probeHistoryCap ≤ 255); bits 8–17 the first of the 1024 ray directions its next update traces; bits 18–29
// its virtual offset (probeOffsetCode); bits 30–31 the placement state.
SSVGI_CONSTANT(uint, kProbeStateNeverTraced, 0u);
SSVGI_CONSTANT(uint, kProbeStateActive, 1u);
// Inside geometry and no way out within half a spacing (ProbeRelocate): traced from its grid position, so that it
// becomes active again when the geometry goes, but left out of gathers and filled by ProbeDilate (SPEC §4.5).
SSVGI_CONSTANT(uint, kProbeStateInvalid, 2u);

// The virtual offset (SPEC §4.5; the talk's "Virtual Offset") moves a probe in steps of 1/16 of its spacing, at most 7
// on each axis: always less than half a spacing, so a probe stays nearer its own grid position than any other's and
// the gather's trilinear weights keep their meaning. 4 bits per axis (two's complement); 6 cm steps at level 0.
SSVGI_CONSTANT(float, kProbeOffsetStepsPerSpacing, 16.0f);
SSVGI_CONSTANT(int, kProbeMaxOffsetSteps, 7);

// One probe, 48 bytes. Radiance SH2 (4 coefficients each, in sh.h's order) as half floats, two per uint, and the
// sky's visibility SH2 likewise. Distance and normal-dot SH2 are used only coarsely (the gather's distance weight,
// ProbeRelocate's sign test), so they are 8-bit fixed point (packProbeUnitSh; docs/ARCHITECTURE.md, "Probe memory").
// Read them through the accessors below, never through the fields.
struct Probe {
  uvec2 radianceRed;    // red radiance SH2, half floats
  uvec2 radianceGreen;
  uvec2 radianceBlue;
  uint distanceSh;      // hit distance SH2 (m, clamped, see above) over the level's distance range, packProbeUnitSh
  uint normalDotSh;     // normal-dot SH2 (dot(-ray, hit normal), +1 for a miss), packProbeUnitSh
  uint state;           // the state word (below)
  uint tag;             // bits 0–23: tag of its world probe coordinate (probeCoordinateTag); bits 24–31: the share of
                        // its rays that found something known (probeKnownFraction)
  uvec2 skyVisibility;  // SH2 of where its rays found the sky (1 there, 0 elsewhere), half floats: readProbeIrradiance
};
SSVGI_CHECK_SIZE(Probe, 48);

// What ProbePlacement and ProbeTrace need to know of this frame's update (uniform buffer, one per frame in flight).
struct ProbeUpdate {
  ivec3 originProbe;             // world probe coordinate of the updated level's minimum corner
  int level;
  ivec3 probesPerAxis;           // multiples of kProbeBlockSize
  int probesPerLevel;
  float spacing;                 // metres between the level's probes
  float rayLength;               // how far rays are traced, metres
  float distanceRange;           // the distance SH's clamp, metres
  float projectionWeight;        // the SH projection weight 4π / rays per probe (SPEC §2)
  uint raysPerProbe;
  uint historyCap;               // Settings::probeHistoryCap
  uint probeBudget;              // probes updated per frame at most
  uint placementSearchLevel;     // the occupancy level (2–4) whose cells ProbePlacement searches for voxels
  uint keepsReservoirs;          // 1 when this level keeps reservoirs (Settings::probeReservoirs, level 0 only):
                                 // ProbeTrace's pipeline (its kKeepsReservoirs)
  uint reservoirHistoryCap;      // their M cap (Settings::probeReservoirHistoryCap)
  uint frameIndex;               // seeds the reservoirs' random choices and the probes' dither
  float sampleClamp;             // Settings::probeSampleClamp (0: off)
  float changeThreshold;         // Settings::probeChangeThreshold (0: off)
  uint startsSharedRecovery;     // 1: every probe with a history starts a recovery (ProbeChangeTally)
  uint hasSkyMap;                // 1: rays that leave the voxel volume see FrameDesc::skyRadianceMap, not skyRadiance
  uint settledProbeInterval;     // Settings::settledProbeInterval (ProbePlacement)
  Sh2Rgb skyRadiance;            // the host's sky (FrameDesc::skyRadianceSh): what a ray that leaves the voxel volume
                                 // sees without the map
};
SSVGI_CHECK_SIZE(ProbeUpdate, 6 * 16 + 48);

SSVGI_INLINE uint packProbeState(uint historyCount, uint nextDirection, uint placement, uint offsetCode) {
  return historyCount | (nextDirection << 8u) | (offsetCode << 18u) | (placement << 30u);
}
// A probe at its grid position (no virtual offset).
SSVGI_INLINE uint packProbeState(uint historyCount, uint nextDirection, uint placement) {
  return packProbeState(historyCount, nextDirection, placement, 0u);
}
SSVGI_INLINE uint probeHistoryCount(uint state) { return state & 0xffu; }
SSVGI_INLINE uint probeNextDirection(uint state) { return (state >> 8u) & 0x3ffu; }
SSVGI_INLINE uint probeOffsetCode(uint state) { return (state >> 18u) & 0xfffu; }
SSVGI_INLINE uint probePlacement(uint state) { return state >> 30u; }

// An offset in steps (each component within ±kProbeMaxOffsetSteps) as the state word's 12 bits, and back.
SSVGI_INLINE uint packProbeOffset(ivec3 steps) {
  return uint(steps.x & 0xf) | (uint(steps.y & 0xf) << 4u) | (uint(steps.z & 0xf) << 8u);
}
SSVGI_INLINE ivec3 unpackProbeOffset(uint offsetCode) {
  ivec3 nibbles = ivec3(int(offsetCode & 0xfu), int((offsetCode >> 4u) & 0xfu), int(offsetCode >> 8u));
  return nibbles - 16 * ivec3(greaterThanEqual(nibbles, ivec3(8)));
}

// Where a probe's rays leave from and where a gather should place it: its grid position plus its virtual offset.
SSVGI_INLINE vec3 probeWorldPosition(ivec3 worldProbe, float spacing, uint state) {
  vec3 offset = vec3(unpackProbeOffset(probeOffsetCode(state))) * (spacing / kProbeOffsetStepsPerSpacing);
  return vec3(worldProbe) * spacing + offset;
}

// 8 bits of each axis of a world probe coordinate. A stale slot holds a probe a multiple of the dimensions away on
// some axis; it carries the same tag only when that distance is also a multiple of 256 probes (768 probes with the
// high tier's 48, 768 m at level 0).
SSVGI_INLINE uint probeCoordinateTag(ivec3 worldProbe) {
  return uint(worldProbe.x & 0xff) | (uint(worldProbe.y & 0xff) << 8u) | (uint(worldProbe.z & 0xff) << 16u);
}
SSVGI_CONSTANT(uint, kProbeTagMask, 0xffffffu);
SSVGI_CONSTANT(uint, kProbeKnownShift, 24u);
SSVGI_INLINE bool probeHoldsCoordinate(Probe probe, ivec3 worldProbe) {
  return (probe.tag & kProbeTagMask) == probeCoordinateTag(worldProbe);
}
// Unknown is not sky (SPEC §6.4): the share of a probe's rays, blended over its updates like its SH, that found a voxel
// or the sky through space a view has observed, rather than space no view has. 8 bits, rounded with a dither as
// packProbeUnitSh rounds.
SSVGI_INLINE float probeKnownFraction(Probe probe) { return float(probe.tag >> kProbeKnownShift) / 255.0f; }
SSVGI_INLINE uint packProbeTag(ivec3 worldProbe, float knownFraction, float dither) {
  uint known = min(uint(floor(clamp(knownFraction, 0.0f, 1.0f) * 255.0f + dither)), 255u);
  return probeCoordinateTag(worldProbe) | (known << kProbeKnownShift);
}

// Index of a probe within its level: its toroidal slot, linearised.
SSVGI_INLINE uint probeSlotIndex(ivec3 worldProbe, ivec3 dimensions) {
  return linearCellIndex(wrapCoordinate(worldProbe, dimensions), dimensions);
}

// The world coordinate of the probe in a slot: the one coordinate in [origin, origin + dimensions) that wraps to it.
SSVGI_INLINE ivec3 probeWorldCoordinate(uint slotIndex, ivec3 origin, ivec3 dimensions) {
  uint planeSize = uint(dimensions.x * dimensions.y);
  ivec3 slot = ivec3(int(slotIndex % uint(dimensions.x)), int((slotIndex / uint(dimensions.x)) % uint(dimensions.y)),
                     int(slotIndex / planeSize));
  return origin + wrapCoordinate(slot - origin, dimensions);
}

// Whether a slot holds this world probe, traced at least once: its history, offset and placement are this probe's (a
// slot that scrolled to another probe is stale).
SSVGI_INLINE bool probeSlotHolds(Probe probe, ivec3 worldProbe) {
  return probePlacement(probe.state) != kProbeStateNeverTraced && probeHoldsCoordinate(probe, worldProbe);
}

// Whether a probe's radiance may be read — by a gather, by a finer level starting a new probe, by ProbeDilate: the
// slot holds this world probe (its tag), the probe is active (not inside geometry) and it has been traced since it
// last started afresh (m > 0; a probe just moved by its virtual offset still holds what it saw from inside).
SSVGI_INLINE bool probeIsUsable(Probe probe, ivec3 worldProbe) {
  return probeHoldsCoordinate(probe, worldProbe) && probePlacement(probe.state) == kProbeStateActive &&
         probeHistoryCount(probe.state) > 0u;
}

// The 8 probes around a point of a level's grid — the corners of the grid cell that holds it — with their trilinear
// weights: `cell` is the cell's minimum corner, `fraction` where the point lies in it (0–1 per axis); corner i
// (0..7) is cell + (i & 1, (i >> 1) & 1, i >> 2). The gather and a new probe's start from the coarser level walk
// them alike: for (int corner = 0; corner < kProbeCellCorners; ++corner).
SSVGI_CONSTANT(int, kProbeCellCorners, 8);
struct ProbeCellCorner {
  ivec3 probe;   // world probe coordinate
  float weight;  // trilinear weight, Σ over the 8 corners = 1
};
SSVGI_CHECK_SIZE(ProbeCellCorner, 16);

SSVGI_INLINE ProbeCellCorner probeCellCorner(ivec3 cell, vec3 fraction, int corner) {
  ivec3 side = ivec3(corner & 1, (corner >> 1) & 1, corner >> 2);
  vec3 axisWeights = mix(vec3(1.0f) - fraction, fraction, vec3(side));
  return ProbeCellCorner(cell + side, axisWeights.x * axisWeights.y * axisWeights.z);
}

// The 26 neighbours of a probe in its level's grid (index 0..25; the probe itself, index 13 of the 3×3×3 block, is
// skipped). ProbeRelocate evaluates the SH along their directions, ProbeDilate reads them.
SSVGI_CONSTANT(uint, kProbeNeighbourCount, 26u);
SSVGI_INLINE ivec3 probeNeighbourOffset(uint neighbour) {
  uint cell = neighbour < 13u ? neighbour : neighbour + 1u;
  return ivec3(int(cell % 3u), int((cell / 3u) % 3u), int(cell / 9u)) - ivec3(1);
}

// ProbePlacement's dispatch: the blocks it places from, and whether they are those in view (their probes must reach
// into the frustum) or those beyond it.
struct ProbePlacementPush {
  uint firstBlock;  // into the list of blocks offered
  uint inView;      // 1: the blocks in view; 0: those beyond it
};
SSVGI_CHECK_SIZE(ProbePlacementPush, 8);

// A block of the CPU cull, in blocks from the level's minimum corner, 10 bits per axis.
SSVGI_INLINE uint packProbeBlock(uvec3 block) { return block.x | (block.y << 10u) | (block.z << 20u); }
SSVGI_INLINE uvec3 unpackProbeBlock(uint packed) {
  return uvec3(packed & 0x3ffu, (packed >> 10u) & 0x3ffu, packed >> 20u);
}

// Ray `ray` of an update that starts at direction `firstDirection` of the fixed set (SPEC §2): an update traces the
// next raysPerProbe directions, so a probe sees all kProbeRayDirectionCount after 1024 / raysPerProbe updates.
SSVGI_INLINE vec3 probeRayDirection(uint firstDirection, uint ray) {
  return haltonSphereDirection((firstDirection + ray) % kProbeRayDirectionCount);
}

// The turn of the direction set in an update of a probe that follows a change (a recovery, "Less lag" below): one
// uniformly random rotation per update of a level, the same for all its probes. A settled probe's estimate averages
// its updates' 32-direction subsets of the fixed set, which together cover the sphere evenly; a recovering probe's is
// its last update, and one subset alone is uneven in a way of its own (the share of its directions within 45° of
// straight up ranges from 0.06 to 0.22 over the 32 subsets) that every probe shares, since all walk the same subsets
// in step: the whole image's light rose and stalled with the subset they traced (docs/QUALITY.md, "The lag's steps are
// the direction subsets"). Turned at random, an update's estimate is unbiased on its own; shared by the level's probes,
// its error is smooth on screen, which the temporal filter hides.
SSVGI_CONSTANT(uint, kProbeRecoveryRotationSeed, 0x5bd1e995u);
SSVGI_INLINE vec4 probeRecoveryRotation(uint frameIndex, uint level) {
  return uniformRandomRotation(hashToUnitCube(uvec3(frameIndex, level, kProbeRecoveryRotationSeed)));
}

// SH2 with half-float coefficients, two per uint.
// The nearest half floats (nearestHalf): the probes' running average is stored in them.
SSVGI_INLINE uvec2 packSh2Half(vec4 coefficients) {
  vec4 stored = vec4(nearestHalf(finiteHalf(coefficients.x)), nearestHalf(finiteHalf(coefficients.y)),
                     nearestHalf(finiteHalf(coefficients.z)), nearestHalf(finiteHalf(coefficients.w)));
  return uvec2(packHalf2x16(vec2(stored.x, stored.y)), packHalf2x16(vec2(stored.z, stored.w)));
}
SSVGI_INLINE vec4 unpackSh2Half(uvec2 packed) {
  vec2 low = unpackHalf2x16(packed.x);
  vec2 high = unpackHalf2x16(packed.y);
  return vec4(low.x, low.y, high.x, high.y);
}

// No SH2 coefficient of a function within [−1, 1] exceeds 2√π = 4π·Y00 (band 1: √(3π) ≈ 3.07): the scale of the
// 8-bit coefficients of the normal-dot SH and of the distance SH over its range.
SSVGI_CONSTANT(float, kUnitSh2Bound, 3.5449077f);

// An SH2 of a function within [−1, 1] as four signed bytes (steps of 2√π/127, 0.8 % of the range). `dither` in [0, 1)
// rounds stochastically: ProbeTrace blends with α down to 1/(m+1), far below one step, and plain rounding would
// freeze the history; dithered rounding keeps its expectation exact.
SSVGI_INLINE uint packProbeUnitSh(vec4 coefficients, float dither) {
  ivec4 steps = ivec4(floor(clamp(coefficients / kUnitSh2Bound, vec4(-1.0f), vec4(1.0f)) * 127.0f + vec4(dither)));
  steps = clamp(steps, ivec4(-127), ivec4(127));
  return uint(steps.x & 0xff) | (uint(steps.y & 0xff) << 8u) | (uint(steps.z & 0xff) << 16u) |
         (uint(steps.w & 0xff) << 24u);
}
SSVGI_INLINE vec4 unpackProbeUnitSh(uint packed) {
  ivec4 bytes = ivec4(int(packed & 0xffu), int((packed >> 8u) & 0xffu), int((packed >> 16u) & 0xffu), int(packed >> 24u));
  bytes = bytes - 256 * ivec4(greaterThanEqual(bytes, ivec4(128)));
  return vec4(bytes) * (kUnitSh2Bound / 127.0f);
}

// How far a level's distance SH reaches: it records hit distances clamped to this (m).
SSVGI_INLINE float probeDistanceRange(float spacing) { return kProbeDistanceRangeSpacings * spacing; }

// The accessors of a probe's SH: radiance (W/(sr·m²)), hit distance (m) on a level of `spacing`, normal-dot, the
// sky's visibility.
SSVGI_INLINE Sh2Rgb probeRadianceSh(Probe probe) {
  return Sh2Rgb(unpackSh2Half(probe.radianceRed), unpackSh2Half(probe.radianceGreen), unpackSh2Half(probe.radianceBlue));
}
SSVGI_INLINE vec4 probeDistanceSh(Probe probe, float spacing) {
  return unpackProbeUnitSh(probe.distanceSh) * probeDistanceRange(spacing);
}
SSVGI_INLINE vec4 probeNormalDotSh(Probe probe) { return unpackProbeUnitSh(probe.normalDotSh); }
SSVGI_INLINE vec4 probeSkyVisibilitySh(Probe probe) { return unpackSh2Half(probe.skyVisibility); }
SSVGI_INLINE Probe makeProbe(Sh2Rgb radiance, vec4 skyVisibility, uint distanceSh, uint normalDotSh, uint state,
                             uint tag) {
  return Probe(packSh2Half(radiance.r), packSh2Half(radiance.g), packSh2Half(radiance.b), distanceSh, normalDotSh, state,
               tag, packSh2Half(skyVisibility));
}
// A round cap of directions about `axis` of half-angle cosine `cosine`, and its moments: its solid angle ∫dω, its
// first moment along the axis ∫(axis·ω)dω, and its second ∫ωωᵀdω = perpendicular·I + (alongAxis − perpendicular)·
// axis axisᵀ, with alongAxis = ∫(axis·ω)²dω = 2π(1 − cos³α)/3 and 2·perpendicular + alongAxis = ∫dω.
struct RoundCap {
  vec3 axis;
  float cosine;
  float solidAngle;
  float firstMoment;
  float alongAxis;
  float perpendicular;
};
SSVGI_INLINE RoundCap roundCap(vec3 axis, float cosine) {
  RoundCap cap;
  cap.axis = axis;
  cap.cosine = cosine;
  cap.solidAngle = 2.0f * kPi * (1.0f - cosine);
  cap.firstMoment = kPi * (1.0f - cosine * cosine);
  cap.alongAxis = 2.0f * kPi * (1.0f - cosine * cosine * cosine) / 3.0f;
  cap.perpendicular = 0.5f * (cap.solidAngle - cap.alongAxis);
  return cap;
}

// Where, on average, a surface of `normal` sees a round cap of sky: the cap's directions weighted by max(0, normal·ω),
// ∫ω·max(0, n·ω)dω / ∫max(0, n·ω)dω. Its light, linear in the direction as the host's SH2 sky is, L(ω) = k0 + k1·ω,
// reaches the surface as k0 + k1·(this point) per unit of the cap's irradiance. Where the cap lies wholly above the
// surface's horizon it is exact: (perpendicular·n + (alongAxis − perpendicular)·axis (axis·n)) / (π sin²α axis·n),
// from the cap's second moment (RoundCap). Past that, as the cap sinks below the horizon, the point moves on from
// where it was exact to the cap's edge point that sinks last; a cap wider than a hemisphere moves from the
// hemisphere's 2/3·axis towards the whole sphere's 2/3·n.
SSVGI_INLINE vec3 skyCapCentroid(RoundCap cap, vec3 normal) {
  vec3 axis = cap.axis;
  if (cap.cosine < 0.0f) {
    vec3 towards = mix(axis, normal, -cap.cosine);
    return (2.0f / 3.0f) * towards / max(length(towards), 1e-6f);
  }
  float cosine = dot(normal, axis);
  vec3 across = normal - axis * cosine;
  float acrossLength = length(across);
  vec3 tangent = acrossLength > 1e-6f ? across / acrossLength : vec3(0.0f);
  float capSine = sqrt(max(1.0f - cap.cosine * cap.cosine, 0.0f));
  float clampedCosine = max(cosine, capSine);
  float clampedSine = sqrt(max(1.0f - clampedCosine * clampedCosine, 0.0f));
  float capIrradiance = kPi * capSine * capSine * clampedCosine;  // ∫ n'·ω over the cap, n' the normal used
  if (!(capIrradiance > 0.0f)) return axis;
  vec3 wholeCapSeen =
      (axis * (cap.alongAxis * clampedCosine) + tangent * (cap.perpendicular * clampedSine)) / capIrradiance;
  vec3 lastPointSeen = axis * cap.cosine + tangent * capSine;  // where the cap sinks below the horizon last
  return mix(wholeCapSeen, lastPointSeen, clamp(0.5f * (capSine - cosine) / capSine, 0.0f, 1.0f));
}

// The irradiance a probe gives a surface of `normal` (SPEC §6.4's sky, read apart). Its sky is read from where its
// rays found it: the solid angle Ω (band 0 of the visibility) around their mean direction (band 1), as a uniform
// round cap — the SH2 of a cap of sky through an opening, read as broad light, gives a surface facing it about 3/4
// of its light. The mean direction's length tells how spread that sky is (a cap of half-angle α has (1 + cos α)/2,
// the most any region of its solid angle can have): a band along the horizon or two openings apart are read as the
// cap of that spread, dimmed to the solid angle found. The sky's radiance is the host's, linear in the direction as
// its SH2 is: the cap's light reaches a surface as the sky's radiance where the surface sees the cap on average
// (skyCapCentroid) — a clear sky brighter towards the sun lights the surfaces facing that way more. The rest of the
// probe's light (its surfaces) is read from the SH2 left when that sky is taken out: the visibility times the sky's
// constant part, and the cap's moments times its linear part.
SSVGI_INLINE vec3 readProbeIrradiance(Probe probe, vec3 normal, Sh2Rgb skyRadianceSh) {
  Sh2Rgb total = probeRadianceSh(probe);
  vec4 visibility = probeSkyVisibilitySh(probe);
  float solidAngle = clamp(visibility.x / kSh2Band0Basis, 0.0f, 4.0f * kPi);
  if (!(solidAngle > 1e-3f)) return sh2IrradianceWithoutRinging(total, normal);
  vec3 meanDirectionSum = vec3(visibility.w, visibility.y, visibility.z);  // Ω · mean direction · Y1's factor
  float meanLength = length(meanDirectionSum);
  vec3 axis = meanLength > 1e-6f ? meanDirectionSum / meanLength : vec3(0.0f, 1.0f, 0.0f);
  float meanCosine = meanLength / (kSh2Band1Basis * solidAngle);
  float spreadCosine = clamp(min(2.0f * meanCosine - 1.0f, 1.0f - solidAngle / (2.0f * kPi)), -1.0f, 1.0f);
  RoundCap spread = roundCap(axis, spreadCosine);
  float spreadSolidAngle = max(spread.solidAngle, solidAngle);
  float dimming = solidAngle / spreadSolidAngle;
  // The cap's moments, dimmed: ∫ (axis·ω) dω and the parts of ∫ ωωᵀ dω.
  float firstMoment = dimming * spread.firstMoment;
  float perpendicular = dimming * spread.perpendicular;
  float axial = dimming * (spread.alongAxis - spread.perpendicular);
  vec3 seenAt = skyCapCentroid(spread, normal);
  vec4 skyChannels[3] = {skyRadianceSh.r, skyRadianceSh.g, skyRadianceSh.b};
  vec4 totalChannels[3] = {total.r, total.g, total.b};
  vec3 skyIrradiance = vec3(0.0f);
  for (int channel = 0; channel < 3; ++channel) {
    vec4 sky = skyChannels[channel];
    float constant = kSh2Band0Basis * sky.x;
    vec3 slope = kSh2Band1Basis * vec3(sky.w, sky.y, sky.z);
    // SH2 rings below zero opposite a bright sky; negative radiance is not light.
    if (!(constant + dot(slope, axis) > 0.0f)) continue;
    float slopeAlongAxis = dot(slope, axis);
    vec3 band1 = kSh2Band1Basis * (slope * perpendicular + axis * (axial * slopeAlongAxis));
    vec4 skyPart = visibility * constant + vec4(kSh2Band0Basis * firstMoment * slopeAlongAxis, band1.y, band1.z, band1.x);
    // No more than all of the probe's light (the two SH2 are blended and dilated alike, but rounded apart, and the
    // host's sky may have changed since the probe saw it).
    float share = skyPart.x > totalChannels[channel].x ? max(totalChannels[channel].x, 0.0f) / skyPart.x : 1.0f;
    totalChannels[channel] -= skyPart * share;
    skyIrradiance[channel] = max(constant + dot(slope, seenAt), 0.0f) * share;
  }
  Sh2Rgb surfaces = Sh2Rgb(totalChannels[0], totalChannels[1], totalChannels[2]);
  return sh2IrradianceWithoutRinging(surfaces, normal) +
         skyIrradiance * dimming * uniformConeIrradiance(spreadSolidAngle, dot(normal, axis));
}

// ---------------------------------------------------------------------------------------------------------------------
// Reservoirs (SPEC §4.5 "Stability"; the talk's ReSTIR part): "one reservoir cannot describe a distribution over the
// sphere — stratify: split the sphere evenly into cells, one reservoir per cell". 8 strata: the two hemispheres of z
// times four quadrants of azimuth, i.e. 2×4 equal cells of the unit square that uniformSphereDirection maps
// area-preservingly onto the sphere. Each stratum has its own fixed low-discrepancy set of 128 directions (the Halton
// (2,3) points scaled into its cell), 1024 in all, as SPEC §2's set.
SSVGI_CONSTANT(uint, kProbeStrataZ, 2u);
SSVGI_CONSTANT(uint, kProbeStrataAzimuth, 4u);
SSVGI_CONSTANT(uint, kProbeStrata, 8u);
SSVGI_CONSTANT(uint, kProbeStratumDirectionCount, 128u);
SSVGI_CONSTANT(float, kProbeStratumSolidAngle, 4.0f * kPi / 8.0f);
SSVGI_CONSTANT(uint, kBindProbeReservoirs, kBindFirstPassSlot + 4u);  // uint[probes of level 0 · kProbeStrata]
SSVGI_CONSTANT(uint, kBindProbeChanges, kBindFirstPassSlot + 5u);     // uint[kProbeLevels · probes per level]
SSVGI_CONSTANT(uint, kBindProbeChangeTally, kBindFirstPassSlot + 6u);  // ProbeChangeTally of this frame
SSVGI_CONSTANT(uint, kBindProbeSkyMap, kBindFirstPassSlot + 7u);  // FrameDesc::skyRadianceMap (sampled; ProbeTrace)

SSVGI_INLINE uvec2 probeStratumCell(uint stratum) { return uvec2(stratum % kProbeStrataZ, stratum / kProbeStrataZ); }

// Direction `index` (0..127) of a stratum's set: uniform over the stratum as the index runs through the set.
SSVGI_INLINE vec3 probeStratumDirection(uint stratum, uint index) {
  vec2 cell = vec2(probeStratumCell(stratum));
  return uniformSphereDirection((cell + halton23(index)) / vec2(float(kProbeStrataZ), float(kProbeStrataAzimuth)));
}

// A stratum's bounds in the coordinates uniformSphereDirection maps area-preservingly: x, y the interval of z (z0 < z1),
// z, w that of the azimuth φ. dω = dz·dφ over it.
SSVGI_INLINE vec4 probeStratumBounds(uint stratum) {
  uvec2 cell = probeStratumCell(stratum);
  float z1 = 1.0f - 2.0f * float(cell.x) / float(kProbeStrataZ);
  float azimuthWidth = 2.0f * kPi / float(kProbeStrataAzimuth);
  return vec4(z1 - 2.0f / float(kProbeStrataZ), z1, azimuthWidth * float(cell.y), azimuthWidth * float(cell.y + 1u));
}

// ∫ √(1−z²) dz = (z√(1−z²) + asin z) / 2: the radius of the direction, integrated over z.
SSVGI_INLINE float probeStratumRadiusIntegral(float z) { return 0.5f * (z * sqrt(max(0.0f, 1.0f - z * z)) + asin(z)); }

// ∫_s ω dω over a stratum, analytically, with ω = (√(1−z²)·cos φ, √(1−z²)·sin φ, z).
SSVGI_INLINE vec3 probeStratumDirectionIntegral(uint stratum) {
  vec4 bounds = probeStratumBounds(stratum);
  float radius = probeStratumRadiusIntegral(bounds.y) - probeStratumRadiusIntegral(bounds.x);
  return vec3(radius * (sin(bounds.w) - sin(bounds.z)), radius * (cos(bounds.z) - cos(bounds.w)),
              0.5f * (bounds.y * bounds.y - bounds.x * bounds.x) * (bounds.w - bounds.z));
}

// The mean of the SH2 basis over a stratum, Ȳ_s = (1/Ω_s)∫_s Y dω: the basis is linear in the direction, so it is the
// basis of the stratum's mean direction vector.
SSVGI_INLINE vec4 probeStratumMeanBasis(uint stratum) {
  return sh2Basis(probeStratumDirectionIntegral(stratum) / kProbeStratumSolidAngle);
}

// C = ∫_s ω ωᵀ dω − (∫_s ω)(∫_s ω)ᵀ / Ω_s over a stratum, analytically (for probeStratumDeviation): its entries
// integrate z², 1−z² and z√(1−z²) over z (the last to −(1−z²)^{3/2}/3) times cos², sin², cos·sin, cos and sin over φ.
SSVGI_INLINE mat3 probeStratumCovariance(uint stratum) {
  vec4 bounds = probeStratumBounds(stratum);
  float z0 = bounds.x, z1 = bounds.y, phi0 = bounds.z, phi1 = bounds.w;
  float zSquared = (z1 * z1 * z1 - z0 * z0 * z0) / 3.0f;
  float radiusSquared = (z1 - z0) - zSquared;
  float r0 = max(0.0f, 1.0f - z0 * z0), r1 = max(0.0f, 1.0f - z1 * z1);
  float zRadius = (r0 * sqrt(r0) - r1 * sqrt(r1)) / 3.0f;
  float width = phi1 - phi0;
  float cosSquared = 0.5f * width + 0.25f * (sin(2.0f * phi1) - sin(2.0f * phi0));
  float sinSquared = width - cosSquared;
  float cosSin = 0.5f * (sin(phi1) * sin(phi1) - sin(phi0) * sin(phi0));
  vec3 mean = probeStratumDirectionIntegral(stratum);
  mat3 second = mat3(radiusSquared * cosSquared, radiusSquared * cosSin, zRadius * (sin(phi1) - sin(phi0)),
                     radiusSquared * cosSin, radiusSquared * sinSquared, zRadius * (cos(phi0) - cos(phi1)),
                     zRadius * (sin(phi1) - sin(phi0)), zRadius * (cos(phi0) - cos(phi1)), zSquared * width);
  return second - outerProduct(mean, mean) / kProbeStratumSolidAngle;
}

// ∫_s f·(Y − Ȳ_s) dω for an SH2 function f (coefficients in SH order) over the stratum whose probeStratumCovariance is
// `covariance`: the part of f's projection onto the basis that lies in the stratum beyond what its mean over the
// stratum gives. f = a + b·ω and ∫_s (Y − Ȳ_s) = 0, so only b counts: band 1 gets Y1 · (C·b).
SSVGI_INLINE vec4 probeStratumDeviation(mat3 covariance, vec4 coefficients) {
  vec3 slope = kSh2Band1Basis * vec3(coefficients.w, coefficients.y, coefficients.z);  // b, in x, y, z
  vec3 band1 = kSh2Band1Basis * (covariance * slope);
  return vec4(0.0f, band1.y, band1.z, band1.x);
}

// A reservoir in one uint: bits 0–15 the mean weight w̄ = Σw/M of the candidates it stands for (half float: a
// luminance times steradians), bits 16–22 the index of its sample in the stratum's direction set, bits 24–31 M
// (candidates seen, at most 255). All zero: empty.
SSVGI_INLINE uint packProbeReservoir(float meanWeight, uint sampleIndex, uint count) {
  return SSVGI_HALF_BITS(meanWeight) | (sampleIndex << 16u) | (count << 24u);
}
SSVGI_INLINE float probeReservoirMeanWeight(uint reservoir) { return SSVGI_HALF_FLOAT(reservoir & 0xffffu); }
SSVGI_INLINE uint probeReservoirSample(uint reservoir) { return (reservoir >> 16u) & 0x7fu; }
SSVGI_INLINE uint probeReservoirCount(uint reservoir) { return reservoir >> 24u; }

// The reservoirs' target p̂: luminance (Rec. 709), the talk's "p(x) = sample luminance".
SSVGI_INLINE float probeSampleLuminance(vec3 radiance) { return rec709Luminance(radiance); }

// ---------------------------------------------------------------------------------------------------------------------
// Less lag (SPEC §6.2): each probe keeps, beside its SH, in its word of the change buffer (packProbeChange): the mean
// luminance of its updates' rays but the brightest eighth (the trimmed mean T, blended as its SH), and the mean
// square of how far an update's T strays from that history H, d = (T − H) / (T + H). An update with d² beyond
// Settings::probeChangeThreshold² times that is a change, not noise: the probe's history count shrinks in proportion,
// so that a light switched on is followed within a few updates. Trimmed, because a probe's noise is mostly a few bright
// rays — the small emitter or sun patch that one ray in thirty finds — while a light switched on or off, or a wall
// moved, changes what most of its rays see.
SSVGI_CONSTANT(uint, kProbeChangeTrimFraction, 8u);
// Its ordinary noise is taken as at least this variance of d (5 % either way): a still probe may tell 32 rays apart
// from its history by less, and changes smaller than threshold × 5 % are left to the plain blend.
SSVGI_CONSTANT(float, kProbeChangeVarianceFloor, 0.0025f);
// Below this history count the blend weight 1/(m+1) is large anyway, and the variance has too few updates.
SSVGI_CONSTANT(uint, kProbeChangeMinimumHistory, 4u);
// Light that keeps coming: after a switch the first bounce arrives at once, the later ones in steps too small for one
// update to tell from noise, and the history would trail them at its own pace — α = 1/(m+1) with m about 10 to 30,
// for every bounce in turn. Evidence of a drift is summed over updates instead (Page's CUSUM): `drift` adds each
// update's deviation in standard deviations less kProbeDriftAllowance, on the side it leans, and never crosses zero
// but to start again on the other. Noise wanders back to zero; a history that falls behind light that keeps growing
// strays further each update and climbs. Past kProbeDriftLimit deviations it starts a recovery: for
// kProbeChangeRecoveryUpdates updates the history count is kProbeChangeRecoveryHistory — each update is taken whole
// (α = 1), so that every bounce goes round voxel → probe → voxel at the pace of the probes' updates, not of their
// blend — and the update's directions are turned (probeRecoveryRotation), so the probe follows the light while it
// grows (or fades). The allowance is one deviation because a smaller one shortened the lag further but let noise start
// recoveries in still scenes, which flicker (docs/QUALITY.md, "Drift summed over updates").
SSVGI_CONSTANT(float, kProbeDriftAllowance, 1.0f);
SSVGI_CONSTANT(float, kProbeDriftLimit, 4.0f);
SSVGI_CONSTANT(uint, kProbeChangeRecoveryUpdates, 15u);
SSVGI_CONSTANT(uint, kProbeChangeRecoveryHistory, 0u);
// The drift is stored in steps of this many deviations (its magnitude in 3 bits, below the limit).
SSVGI_CONSTANT(float, kProbeDriftStep, kProbeDriftLimit / 7.0f);

// A change many probes see at once is not their noise. A light switched on cuts the history of a fifth of the probes
// an update traces, the probes near it; by chance a still scene's cuts reach about one probe in a hundred. After the
// first bounce the later ones come in steps too small for any probe to tell from its noise, and each probe would trail
// them at its own pace, bounce after bounce. So ProbeTrace counts, each frame, the probes that can tell (a history of
// at least kProbeChangeMinimumHistory updates) and those whose history a large change cut; where at least
// Settings::probeSharedChangeShare of at least kProbeSharedChangeMinimumProbes were cut, ProbeVolume has every probe
// updated in the next kProbeLevels frames (an update of each level) start a recovery, as a drift does
// (startsSharedRecovery): the whole loop then follows the light at α = 1 for kProbeChangeRecoveryUpdates updates.
//
// A drift many probes share is not their noise either. Where light comes round the loop bounce after bounce — the first
// frames of a view, a hall lit through openings in its roof whose later bounces are most of its light — every probe's
// history trails light that keeps growing by a step too small for its own drift sum to tell, and a window of about the
// history cap (32 updates, 96 frames) makes each bounce take that long again. So ProbeTrace also sums, over the watched
// probes, each update's leaning (probeUpdateLeaning) and its square, and the share of its known rays' light that did
// not come round the loop (direct light and sky: the direct share s), in steps of 1/kProbeLeaningScale. Where the loop
// feeds back a share 1 − s of the light, an update T of a probe whose history H falls a share G short of the loop's
// fixed point leans by T − H = s·G·H: a lean tells the gap only with the direct share, and a hall whose light is mostly
// bounced can be far from its end with a lean the size of a sunlit courtyard's last percent (docs/QUALITY.md, "The
// loop's gap, not its lean"). ProbeVolume pools the tallies of the last kProbeSharedDriftWindow frames — rounds of an
// update of each level, each with its own 32 directions, which the probes of a level share (so one frame's mean leans
// now and then in a still scene) — and where their mean leaning is toward more light by more than
// kProbeSharedDriftErrors standard errors and tells a gap 2·lean / s above kProbeSharedDriftGapFloor, it holds the
// history cap of each update at about 1/gap updates, between kProbeSharedDriftShortestHistoryCap and
// kProbeSharedDriftHistoryCap, and lets no probe sit out, for as long as the window still leans by
// kProbeSharedDriftHoldErrors and tells such a gap: the loop goes round at the pace of that shorter window until the
// probes no longer lean, and the full window then averages their noise away again. A small room's few probes tell its
// lean by four standard errors only now and then, however far it still has to go (docs/QUALITY.md, "A drift followed
// while it lasts"). A history 12 % or more short of its end takes a window of 8 updates, one 6 % short 16: a hall whose
// light is mostly bounced gets there sooner (docs/QUALITY.md, "The loop's gap, not its lean"). Not 4: the hall without
// the capture, many of whose rays are unknown, went blotchy (its error twice as large).
struct ProbeChangeTally {
  uint watchedProbes;   // traced with a history of at least kProbeChangeMinimumHistory, change detection on
  uint cutProbes;       // of those, whose history a large change cut
  uint leaningProbes;   // of those, the probes whose leaning is summed: with a history of some light, no reservoirs
  int leaningSum;       // Σ probeUpdateLeaning · kProbeLeaningScale over them, each rounded to the nearest step
  uint leaningSquares;  // Σ probeUpdateLeaning² · kProbeLeaningScale alike
  uint directShareSum;  // Σ s · kProbeLeaningScale alike: the share of the known rays' light that is direct or sky
};
SSVGI_CHECK_SIZE(ProbeChangeTally, 24);
SSVGI_CONSTANT(uint, kProbeSharedChangeMinimumProbes, 32u);
SSVGI_CONSTANT(float, kProbeLeaningScale, 1024.0f);  // leanings ≤ 4: squares of 2^18 probes fit in 32 bits
SSVGI_CONSTANT(float, kProbeSharedDriftErrors, 4.0f);     // to start following a drift
SSVGI_CONSTANT(float, kProbeSharedDriftHoldErrors, 1.0f);  // to go on following it
SSVGI_CONSTANT(float, kProbeSharedDriftGapFloor, 0.05f);  // histories 5 % short of the loop's fixed point
SSVGI_CONSTANT(uint, kProbeSharedDriftWindow, 9u);        // frames: three rounds of the three levels
SSVGI_CONSTANT(uint, kProbeSharedDriftHistoryCap, 16u);
SSVGI_CONSTANT(uint, kProbeSharedDriftShortestHistoryCap, 8u);
// How far an update T leans from the history H of a probe: (T − H) / 2H, half its relative change, at most
// kProbeLeaningCap. Divided by the history alone, so that noise leans it neither way: a history that is the mean of
// past updates gives it a mean of zero whatever the spread of T. (d = (T − H)/(T + H) leans toward less light under
// noise, and d + d², which takes that back to the second order, leaned by about 0.02 in still scenes where updates
// often meet no light: T = 0 gives d + d² = 0 where its share of the truth is −1/2.) The cap bounds the sums.
SSVGI_CONSTANT(float, kProbeLeaningCap, 4.0f);
SSVGI_INLINE float probeUpdateLeaning(float update, float history) {
  return min((update - history) / (2.0f * history), kProbeLeaningCap);
}

// A probe's word of the change buffer: bits 0–15 the trimmed mean H (half float); bits 16–23 the rms of d, √(mean
// d²), in 8-bit fixed point over [0, 1] (|d| ≤ 1), rounded with `dither` as packProbeUnitSh rounds (the variance
// blends with α down to 1/(m+1), below one step); bits 24–27 the updates left of a recovery; bits 28–30 the drift's
// magnitude in kProbeDriftSteps (rounded with the same dither), bit 31 its sign.
struct ProbeChange {
  float mean;
  float variance;
  uint recoveryUpdates;
  float drift;  // in standard deviations; negative: the light fades
};
SSVGI_INLINE uint packProbeChange(ProbeChange change, float dither) {
  uint deviation = min(uint(floor(sqrt(clamp(change.variance, 0.0f, 1.0f)) * 255.0f + dither)), 255u);
  uint drift = min(uint(floor(min(abs(change.drift), kProbeDriftLimit) / kProbeDriftStep + dither)), 7u);
  return SSVGI_HALF_BITS(min(change.mean, 65504.0f)) | (deviation << 16u) | (min(change.recoveryUpdates, 15u) << 24u) |
         (drift << 28u) | (change.drift < 0.0f ? 1u << 31u : 0u);
}
SSVGI_INLINE ProbeChange unpackProbeChange(uint word) {
  float deviation = float((word >> 16u) & 0xffu) / 255.0f;
  ProbeChange change;
  change.mean = SSVGI_HALF_FLOAT(word & 0xffffu);
  change.variance = deviation * deviation;
  change.recoveryUpdates = (word >> 24u) & 0xfu;
  change.drift = float((word >> 28u) & 0x7u) * kProbeDriftStep * ((word >> 31u) != 0u ? -1.0f : 1.0f);
  return change;
}
// The drift sum after an update that strays by `deviations` standard deviations (Page's CUSUM, one side at a time):
// on the side it leans, down to zero; from zero, on whichever side the update leans past the allowance.
SSVGI_INLINE float accumulateProbeDrift(float drift, float deviations) {
  float leaning = drift >= 0.0f ? max(drift + deviations - kProbeDriftAllowance, 0.0f)
                                : min(drift + deviations + kProbeDriftAllowance, 0.0f);
  if (leaning != 0.0f) return leaning;
  if (deviations > kProbeDriftAllowance) return deviations - kProbeDriftAllowance;
  if (deviations < -kProbeDriftAllowance) return deviations + kProbeDriftAllowance;
  return 0.0f;
}
// The mean radiance over the sphere of an SH2, as luminance: band 0 over 4π·Y00.
SSVGI_INLINE float probeMeanLuminance(Sh2Rgb radiance) {
  return probeSampleLuminance(vec3(radiance.r.x, radiance.g.x, radiance.b.x)) / (4.0f * kPi * kSh2Band0Basis);
}

SSVGI_SHARED_END

#endif
