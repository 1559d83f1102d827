#version 450
// ProbeTrace with UpdateReservoirs (SPEC §4 step 8, §4.5; the talk's "Probe Light", GatherRadianceFromVoxelScene and
// UpdateReservoirPool): for each listed probe, one thread per ray, traced through the voxels from the probe. A hit gives
// the voxel's radiance (black from behind), a miss the sky's: the sky is thereby occluded by geometry ("sky visibility
// matters", the talk). The samples are projected onto SH2 (SPEC §2) — radiance, hit distance and normal-dot — summed
// across the workgroup and blended into the probe's history with α = 1/(m+1). Rays leave from the probe's position plus
// its virtual offset (ProbeRelocate). A new probe starts from the coarser level (SPEC §4.5; the talk's fix for the
// flicker of new probes while moving: "initialise from the higher-level probe volume").
//
// Without reservoirs (Settings::probeReservoirs off, and levels 1 and 2 always) the rays are the next raysPerProbe of
// the fixed 1024 directions, turned by the update's random rotation while the probe follows a change
// (probeRecoveryRotation). With them (level 0) the sphere is split into kProbeStrata strata, each with a reservoir
// (probe_interface.h); per stratum, raysPerProbe/8 − 1 rays are the next directions of its own Halton set (uniform
// candidates) and the last one re-traces the direction its reservoir holds (ray guiding: a bright direction found
// before keeps being sampled). The reservoir update is merged into this pass rather than being a pass of its own: it
// needs every ray's radiance, which only this workgroup has — a separate UpdateReservoirs would store 32 rays' radiance
// for 4096 probes (≈ 1.5 MB) that SPEC §5's 30 MB cannot spare, or trace them again.
//
// The reservoir update (weighted reservoir sampling with temporal reuse, Bitterli et al. 2020): the stored reservoir
// (y, w̄, M) — w̄ the mean weight of the candidates it stands for — counts as min(M, cap) candidates of weight w̄, then
// each candidate x adds w = p̂(x)/p(x), p = 1/Ω_s, p̂ its luminance (the talk: "p(x) = sample luminance"); the kept
// sample y' is drawn in proportion to w, and W = Σw / (M·p̂(y')) is its unbiased contribution weight. The estimate of
// the stratum's SH integral I_s = ∫_s L·Y dω (per colour channel) is then
//     Î_s = L(y')·W·Ȳ_s + (Ω_s/c)·Σ_i (L(x_i) − H(x_i))·(Y(x_i) − Ȳ_s) + ∫_s H·(Y − Ȳ_s) dω,   Ȳ_s = (1/Ω_s)∫_s Y dω,
// where H is the probe's radiance SH before this update (zero for a probe that starts afresh). I_s = Ȳ_s·∫_s L +
// ∫_s L·(Y − Ȳ_s) exactly. The first part comes from the reservoir: L(y')·W is a mean over up to cap candidates of
// several updates, not over this update's few rays, and it carries the stratum's total radiance — the part that
// flickers when few rays find a small bright source. Its expectation is ∫_s L where the light holds still (the
// defining property of W; p̂ = 0 only where L = 0, where there is nothing to miss); where it changes, the reused
// candidates' weights are from the updates that drew them, so the reservoir lags, by no more than the probe's history
// (the bound on M below). The old weights are not re-weighted by the re-traced ray's radiance this frame, as ReSTIR
// does with an exact target: a voxel's radiance is itself an estimate, and a sample kept because it was bright when
// drawn is, this frame, on average less bright, so re-weighting by it biased every reservoir low (cornell's probes
// came out too dark: docs/QUALITY.md, "Probe stability") and passed that one voxel's noise on to the whole stratum.
// The re-traced ray still gives L(y')/p̂(y'), the colour, and a kept sample that has gone dark empties its reservoir
// (what it stood for is gone). The second part, by the c uniform candidates, is stratified Monte Carlo with H as
// control variate, whose own integral is exact (probeStratumDeviation); H is fixed before the candidates are drawn, so
// it changes only the variance. It is left with the way the light varies across the stratum — band 1, which E(n)
// along the axes mostly depends on — and without the control variate 3 candidates per stratum do worse there than
// the plain 32 rays (docs/QUALITY.md, "Probe stability"). Under constant radiance L·W = L·Ω_s exactly, H converges to
// the constant, and the estimate is the plain stratified one, so a uniform sky converges to the analytic SH either way.
//
// The luminance clamp (Settings::probeSampleClamp; the talk: "limit the current frame's brightness by the history's
// maximum"): a candidate's radiance enters the estimate scaled down to at most clamp × the brightest direction the
// probe's reservoirs hold (their re-traced rays, this frame), and the reservoir in full: a bright direction found for
// the first time raises the maximum by the next update, so the clamp only cuts a sudden outlier's first update.
#include "gi/voxels/voxel_trace.glsl"
#include "gi/work_counting.glsl"
#include "shared/probe_interface.h"
#include "shared/sky_map.h"

layout(local_size_x = kProbeTraceGroupSize) in;
// Whether the updated level keeps reservoirs (ProbeUpdate::keepsReservoirs, by which ProbeTrace::record picks the
// pipeline): a pipeline of its own, since lavapipe would run the reservoirs' code for every probe, taken or not.
layout(constant_id = 0) const bool kKeepsReservoirs = false;

layout(binding = kBindProbeUpdate, std140) readonly buffer ProbeUpdateBlock { ProbeUpdate update; };
layout(binding = kBindProbes) buffer Probes { Probe probes[]; };
layout(binding = kBindProbeList) readonly buffer ProbeList {
  IndirectList list;
  uint listedProbes[];
};
// One reservoir per stratum of every probe of level 0 (probe_interface.h); read and written only when the updated
// level keeps reservoirs.
layout(binding = kBindProbeReservoirs) buffer Reservoirs { uint reservoirs[]; };
layout(binding = kBindProbeChanges) buffer Changes { uint changes[]; };
layout(binding = kBindProbeChangeTally) buffer ChangeTally { ProbeChangeTally tally; };
// The host's sky map where it gives one (update.hasSkyMap; bound but not read without).
layout(binding = kBindProbeSkyMap) uniform sampler2D skyMap;

// Per thread: its sample times the basis, for the SH2 of a probe: radiance, distance, normal-dot.
shared Sh2Rgb radianceSums[kProbeTraceGroupSize];
shared vec4 distanceSums[kProbeTraceGroupSize];
shared vec4 normalDotSums[kProbeTraceGroupSize];
shared vec4 skyVisibilitySums[kProbeTraceGroupSize];  // where the rays found the sky (readProbeIrradiance)
// With reservoirs: each ray's radiance, for the reservoir update of its stratum, and the factor the clamp scales it by
// in the estimate (1: not clamped).
shared vec3 rayRadiance[kProbeTraceGroupSize];
shared float clampScale[kProbeTraceGroupSize];
// The luminance of each ray but the brightest eighth, over their count: summed, the update's trimmed mean, which
// "Less lag" watches (shared/probe_interface.h).
shared float trimmedLuminance[kProbeTraceGroupSize];
// The history count this update blends with (followChange), for every thread: the reservoirs forget as much.
shared uint blendedHistoryCount;
// Unknown is not sky (SPEC §6.4): what each ray found (below), the light of those that met a surface less its direct
// part, how many found something known and the radiance the rays into unobserved space stand for (averageKnownRays);
// and what the probe holds — its history, or, for a probe that starts afresh, the coarser level's radiance it starts
// from (black without one), which it keeps where none of its rays found anything known.
const uint kRayFoundSky = 0u;
const uint kRayMetSurface = 1u;
const uint kRayUnknownInSpace = 2u;          // it crossed space no view has observed and met nothing
const uint kRayUnknownBesideSurface = 3u;    // it ended at unobserved voxels beside a seen surface (voxel_trace.glsl),
                                             // and stands for that surface's light
shared uint rayFound[kProbeTraceGroupSize];
shared vec3 rayIndirectRadiance[kProbeTraceGroupSize];
shared uint knownRays;
// What a ray into unobserved space stands for (averageKnownRays): its radiance and its share of sky, in each half of
// the sphere (0: below the horizon, 1: above).
shared uint rayHalf[kProbeTraceGroupSize];
shared vec3 knownMeanWithoutDirect[2];
shared float knownSkyShare[2];
shared float knownDirectShare;  // of the known rays' light, the share not relit from the probes: direct and sky
shared vec4 heldSkyVisibility;
shared Sh2Rgb heldRadiance;
shared bool startsFromCoarserLevel;
// The workgroup's rays and their reads, summed here on a frame that counts its work, then added once for the probe.
shared uint rayCount;
shared uint rayReads;

vec3 skyRadiance(vec3 direction) {
  if (update.hasSkyMap != 0u)
    return finiteHalf(max(textureLod(skyMap, skyMapCoordinates(direction), 0.0).rgb, vec3(0.0)));
  // SH2 rings below zero opposite a bright sky; negative radiance is not light.
  return max(sh2Evaluate(update.skyRadiance, sh2Basis(direction)), vec3(0.0));
}

// What a new probe of this level starts from: the radiance of the coarser level at its position, trilinear over the
// coarser probes around it that are usable, renormalised. Trilinear rather than nearest: it is what a gather reads
// there, so a probe that appears continues the light that was shown before it, and the levels nest, so half the
// weights are zero (a probe on a coarser probe takes exactly that probe's value). False where no coarser probe around
// it is usable, and always on the coarsest level: the probe then starts from its first trace alone. A coarser probe
// with a voxel between it and this one is left out: it may stand on the other side of a wall (`ssvgi scenario leak`).
// False too for a probe that does not start afresh (`startsAfresh`).
bool coarserLevelRadiance(ivec3 probe, vec3 position, bool startsAfresh, out Sh2Rgb radiance, out vec4 skyVisibility) {
  radiance = sh2Zero();
  skyVisibility = vec4(0.0);
  uint coarserLevel = uint(update.level) + 1u;
  if (coarserLevel >= kProbeLevels) return false;
  ivec3 cell = probe >> 1;  // the coarser cell holding the probe (arithmetic shift: floor for negative coordinates)
  vec3 fraction = vec3(probe & 1) * 0.5;
  float weightSum = 0.0;
  // The count is not a constant, so that the loop stays a loop: unrolled, it would hold eight traces, which lavapipe
  // would run for every probe (it runs both sides of a branch), where only a probe that starts afresh needs them.
  int corners = startsAfresh ? kProbeCellCorners : 0;
  // Read once, not in the loop (voxel_access.glsl's VolumeLayout says why).
  uint firstCoarserProbe = coarserLevel * uint(update.probesPerLevel);
  ivec3 probesPerAxis = update.probesPerAxis;
  float coarserSpacing = 2.0 * update.spacing;
  float ownVoxel = 0.5 * volume.voxelSize;
  for (int corner = 0; corner < corners; ++corner) {
    ProbeCellCorner around = probeCellCorner(cell, fraction, corner);
    float weight = around.weight;
    ivec3 coarser = around.probe;
    Probe candidate = probes[firstCoarserProbe + probeSlotIndex(coarser, probesPerAxis)];
    if (weight == 0.0 || !probeIsUsable(candidate, coarser)) continue;
    vec3 coarserPosition = probeWorldPosition(coarser, coarserSpacing, candidate.state);
    float separation = distance(coarserPosition, position);
    vec3 towardProbe = (position - coarserPosition) / separation;
    if (separation > ownVoxel &&
        traceVoxelsNearSurfaces(coarserPosition, towardProbe, separation - ownVoxel, kIgnoreObservedSpace).hit)
      continue;
    radiance = sh2Add(radiance, sh2Scale(probeRadianceSh(candidate), weight));
    skyVisibility += probeSkyVisibilitySh(candidate) * weight;
    weightSum += weight;
  }
  if (weightSum == 0.0) return false;
  radiance = sh2Divide(radiance, weightSum);
  skyVisibility /= weightSum;
  return true;
}

// The rays of a probe with reservoirs: ray r belongs to stratum r / raysPerStratum; the last ray of each stratum
// re-traces its reservoir's sample, the others are uniform candidates.
struct StratifiedRays {
  uint raysPerStratum;
  uint candidates;  // per stratum: raysPerStratum − 1
};

StratifiedRays stratifiedRays() {
  uint raysPerStratum = max(update.raysPerProbe / kProbeStrata, 1u);  // ≥ 2 with reservoirs (validateSettings)
  return StratifiedRays(raysPerStratum, raysPerStratum - 1u);
}

// The sample index in its stratum's direction set of candidate `candidate` of an update starting at `firstDirection`.
uint candidateSample(uint firstDirection, uint candidate) {
  return (firstDirection + candidate) % kProbeStratumDirectionCount;
}

// The reservoir update of one stratum and its estimate Î_s of the radiance SH (see the top of this file), as the
// three channels' SH2. `reservoir` is the stored one (empty for a probe that starts afresh); `reusableUpdates` how many
// updates' candidates it may stand for; `history` the control variate H. Writes the updated reservoir.
Sh2Rgb updateStratum(uint stratum, StratifiedRays rays, uint firstDirection, uint reservoir, uint reusableUpdates,
                     Sh2Rgb history, uint reservoirSlot, uint seed) {
  uint firstRay = stratum * rays.raysPerStratum;
  uint reusedRay = firstRay + rays.candidates;
  vec3 random = hashToUnitCube(uvec3(seed, update.frameIndex, stratum));
  float solidAngle = kProbeStratumSolidAngle;

  // Temporal reuse: the stored reservoir, its sample re-traced this frame (never clamped). Capping M bounds how long
  // old candidates outweigh new ones (ReSTIR's M-cap); so does the probe's history (`reusableUpdates`), so that when
  // Less lag shortens it (a light switched on, a wall moved) the reservoir forgets too.
  uint kept = probeReservoirSample(reservoir);
  vec3 keptRadiance = rayRadiance[reusedRay];
  float keptTarget = probeSampleLuminance(keptRadiance);
  uint reusedCount = keptTarget > 0.0 ? min(min(probeReservoirCount(reservoir), update.reservoirHistoryCap),
                                            rays.candidates * reusableUpdates)
                                      : 0u;
  float weightSum = probeReservoirMeanWeight(reservoir) * float(reusedCount);

  vec4 meanBasis = probeStratumMeanBasis(stratum);
  Sh2Rgb deviation = sh2Zero();
  for (uint candidate = 0u; candidate < rays.candidates; ++candidate) {
    uint sampleIndex = candidateSample(firstDirection, candidate);
    // The reservoir weighs the candidate as traced, the estimate takes it clamped: a bright direction found for the
    // first time enters the reservoir in full, its re-traced ray raises the clamp's maximum by the next update, and
    // the clamp only delays light that keeps being found (without this, a small emitter that few candidates see
    // would stay clamped for good: a dark bias).
    vec3 radiance = rayRadiance[firstRay + candidate];
    float target = probeSampleLuminance(radiance);
    radiance *= clampScale[firstRay + candidate];
    float weight = target * solidAngle;  // p̂(x) / p(x), p = 1/Ω_s
    weightSum += weight;
    if (weightSum > 0.0 && random[candidate] * weightSum < weight) {
      kept = sampleIndex;
      keptRadiance = radiance;
      keptTarget = target;
    }
    // The second integral, ∫_s L·(Y − Ȳ_s), by the candidates, weight Ω_s / c each, less the control variate's.
    vec4 basis = sh2Basis(probeStratumDirection(stratum, sampleIndex));
    vec3 residual = radiance - sh2Evaluate(history, basis);
    vec4 weightedDeviation = (basis - meanBasis) * (solidAngle / float(rays.candidates));
    deviation = sh2Add(deviation, sh2Project(residual, weightedDeviation));
  }
  mat3 covariance = probeStratumCovariance(stratum);
  deviation = sh2Add(deviation, Sh2Rgb(probeStratumDeviation(covariance, history.r),
                                       probeStratumDeviation(covariance, history.g),
                                       probeStratumDeviation(covariance, history.b)));
  uint count = reusedCount + rays.candidates;
  float contributionWeight = weightSum > 0.0 ? weightSum / (float(count) * keptTarget) : 0.0;
  uint storedCandidates = weightSum > 0.0 ? count : 0u;  // nothing bright seen: empty
  reservoirs[reservoirSlot] = packProbeReservoir(min(weightSum / float(count), 65504.0), kept, storedCandidates);
  // The first integral, Ȳ_s·∫_s L, by the reservoir: L(y')·W.
  vec3 total = keptRadiance * contributionWeight;
  return sh2Add(sh2Project(total, meanBasis), deviation);
}

// This update's dither of the probe's 8-bit values (SH, change statistics).
float probeDither(uint probeIndex) { return hashToUnitCube(uvec3(probeIndex, update.frameIndex, kProbeStrata)).x; }

// Less lag (SPEC §6.2; shared/probe_interface.h): an update whose trimmed mean strays from its history's by more than
// its usual noise shortens the history in proportion. Its deviation is then not learnt as noise, so that a change does
// not teach the probe to expect changes. Light that keeps growing (or fading) — a drift summed over updates past
// kProbeDriftLimit deviations, or a change many probes saw at once (ProbeChangeTally) — holds the history short for
// a while. Counts the probe in this frame's tally, updates its change statistics and returns the history count this
// update blends with.
uint followChange(uint probeIndex, uint storedCount, float trimmedMean) {
  uint historyCount = storedCount;
  float threshold = update.changeThreshold;
  ProbeChange change =
      storedCount > 0u ? unpackProbeChange(changes[probeIndex]) : ProbeChange(trimmedMean, 0.0, 0u, 0.0);
  float deviation = (trimmedMean - change.mean) / max(trimmedMean + change.mean, 1e-20);
  float squaredDeviation = deviation * deviation;
  float drift = 0.0;
  if (threshold > 0.0 && storedCount >= kProbeChangeMinimumHistory) {
    atomicAdd(tally.watchedProbes, 1u);
    // A probe with reservoirs draws its rays toward its bright directions, so the trimmed mean of their light leans
    // from its history by itself (in the dark room by enough to start a shared drift that doubled its noise): it
    // tells no shared drift.
    if (!kKeepsReservoirs && change.mean > 0.0) {
      float leaning = probeUpdateLeaning(trimmedMean, change.mean);
      atomicAdd(tally.leaningProbes, 1u);
      atomicAdd(tally.leaningSum, int(round(leaning * kProbeLeaningScale)));
      atomicAdd(tally.leaningSquares, uint(round(leaning * leaning * kProbeLeaningScale)));
      atomicAdd(tally.directShareSum, uint(round(knownDirectShare * kProbeLeaningScale)));
    }
    float noise = max(change.variance, kProbeChangeVarianceFloor);
    float expected = threshold * threshold * noise;
    drift = accumulateProbeDrift(change.drift, deviation / sqrt(noise));
    if (abs(drift) >= kProbeDriftLimit) {
      change.recoveryUpdates = kProbeChangeRecoveryUpdates;
      drift = 0.0;
    }
    if (squaredDeviation > expected) {
      historyCount = uint(float(storedCount) * expected / squaredDeviation);
      squaredDeviation = change.variance;
      atomicAdd(tally.cutProbes, 1u);
    }
  }
  if (update.startsSharedRecovery != 0u && storedCount > 0u) {  // many probes saw a change at once
    change.recoveryUpdates = kProbeChangeRecoveryUpdates;
    drift = 0.0;
  }
  change.drift = drift;
  if (change.recoveryUpdates > 0u) {
    historyCount = min(historyCount, kProbeChangeRecoveryHistory);
    --change.recoveryUpdates;
  }
  // Both as the SH blend: the mean over the updates so far, then a window of about the history cap.
  change.variance = mix(change.variance, squaredDeviation, 1.0 / float(storedCount + 1u));
  change.mean = mix(change.mean, trimmedMean, 1.0 / float(historyCount + 1u));
  changes[probeIndex] = packProbeChange(change, probeDither(probeIndex));
  return historyCount;
}

// The probe a workgroup updates, as it stands before the update.
struct ListedProbe {
  uint index;            // its slot in the probe buffer
  ivec3 coordinate;      // its world probe coordinate
  Probe stored;
  uint historyCount;     // m: 0 for a probe that starts afresh
  Sh2Rgb history;        // its radiance so far: what this update blends into, and the reservoirs' control variate
  uint firstDirection;   // where this update's rays start in the probe's direction set
  uint offsetCode;
  uint placement;
  vec3 origin;           // where its rays leave from: its position plus its virtual offset
  bool recovering;       // following a change (a recovery, or one many probes start now): its directions are turned
};

// History, offset and placement count only if this slot has held this probe (a slot that scrolled to another probe
// is stale). An invalid probe keeps its history count but has no offset: it is traced from its grid position.
ListedProbe readProbe(uint probeIndex) {
  ListedProbe probe;
  probe.index = probeIndex;
  probe.coordinate =
      probeWorldCoordinate(probeIndex % uint(update.probesPerLevel), update.originProbe, update.probesPerAxis);
  probe.stored = probes[probeIndex];
  uint state = probe.stored.state;
  bool ownsSlot = probeSlotHolds(probe.stored, probe.coordinate);
  probe.historyCount = ownsSlot ? probeHistoryCount(state) : 0u;
  probe.history = probe.historyCount > 0u ? probeRadianceSh(probe.stored) : sh2Zero();
  probe.firstDirection = ownsSlot ? probeNextDirection(state) : 0u;
  probe.offsetCode = ownsSlot ? probeOffsetCode(state) : 0u;
  probe.placement = ownsSlot ? probePlacement(state) : kProbeStateActive;
  probe.origin = probeWorldPosition(probe.coordinate, update.spacing, ownsSlot ? state : 0u);
  probe.recovering = probe.historyCount > 0u && (unpackProbeChange(changes[probeIndex]).recoveryUpdates > 0u ||
                                                 update.startsSharedRecovery != 0u);
  return probe;
}

// A thread's ray.
struct ProbeRay {
  bool traced;           // the thread has a ray: it is one of the first raysPerProbe
  uint stratum;          // with reservoirs: the stratum it belongs to
  bool reusesReservoir;  // with reservoirs: it re-traces its stratum's reservoir sample
  uint reservoirSlot;
  uint reservoir;        // its stratum's stored reservoir
  vec3 direction;
  // The projection weight of its distance and normal-dot: 4π/N over the sphere, Ω_s/c per candidate of a stratum; a
  // re-traced reservoir ray is not uniform and leaves them out.
  float uniformWeight;
};

// Without reservoirs the ray is the next of the probe's 1024 directions; with them a candidate of its stratum's set
// or the re-traced reservoir sample (see the top of this file).
ProbeRay chooseRay(ListedProbe probe, uint ray) {
  StratifiedRays rays = stratifiedRays();
  ProbeRay chosen;
  chosen.traced = ray < update.raysPerProbe;
  chosen.stratum = ray / rays.raysPerStratum;
  chosen.reusesReservoir = ray % rays.raysPerStratum == rays.candidates;
  // A probe that starts afresh (m = 0: new, stale, or just moved by ProbeRelocate) starts with empty reservoirs: what
  // they hold was seen from elsewhere.
  chosen.reservoirSlot = probe.index * kProbeStrata + chosen.stratum;
  chosen.reservoir =
      kKeepsReservoirs && chosen.traced && probe.historyCount > 0u ? reservoirs[chosen.reservoirSlot] : 0u;
  chosen.direction = vec3(0.0, 0.0, 1.0);
  chosen.uniformWeight = 0.0;
  if (!chosen.traced) return chosen;
  if (kKeepsReservoirs) {
    uint sampleIndex = chosen.reusesReservoir ? probeReservoirSample(chosen.reservoir)
                                              : candidateSample(probe.firstDirection, ray % rays.raysPerStratum);
    chosen.direction = probeStratumDirection(chosen.stratum, sampleIndex);
    chosen.uniformWeight = chosen.reusesReservoir ? 0.0 : kProbeStratumSolidAngle / float(rays.candidates);
  } else {
    chosen.direction = probeRayDirection(probe.firstDirection, ray);
    if (probe.recovering)
      chosen.direction =
          normalize(rotateByQuaternion(chosen.direction, probeRecoveryRotation(update.frameIndex, uint(update.level))));
    chosen.uniformWeight = update.projectionWeight;
  }
  return chosen;
}

// What the probe holds before the update, for the rays that find nothing known: its history, or for a probe that
// starts afresh the coarser level's radiance (black without one). One thread.
void holdRadiance(ListedProbe probe) {
  Sh2Rgb start;
  vec4 startSkyVisibility;
  startsFromCoarserLevel =
      coarserLevelRadiance(probe.coordinate, probe.origin, probe.historyCount == 0u, start, startSkyVisibility);
  heldRadiance = probe.historyCount > 0u ? probe.history : start;
  heldSkyVisibility = probe.historyCount > 0u ? probeSkyVisibilitySh(probe.stored) : startSkyVisibility;
}

// Traces the thread's ray through the voxels: its radiance (black from behind), the sky's on a miss, and whether it
// found neither a surface nor the sky (SPEC §6.4).
VoxelHit traceRay(ListedProbe probe, ProbeRay chosen, uint ray) {
  rayRadiance[ray] = vec3(0.0);
  rayFound[ray] = kRayFoundSky;
  rayIndirectRadiance[ray] = vec3(0.0);
  rayHalf[ray] = chosen.direction.y > 0.0 ? 1u : 0u;
  VoxelHit hit;
  if (!chosen.traced) return hit;
  bool watchesObservedSpace = volume.skyOnlyThroughObservedSpace != 0u;
  hit = traceVoxelsNearSurfaces(probe.origin, chosen.direction, update.rayLength, watchesObservedSpace);
  if (hit.hit) {
    rayFound[ray] = kRayMetSurface;
    vec3 direct = unpackR11G11B10F(voxels[hit.brick * kVoxelsPerBrick + hit.voxelIndex].directRadiance);
    rayIndirectRadiance[ray] = max(hit.radiance - direct, vec3(0.0));  // black from behind
  } else if (hit.unobserved) {  // neither a surface nor the sky (SPEC §6.4)
    rayFound[ray] = hit.endedBesideSurface ? kRayUnknownBesideSurface : kRayUnknownInSpace;
  }
  rayRadiance[ray] = hit.hit || hit.endedBesideSurface ? hit.radiance : skyRadiance(chosen.direction);
  return hit;
}

// Unknown is not sky (SPEC §6.4): the estimate is formed over the rays that found something known. A ray into space no
// view has observed stands for the mean of this update's known rays: the surfaces' mean less their direct part, and the
// sky as often as the known rays of its own half of the sphere, above or below the horizon, found it. Less the direct
// part: the sun's view covers the camera's surroundings and the local lights' views their reach, so a surface no view
// has seen is one no light's view saw lit (counting the sunlit walls in gave the courtyard's probes sunlight behind its
// buildings: docs/QUALITY.md). The sky by halves: it lies above the horizon, and over the whole sphere the sky openings
// show above lit the unknown space at floor level too; the surfaces over the whole sphere, whose mean is steadier than
// a half's (by halves, more light came through a wall's junctions in `two-rooms`: docs/QUALITY.md, "Unknown rays take
// the known sky's share"). Alike for every direction of its half, so that what the probe learns does not depend on
// what it held before, which would keep a camera cut's old light in it for good. (Unknown rays once stood for the
// surfaces' mean alone, never the sky: it kept the hall without the capture around the camera from taking the sky
// through its roof's openings to the whole unknown sphere, when views observed the space beside walls they grazed; with
// today's stricter observed space that rule left the hall's probes that see the nearer opening only through air no
// view observed too dark.) A half no known ray lies in takes the whole sphere's share of sky; a probe none of whose
// rays found anything known keeps what it holds. (A ray that ended beside a seen surface stands for that surface's
// light, which the trace gives it.) One thread.
void averageKnownRays() {
  vec3 surfaceSum = vec3(0.0), surfaceIndirectSum = vec3(0.0), skySum[3];
  uint surfaces = 0u, count[3], skyRays[3];
  for (uint side = 0u; side < 3u; ++side) {
    skySum[side] = vec3(0.0);
    count[side] = skyRays[side] = 0u;
  }
  uint raysPerProbe = update.raysPerProbe;
  for (uint other = 0u; other < raysPerProbe; ++other) {
    uint found = rayFound[other];
    if (found == kRayUnknownInSpace || found == kRayUnknownBesideSurface) continue;
    uint side = rayHalf[other];
    ++count[side];
    ++count[2];
    if (found == kRayMetSurface) {
      surfaceSum += rayRadiance[other];
      surfaceIndirectSum += rayIndirectRadiance[other];
      ++surfaces;
    } else {
      skySum[side] += rayRadiance[other];
      skySum[2] += rayRadiance[other];
      ++skyRays[side];
      ++skyRays[2];
    }
  }
  knownRays = count[2];
  float knownLuminance = probeSampleLuminance(surfaceSum + skySum[2]);
  knownDirectShare =
      knownLuminance > 0.0 ? clamp(1.0 - probeSampleLuminance(surfaceIndirectSum) / knownLuminance, 0.0, 1.0) : 1.0;
  vec3 surfacesIndirectMean = surfaces > 0u ? surfaceIndirectSum / float(surfaces) : vec3(0.0);
  for (uint side = 0u; side < 2u; ++side) {
    uint h = count[side] > 0u ? side : 2u;  // a half with no known ray takes the whole sphere's
    float skyShare = count[h] > 0u ? float(skyRays[h]) / float(count[h]) : 0.0;
    vec3 skyMean = skyRays[h] > 0u ? skySum[h] / float(skyRays[h]) : vec3(0.0);
    knownMeanWithoutDirect[side] = mix(surfacesIndirectMean, skyMean, skyShare);
    knownSkyShare[side] = skyShare;
  }
}

// The thread's terms of the probe's three SH2, L_lm = (4π/N) Σ L(ω_i) Y_lm(ω_i) (SPEC §2).
void projectRay(ProbeRay chosen, VoxelHit hit, uint ray) {
  radianceSums[ray] = sh2Zero();
  distanceSums[ray] = vec4(0.0);
  normalDotSums[ray] = vec4(0.0);
  skyVisibilitySums[ray] = vec4(0.0);
  if (!chosen.traced) return;
  vec3 radiance = rayRadiance[ray];
  uint found = rayFound[ray];
  bool unknown = found == kRayUnknownInSpace || found == kRayUnknownBesideSurface;
  float skyVisibility = found == kRayFoundSky ? 1.0 : 0.0;
  if (found == kRayUnknownInSpace && knownRays > 0u) {
    radiance = knownMeanWithoutDirect[rayHalf[ray]];
    skyVisibility = knownSkyShare[rayHalf[ray]];
  } else if (found == kRayUnknownInSpace) {
    radiance = max(sh2Evaluate(heldRadiance, sh2Basis(chosen.direction)), vec3(0.0));
    skyVisibility = clamp(dot(heldSkyVisibility, sh2Basis(chosen.direction)), 0.0, 1.0);
  }
  // A miss meets no surface, front or back: +1 (a front face head-on) keeps it from suggesting the probe is inside
  // geometry, which is what negative values will tell the virtual offset.
  float normalDot = hit.hit ? dot(-chosen.direction, hit.normal) : 1.0;
  // An unknown ray's distance: how far its way is known to be free.
  float distance = min(unknown ? hit.unobservedDistance : hit.distance, update.distanceRange);
  vec4 weightedBasis = sh2Basis(chosen.direction) * chosen.uniformWeight;
  radianceSums[ray] = sh2Project(radiance, weightedBasis);
  distanceSums[ray] = distance * weightedBasis;
  normalDotSums[ray] = normalDot * weightedBasis;
  skyVisibilitySums[ray] = skyVisibility * weightedBasis;
  // An empty reservoir's ray stands for nothing: black, so that it neither raises the clamp's maximum nor is kept.
  bool emptyReservoir =
      kKeepsReservoirs && chosen.reusesReservoir && probeReservoirCount(chosen.reservoir) == 0u;
  rayRadiance[ray] = emptyReservoir ? vec3(0.0) : radiance;
}

// Less lag's statistic, the update's trimmed mean, and the history count the update blends with (followChange), for
// every thread. A ray's share of the trimmed mean: its rank among the rays (ties broken by index) decides whether it
// is among the brightest eighth, which are left out. With reservoirs their re-traced rays count too: they keep
// looking where the light was found, so they change little from one update to the next unless the light does, and
// leaving them out would make the statistic noisier than without reservoirs (24 rays instead of 32), which the
// change detection would take for change.
uint detectChange(ListedProbe probe, uint ray) {
  uint raysPerProbe = update.raysPerProbe;
  float luminance = probeSampleLuminance(rayRadiance[ray]);
  uint brighter = 0u;
  for (uint other = 0u; other < raysPerProbe; ++other) {
    float otherLuminance = probeSampleLuminance(rayRadiance[other]);
    if (otherLuminance > luminance || (otherLuminance == luminance && other < ray)) ++brighter;
  }
  uint trimmedRays = raysPerProbe / kProbeChangeTrimFraction;
  trimmedLuminance[ray] =
      ray < raysPerProbe && brighter >= trimmedRays ? luminance / float(raysPerProbe - trimmedRays) : 0.0;
  barrier();
  if (ray == 0u) {
    float trimmedMean = 0.0;
    for (uint other = 0u; other < raysPerProbe; ++other) trimmedMean += trimmedLuminance[other];
    blendedHistoryCount = followChange(probe.index, probe.historyCount, trimmedMean);
  }
  barrier();
  return blendedHistoryCount;
}

// UpdateReservoirs (see the top of this file): the clamp's maximum, then each stratum's reservoir update, whose
// radiance estimate replaces the rays' uniform ones (distance and normal-dot stay the candidates').
void updateReservoirs(ListedProbe probe, ProbeRay chosen, uint ray, uint reusableUpdates) {
  StratifiedRays rays = stratifiedRays();
  // The clamp: the brightest direction the reservoirs hold, re-traced this frame (none for empty reservoirs).
  float clampFactor = update.sampleClamp;
  clampScale[ray] = 1.0;
  if (clampFactor > 0.0 && chosen.traced && !chosen.reusesReservoir) {
    float historyMaximum = 0.0;
    for (uint s = 0u; s < kProbeStrata; ++s) {
      uint reusedRay = s * rays.raysPerStratum + rays.candidates;
      historyMaximum = max(historyMaximum, probeSampleLuminance(rayRadiance[reusedRay]));
    }
    float luminance = probeSampleLuminance(rayRadiance[ray]);
    float limit = clampFactor * historyMaximum;
    if (historyMaximum > 0.0 && luminance > limit) clampScale[ray] = limit / luminance;
  }
  barrier();
  if (chosen.traced && ray % rays.raysPerStratum == 0u) {
    radianceSums[ray] = updateStratum(chosen.stratum, rays, probe.firstDirection, chosen.reservoir, reusableUpdates,
                                      probe.history, chosen.reservoirSlot, probe.index);
  } else {
    radianceSums[ray] = sh2Zero();
  }
  barrier();
}

// Sums the threads' terms into thread 0's.
void sumOverRays(uint ray) {
  for (uint stride = kProbeTraceGroupSize / 2u; stride > 0u; stride /= 2u) {
    if (ray < stride) {
      radianceSums[ray] = sh2Add(radianceSums[ray], radianceSums[ray + stride]);
      distanceSums[ray] += distanceSums[ray + stride];
      normalDotSums[ray] += normalDotSums[ray + stride];
      skyVisibilitySums[ray] += skyVisibilitySums[ray + stride];
    }
    barrier();
  }
}

// S = (1-α)·S_hist + α·S_new with α = 1/(m+1) (SPEC §4.5): the mean of the updates so far until m reaches its cap,
// then an exponential window of about cap updates. A new probe (m = 0) takes its radiance half from the coarser
// level, half from this first trace — the coarser value counts as one earlier update, so its weight then decays as
// 1/(m+1) like any update's; without a coarser value, and always for distance and normal-dot (which belong to this
// probe's own position and spacing), it takes the first trace whole. A stale slot may hold anything: no history.
// `probe.historyCount` is the count this update blends with. One thread.
void writeProbe(ListedProbe probe) {
  uint raysPerProbe = update.raysPerProbe;
  float alpha = 1.0 / float(probe.historyCount + 1u);
  float radianceAlpha = alpha;
  Sh2Rgb history = probe.history;
  if (startsFromCoarserLevel) {
    history = heldRadiance;
    radianceAlpha = 0.5;
  }
  Sh2Rgb radiance = sh2Mix(history, radianceSums[0], radianceAlpha);
  vec4 skyVisibility = mix(heldSkyVisibility, skyVisibilitySums[0], radianceAlpha);
  float range = update.distanceRange;
  vec4 distanceHistory = probe.historyCount > 0u ? probeDistanceSh(probe.stored, update.spacing) : vec4(0.0);
  vec4 normalDotHistory = probe.historyCount > 0u ? probeNormalDotSh(probe.stored) : vec4(0.0);
  float dither = probeDither(probe.index);
  uint distanceSh = packProbeUnitSh(mix(distanceHistory, distanceSums[0], alpha) / range, dither);
  uint normalDotSh = packProbeUnitSh(mix(normalDotHistory, normalDotSums[0], alpha), dither);
  // With reservoirs each stratum's candidates walk its 128-direction set, c per update: the counter runs modulo
  // c·128 so that it stays continuous modulo 128.
  StratifiedRays rays = stratifiedRays();
  uint nextDirection = kKeepsReservoirs
                           ? (probe.firstDirection + rays.candidates) % (rays.candidates * kProbeStratumDirectionCount)
                           : (probe.firstDirection + raysPerProbe) % kProbeRayDirectionCount;
  uint nextState =
      packProbeState(min(probe.historyCount + 1u, update.historyCap), nextDirection, probe.placement, probe.offsetCode);
  float knownFraction = float(knownRays) / float(raysPerProbe);
  float knownHistory = probe.historyCount > 0u ? probeKnownFraction(probe.stored) : knownFraction;
  uint tag = packProbeTag(probe.coordinate, mix(knownHistory, knownFraction, alpha), dither);
  probes[probe.index] = makeProbe(radiance, skyVisibility, distanceSh, normalDotSh, nextState, tag);
}

// The probe's work (shared/work_counters.h), by thread 0 once the workgroup's rays are summed: the probe, its rays
// and their reads, and the visibility tests of the coarser level's probes thread 0 made before them (`seeding`).
void countProbeWork(TracedWork seeding) {
  atomicAdd(work.probeTraceProbes, 1u);
  atomicAdd(work.probeTraceRays, rayCount);
  atomicAdd(work.probeTraceReads, rayReads);
  atomicAdd(work.probeTraceSeedRays, seeding.rays);
  atomicAdd(work.probeTraceSeedReads, seeding.reads);
}

// Which of the probe's rays each thread traces. A lock-step group of threads (8 on lavapipe) walks for as long as its
// longest ray: the threads take the rays in order of their direction's height, so that a group's rays go the same way
// — up to the sky or the roof, sideways, down to the floor — and end at much the same distance. Every per-ray
// result is kept in the ray's own slot, so the order changes nothing but the time. Each thread chooses the ray of its
// own index, and hands it on to the thread that traces it (`chosen`).
shared float rayHeight[kProbeTraceGroupSize];
shared uint rayOfThread[kProbeTraceGroupSize];
shared ProbeRay chosenRays[kProbeTraceGroupSize];

uint rayInHeightOrder(ListedProbe probe, out ProbeRay chosen) {
  uint thread = gl_LocalInvocationID.x;
  ProbeRay own = chooseRay(probe, thread);
  chosenRays[thread] = own;
  rayHeight[thread] = own.traced ? own.direction.y : 2.0;  // rays not traced last
  barrier();
  float height = rayHeight[thread];
  uint rank = 0u;
  for (uint other = 0u; other < kProbeTraceGroupSize; ++other) {
    float otherHeight = rayHeight[other];
    if (otherHeight < height || (otherHeight == height && other < thread)) ++rank;
  }
  rayOfThread[rank] = thread;
  barrier();
  uint ray = rayOfThread[thread];
  chosen = chosenRays[ray];
  return ray;
}

// The update as the list of its steps; the barriers between them are the workgroup's.
void main() {
  ListedProbe probe = readProbe(listedProbes[gl_WorkGroupID.x]);
  ProbeRay chosen;
  uint ray = rayInHeightOrder(probe, chosen);
  if (ray == 0u) {
    holdRadiance(probe);
    rayCount = 0u;
    rayReads = 0u;
  }
  TracedWork seeding = tracedWork;  // thread 0's: holdRadiance's visibility tests of the coarser level's probes
  barrier();
  VoxelHit hit = traceRay(probe, chosen, ray);
  if (countsWork()) {
    atomicAdd(rayCount, tracedWork.rays - seeding.rays);
    atomicAdd(rayReads, tracedWork.reads - seeding.reads);
  }
  barrier();
  if (ray == 0u) averageKnownRays();
  barrier();
  projectRay(chosen, hit, ray);
  barrier();
  uint storedCount = probe.historyCount;
  probe.historyCount = detectChange(probe, ray);
  // The updates a reservoir may stand for: as many as the probe blends with, and none once Less lag has cut the
  // history to less than half — a change, not noise: the reservoir and the history would otherwise each follow part
  // of the way, one after the other, and cornell's lag grew (docs/QUALITY.md, "Probe stability").
  uint reusableUpdates = 2u * probe.historyCount < storedCount ? 0u : probe.historyCount;
  if (kKeepsReservoirs) updateReservoirs(probe, chosen, ray, reusableUpdates);
  sumOverRays(ray);
  if (ray == 0u) {
    writeProbe(probe);
    if (countsWork()) countProbeWork(seeding);
  }
}
