// The voxel scene of SPEC §4.1–4.4 ("GI scene", the talk's Part 1): layouts, binding slots and addressing shared by the
// GI shaders and the host. A box of bricks (4×4×4 voxels) around the camera — centred across, standing up or down where
// it holds what the camera sees — addressed toroidally; a pool of bricks with
// a bump allocator and a free list; a 64-bit occupancy mask per brick and bit volumes over the brick grid for the
// coarser levels of the occupancy hierarchy.
#ifndef SSVGI_SHARED_VOXEL_INTERFACE_H
#define SSVGI_SHARED_VOXEL_INTERFACE_H

#include "shared/glsl_cpp.h"

SSVGI_SHARED_BEGIN

SSVGI_CONSTANT(uint, kBrickSizeVoxels, 4u);   // a brick is 4×4×4 voxels
SSVGI_CONSTANT(uint, kVoxelsPerBrick, 64u);
// SceneVoxelization takes a brick's voxels by blocks of 2×2×2 (level 1 of the hierarchy below), eight threads a brick,
// kInjectionBricksPerGroup bricks a workgroup.
SSVGI_CONSTANT(uint, kInjectionBricksPerGroup, 8u);
SSVGI_CONSTANT(uint, kInvalidBrick, 0xffffffffu);  // brickLookup: no brick in this cell
SSVGI_CONSTANT(uint, kAllocatingBrick, 0xfffffffeu);  // brickLookup: a thread is allocating this cell right now
// Occupancy hierarchy (SPEC §4.4): level 0 = voxel (the brick's 64-bit mask), 1 = 2×2×2 voxels (derived from the
// mask), 2 = brick, 3 = 2×2×2 bricks, 4 = 4×4×4 bricks, 5 = 8×8×8 bricks, 6 = 16×16×16 bricks; levels 2–6 are bit
// volumes. Levels 2–4 lie over the toroidal brick grid in world cells; the volume scrolls by a level-4 cell
// (kScrollStepBricks), so the cells of levels 5 and 6 are counted from the volume's minimum corner instead — those at
// its far faces may reach past it — and BuildOctree makes them again every frame from level 4: they are small (1,536
// and 192 cells at high tier) and spare a ray crossing open space most of its steps.
SSVGI_CONSTANT(uint, kOccupancyLevels, 7u);
SSVGI_CONSTANT(uint, kFirstGridLevel, 2u);
SSVGI_CONSTANT(uint, kFirstLocalGridLevel, 5u);

// Binding slots of the voxel scene, the same in every GI shader that reads or writes it (voxel_access.glsl declares
// them); a pass's own bindings start at kBindFirstPassSlot.
SSVGI_CONSTANT(uint, kBindVoxelVolume, 0u);     // VoxelVolume (uniform)
SSVGI_CONSTANT(uint, kBindBrickLookup, 1u);     // uint per brick cell: pool index or kInvalidBrick
SSVGI_CONSTANT(uint, kBindBricks, 2u);          // Brick[capacity]
SSVGI_CONSTANT(uint, kBindVoxels, 3u);          // Voxel[capacity * 64]
SSVGI_CONSTANT(uint, kBindOccupancyGrid, 4u);   // bit volumes of levels 2–6 (VoxelVolume::gridWordOffsets,
                                                // localGridWordOffsets)
// (slot 5 is the GiFrame uniform of gi_frame.h)
SSVGI_CONSTANT(uint, kBindPoolState, 6u);       // BrickPoolState + free list (brick_pool.glsl; allocating passes only)
SSVGI_CONSTANT(uint, kBindChangedCells, 7u);    // IndirectList of brick cells whose occupancy may have changed
SSVGI_CONSTANT(uint, kBindObservedSpace, 8u);   // bit volumes of the observed space (below), laid out as the
                                                // occupancy grid's levels 2–6
SSVGI_CONSTANT(uint, kBindWorkCounters, 9u);    // WorkCounters (work_counters.h; gi/work_counting.glsl)
SSVGI_CONSTANT(uint, kBindFirstPassSlot, 10u);
// SceneVoxelization's own slots.
SSVGI_CONSTANT(uint, kBindInjectionColor, kBindFirstPassSlot);        // the view's radiance (sampled)
SSVGI_CONSTANT(uint, kBindInjectionDepth, kBindFirstPassSlot + 1u);   // its depth, D32 reversed-Z (sampled)
SSVGI_CONSTANT(uint, kBindInjectionNormal, kBindFirstPassSlot + 2u);  // its world normal (sampled)
SSVGI_CONSTANT(uint, kBindInjectionAlbedo, kBindFirstPassSlot + 3u);  // its albedo (sampled; read for kViewIsDirectOnly)
SSVGI_CONSTANT(uint, kBindInjectionBricks, kBindFirstPassSlot + 4u);  // IndirectList of the bricks to inject
SSVGI_CONSTANT(uint, kBindInjectionIrradiance, kBindFirstPassSlot + 5u);  // ssvgi's last output (sampled; read for
                                                                          // kViewIsLitWithOutput)
// The Hi-Z levels HiZBuild wrote (float[]), read by BrickCulling and SceneVoxelization (gi/voxels/hiz_occlusion.glsl).
SSVGI_CONSTANT(uint, kBindHiZ, kBindFirstPassSlot + 6u);
// HiZBuild's, BrickAllocate's and BrickCulling's own slots.
SSVGI_CONSTANT(uint, kBindHiZDepth, kBindFirstPassSlot);                // the camera's depth (sampled)
SSVGI_CONSTANT(uint, kBindHiZPyramid, kBindFirstPassSlot + 1u);         // float[]: the Hi-Z levels HiZBuild writes
SSVGI_CONSTANT(uint, kBindAllocationDepth, kBindFirstPassSlot);         // the camera's depth (sampled)
SSVGI_CONSTANT(uint, kBindAllocationNormal, kBindFirstPassSlot + 1u);   // its world normal (sampled)
SSVGI_CONSTANT(uint, kBindCullingVisibleBricks, kBindFirstPassSlot + 1u);  // IndirectList of the bricks in view

// Per-frame description of the volume (uniform buffer).
struct VoxelVolume {
  ivec3 originBrick;            // world brick coordinate of the volume's minimum corner
  uint brickPoolCapacity;       // Settings::brickPoolCapacity
  ivec3 dimensionsBricks;       // the volume's size in bricks (multiples of 4)
  uint invalidFramesToClear;    // Settings::invalidFramesToClear: injections a voxel may be seen through
  float voxelSize;              // metres
  float brickSize;              // metres
  float bricksPerMetre;         // 1 / brickSize
  uint emptyFramesToRelease;    // Settings::emptyFramesToRelease: injections an empty brick is kept
  uvec3 gridWordOffsets;        // the first uint of occupancy levels 2, 3, 4 in the grid bit buffer
  uint gridWords;               // the grid bit buffer's size in uints
  ivec3 previousOriginBrick;    // originBrick of the last frame (VolumeScroll forgets what scrolled in)
  uint skyOnlyThroughObservedSpace;  // 1: probe rays see the sky only through observed space (Settings::…)
  uint countsWork;              // 1: the passes count their work this frame (WorkCounters)
  // Bricks the volume stands above (negative: below) the placement centred on the camera's step, moved toward the
  // surfaces the camera sees (VoxelScene::place); volumeViewpoint() takes it off again. Puts the uvec2 below on its
  // 8-byte boundary.
  int verticalShiftBricks;
  uvec2 localGridWordOffsets;   // the first uint of occupancy levels 5, 6 (cells counted from the volume's corner)
};
SSVGI_CHECK_SIZE(VoxelVolume, 96);

// Observed space (SPEC §6.4, "unknown is not sky"): which brick cells of the volume a view — the camera or an extra
// view — has observed, by seeing through them (known empty) or into them (they hold the surface it saw). Bit volumes
// in the occupancy grid's layout: at level 2 a bit per brick cell, set once observed; at levels 3–6 a bit per cell of
// that level, set once all of its cells of the level below inside the volume are, so that a ray crosses observed space
// at the occupancy grid's pace. ObservedSpace sets levels 2–4, VolumeScroll clears the cells that scroll in, and
// BuildOctree makes levels 5 and 6 from level 4 with the occupancy grid's.
// A probe ray that enters an unobserved cell holding no voxel has found neither a surface nor the sky.

// A brick of the pool.
struct Brick {
  ivec3 coordinate;        // world brick coordinate
  uint live;               // 1 while the brick is live, 0 when free
  uvec2 occupancy;         // 64-bit voxel occupancy mask (bit = x + 4y + 16z)
  uvec2 observed;          // voxels a view has observed since the brick was allocated: seen holding a surface, or
                           // seen through (SPEC §6.4, at the voxel's scale; the trace's use in voxel_trace.glsl)
  uint emptyInjections;    // injections the mask has been empty
  uint changeListedStamp;  // 1 + the frame index at which the brick's cell was last listed as changed
  uvec2 padding;           // std430 rounds a struct holding an ivec3 up to a multiple of 16 bytes
};
SSVGI_CHECK_SIZE(Brick, 48);

// BrickAllocate counts the surface pixels of the camera by their height, in bands one scroll step (kScrollStepBricks
// bricks) tall, the camera's step in the middle band (kSurfaceHeightBands / 2) and those further away in the end
// bands: where the volume's few steps of height (12 at high tier, against 32 across) are best spent
// (VoxelScene::place). The 62 bands between the end bands cover every placement that holds the camera's step of a
// volume up to 31 steps tall.
SSVGI_CONSTANT(uint, kSurfaceHeightBands, 64u);

// Allocation state of the pool, plus this frame's counters (reset at the start of every frame). Followed in its
// buffer by the free list: brickPoolCapacity pool indices, the first freeCount of them free.
struct BrickPoolState {
  uint bumpCount;           // slots handed out by the bump allocator so far (never decreases)
  uint freeCount;           // entries on the free list
  uint droppedTotal;        // allocations refused because the pool was full, since creation
  uint droppedThisFrame;
  uint allocatedThisFrame;
  uint releasedThisFrame;
  uint visibleThisFrame;    // bricks listed by BrickCulling for injection, summed over the views
  uint voxelsValid;         // occupied voxels of all live bricks, counted by the camera's BrickCulling (after the
                            // extra views' injection, before the lit frame's)
  uint surfacePixelsByHeight[kSurfaceHeightBands];  // the camera's pixels BrickAllocate read, by height band
};
SSVGI_CHECK_SIZE(BrickPoolState, 32 + 4 * 64);

// A list built by atomic appends that a later pass consumes with vkCmdDispatchIndirect: the first appender of every
// `groupSize` entries adds a workgroup, so the dispatch arguments are always ceil(count / groupSize) without a pass
// of their own. Followed in its buffer by the entries (uint each).
struct IndirectList {
  uint groupCountX;  // VkDispatchIndirectCommand
  uint groupCountY;  // 1
  uint groupCountZ;  // 1
  uint count;
};
SSVGI_CHECK_SIZE(IndirectList, 16);
SSVGI_CONSTANT(uint, kIndirectListHeaderWords, 4u);

// A voxel: the radiance its surface sends out (what rays that meet it see) and its surface: octahedral normal
// (2 × 8 bit, bits 0–15) and where the surface's plane lies in the voxel (8 bit, bits 16–23, packVoxelPlane); frames
// it has been seen through since the last valid injection (6 bit, 24–29); extra views that have seen it since the
// camera's lit frame last gave it light (2 bit, 30–31, saturating at kVoxelExtraViewsBeforeWrite). SPEC §4.1 gives
// the counter 16 bits; it counts to invalidFramesToClear (about 8), and the plane makes a thin or off-grid surface stop
// rays where it is rather than at the voxel's box (voxel_trace.glsl, voxelHitAt).
// Where a view lit by direct light only gave it (kViewIsDirectOnly), the voxel also keeps that direct (+ emitted)
// light and its albedo, and VoxelRelight recomputes its radiance as direct + albedo/π · E of the probes (SPEC §6.1);
// a voxel given all of its light by its view (albedo's relight bit clear) keeps that light as it was given.
struct Voxel {
  uint radiance;           // R11G11B10F
  uint surfaceAndLastHit;
  uint directRadiance;     // R11G11B10F: direct and emitted light leaving the surface, as a view last gave it
  uint albedo;             // packVoxelAlbedo: RGB 8 bits each, bit 24 (kVoxelRelit) set when the voxel is relit
};
SSVGI_CHECK_SIZE(Voxel, 16);

SSVGI_CONSTANT(uint, kVoxelRelit, 1u << 24u);
// A VoxelRelight workgroup relights this many bricks at a time, this many occupied voxels of each at a time: a brick
// holds a dozen occupied voxels on average (a wall fills 16 of its 64). With a thread per voxel slot the idle three
// quarters of each workgroup still cost lavapipe a fifth of the pass, and with 16 slots a brick of 8 voxels or fewer
// still ran its second 8 (lavapipe's vector) through the relight, masked (docs/PERFORMANCE.md).
SSVGI_CONSTANT(uint, kRelightBricksAtOnce, 8u);
SSVGI_CONSTANT(uint, kRelightVoxelsAtOnce, 8u);
SSVGI_INLINE uint packVoxelAlbedo(vec3 albedo) {
  uvec3 quantised = uvec3(clamp(albedo, vec3(0.0f), vec3(1.0f)) * 255.0f + vec3(0.5f));
  return quantised.x | (quantised.y << 8u) | (quantised.z << 16u) | kVoxelRelit;
}
SSVGI_INLINE vec3 unpackVoxelAlbedo(uint packed) {
  return vec3(float(packed & 0xffu), float((packed >> 8u) & 0xffu), float((packed >> 16u) & 0xffu)) / 255.0f;
}

// The surface's plane in a voxel: its signed distance from the voxel's centre along the normal, in voxels (at most
// √3/2, the centre-to-corner distance), in 8 bits. Code 0: no plane is known, a ray meets the voxel's box wherever it
// enters it.
SSVGI_CONSTANT(uint, kVoxelPlaneShift, 16u);
SSVGI_CONSTANT(uint, kVoxelLastHitShift, 24u);
SSVGI_CONSTANT(uint, kVoxelMaxLastHit, 0x3fu);
SSVGI_CONSTANT(uint, kVoxelExtraViewsShift, 30u);
// Where the camera's lit frame keeps giving a voxel its light, that light stays (SPEC §6.3): an extra view writes a
// voxel the lit frame has lit only once it has seen it this many times since — a surface the camera stops looking at
// takes the views' light again within a few of their renders.
SSVGI_CONSTANT(uint, kVoxelExtraViewsBeforeWrite, 3u);
// An extra view's texels are about a voxel wide and move by a fraction of one from render to render: each render
// samples the voxel at another point, of its surface or — where two meet in it, a floor and a wall — of either. Its
// writes are averaged, an exponential window of about 1/this many renders, rather than each replacing the last, which
// flickered; the lit frame's light, finer and already filtered, replaces.
SSVGI_CONSTANT(float, kVoxelExtraViewRadianceBlend, 0.25f);
// SceneVoxelization's second look at a voxel, at a random texel of its footprint in the view (footprintTexel): its
// hash's input, apart from that of the voxel's random point.
SSVGI_INLINE uvec3 voxelFootprintSeed(uvec3 worldVoxel, uint frameIndex) {
  return worldVoxel ^ uvec3(0x68bc21ebu, frameIndex * 0x9e3779b9u, 0x297a2d39u);
}
SSVGI_CONSTANT(float, kVoxelPlaneRange, 0.875f);
SSVGI_INLINE uint packVoxelPlane(float offsetVoxels) {
  float unit = clamp(offsetVoxels / kVoxelPlaneRange, -1.0f, 1.0f) * 0.5f + 0.5f;
  return 1u + uint(unit * 254.0f + 0.5f);
}
SSVGI_INLINE float unpackVoxelPlane(uint code) { return (float(code - 1u) / 254.0f * 2.0f - 1.0f) * kVoxelPlaneRange; }

// The volume's origin moves in steps of this many bricks (the cell size of the coarsest toroidal level, 4), so that
// every cell of levels 2–4 lies wholly inside or wholly outside the volume and toroidal slots never alias.
SSVGI_CONSTANT(int, kScrollStepBricks, 4);

// The largest half float. What ssvgi stores in half floats goes through finiteHalf: a NaN or an infinity that reaches
// it from a host's image or from light too bright for the format must not stay in a voxel, a probe or the output.
SSVGI_CONSTANT(float, kHalfMax, 65504.0f);
SSVGI_INLINE float finiteHalf(float value) {
  // Written so that NaN fails every comparison and becomes 0.
  return abs(value) <= kHalfMax ? value : (value > 0.0f ? kHalfMax : (value < 0.0f ? -kHalfMax : 0.0f));
}
SSVGI_INLINE vec3 finiteHalf(vec3 value) { return vec3(finiteHalf(value.x), finiteHalf(value.y), finiteHalf(value.z)); }

// The half float nearest a finite value within the half range. A store to a half-float image or packHalf2x16 may round
// toward zero (Vulkan allows it): a running average stored in half floats then loses up to a step every frame and
// settles below its input, by as many steps as its history spans (16 steps, 0.8–1.6 %, at a 1/16 blend). Storing the
// nearest half float leaves the conversion nothing to round.
SSVGI_INLINE float nearestHalf(float value) {
  uint bits = SSVGI_HALF_BITS(value);
  float stored = SSVGI_HALF_FLOAT(bits);
  if (abs(stored) == abs(value)) return stored;
  // The next half float on the value's side of `stored` (bits order half floats of one sign by magnitude).
  float neighbour = SSVGI_HALF_FLOAT(abs(value) > abs(stored) ? bits + 1u : bits - 1u);
  return abs(neighbour - value) < abs(stored - value) ? neighbour : stored;
}
SSVGI_INLINE vec3 nearestHalf(vec3 value) {
  return vec3(nearestHalf(value.x), nearestHalf(value.y), nearestHalf(value.z));
}

// Radiance in R11G11B10F (SPEC §4.1): each channel is a half float with the sign dropped and the mantissa cut to
// 6 (R, G) or 5 (B) bits, rounded to nearest. Negative values and NaN become 0, values past the format's range (and
// +∞) its maximum.
SSVGI_INLINE uint packSmallFloat(float value, uint mantissaBits) {
  uint dropped = 10u - mantissaBits;
  float largest = mantissaBits == 6u ? 65024.0f : 64512.0f;  // (2 - 2^-mantissaBits) · 2^15
  uint halfBits = SSVGI_HALF_BITS(value > 0.0f ? min(value, largest) : 0.0f);
  return (halfBits + (1u << (dropped - 1u))) >> dropped;
}
SSVGI_INLINE float unpackSmallFloat(uint bits, uint mantissaBits) { return SSVGI_HALF_FLOAT(bits << (10u - mantissaBits)); }

SSVGI_INLINE uint packR11G11B10F(vec3 radiance) {
  return packSmallFloat(radiance.x, 6u) | (packSmallFloat(radiance.y, 6u) << 11u) | (packSmallFloat(radiance.z, 5u) << 22u);
}
SSVGI_INLINE vec3 unpackR11G11B10F(uint packed) {
  return vec3(unpackSmallFloat(packed & 0x7ffu, 6u), unpackSmallFloat((packed >> 11u) & 0x7ffu, 6u),
              unpackSmallFloat(packed >> 22u, 5u));
}

// Unit normal in 16 bits: octahedral mapping (Meyer et al. 2010), 8 bits per coordinate.
SSVGI_INLINE uint packOctahedralNormal(vec3 normal) {
  vec3 n = normal / (abs(normal.x) + abs(normal.y) + abs(normal.z));
  vec2 folded = vec2(n.x, n.y);
  if (n.z < 0.0f) {
    folded = (vec2(1.0f) - abs(vec2(n.y, n.x))) * vec2(n.x >= 0.0f ? 1.0f : -1.0f, n.y >= 0.0f ? 1.0f : -1.0f);
  }
  uvec2 quantised = uvec2(clamp(folded * 0.5f + vec2(0.5f), vec2(0.0f), vec2(1.0f)) * 255.0f + vec2(0.5f));
  return quantised.x | (quantised.y << 8u);
}
SSVGI_INLINE vec3 unpackOctahedralNormal(uint packed) {
  vec2 folded = vec2(float(packed & 0xffu), float((packed >> 8u) & 0xffu)) / 255.0f * 2.0f - vec2(1.0f);
  vec3 n = vec3(folded.x, folded.y, 1.0f - abs(folded.x) - abs(folded.y));
  if (n.z < 0.0f) {
    vec2 unfolded = (vec2(1.0f) - abs(vec2(n.y, n.x))) * vec2(n.x >= 0.0f ? 1.0f : -1.0f, n.y >= 0.0f ? 1.0f : -1.0f);
    n.x = unfolded.x;
    n.y = unfolded.y;
  }
  return normalize(n);
}

// The fields of Voxel::surfaceAndLastHit.
SSVGI_INLINE vec3 voxelNormal(Voxel voxel) { return unpackOctahedralNormal(voxel.surfaceAndLastHit & 0xffffu); }
SSVGI_INLINE uint voxelPlaneCode(Voxel voxel) { return (voxel.surfaceAndLastHit >> kVoxelPlaneShift) & 0xffu; }
SSVGI_INLINE uint voxelSeenThroughCount(Voxel voxel) {
  return (voxel.surfaceAndLastHit >> kVoxelLastHitShift) & kVoxelMaxLastHit;
}
SSVGI_INLINE uint voxelExtraViewsSinceLitFrame(Voxel voxel) { return voxel.surfaceAndLastHit >> kVoxelExtraViewsShift; }
// The surface alone (normal and plane), as a valid injection sets it; the counters beside it.
SSVGI_INLINE uint packVoxelSurface(vec3 normal, uint planeCode) {
  return packOctahedralNormal(normal) | (planeCode << kVoxelPlaneShift);
}
SSVGI_INLINE uint voxelSurface(Voxel voxel) { return voxel.surfaceAndLastHit & ((1u << kVoxelLastHitShift) - 1u); }
SSVGI_INLINE uint packVoxelSurfaceAndCounters(uint surface, uint seenThroughCount, uint extraViewsSinceLitFrame) {
  return surface | (seenThroughCount << kVoxelLastHitShift) | (extraViewsSinceLitFrame << kVoxelExtraViewsShift);
}

// Positive modulo: toroidal addressing of world coordinates into the volume and the probe grids (SPEC §4.1). By a
// float division, not %: integer division has no vector instruction on a CPU, so lavapipe makes it one lane at a time,
// and the traces and gathers wrap coordinates at every step. The quotient is exact for |coordinate| < 2^24 cells
// (thousands of kilometres) but for its rounding, which puts it at most one off where it lies within an ulp of a whole
// number; the remainder is brought back into [0, dimensions) after.
SSVGI_INLINE ivec3 wrapCoordinate(ivec3 coordinate, ivec3 dimensions) {
  ivec3 wrapped = coordinate - dimensions * ivec3(floor(vec3(coordinate) / vec3(dimensions)));
  wrapped += dimensions * ivec3(lessThan(wrapped, ivec3(0)));
  return wrapped - dimensions * ivec3(greaterThanEqual(wrapped, dimensions));
}

// The index of a cell of a box of `dimensions` cells (0 ≤ cell < dimensions), x fastest.
SSVGI_INLINE uint linearCellIndex(ivec3 cell, ivec3 dimensions) {
  return uint(cell.x + dimensions.x * (cell.y + dimensions.y * cell.z));
}

// The cells of grid level `level` (kFirstGridLevel and up) on each axis of a volume of `dimensionsBricks`: its bricks
// over the cell's, rounded up — exact for the toroidal levels, whose cells divide the volume's sides; a local level's
// last cells may reach past the volume.
SSVGI_INLINE ivec3 gridLevelCells(uint level, ivec3 dimensionsBricks) {
  int shift = int(level - kFirstGridLevel);
  return (dimensionsBricks + ((1 << shift) - 1)) >> shift;
}

SSVGI_INLINE uint brickCellIndex(ivec3 worldBrick, ivec3 dimensions) {
  return linearCellIndex(wrapCoordinate(worldBrick, dimensions), dimensions);
}

SSVGI_INLINE bool brickInVolume(ivec3 worldBrick, ivec3 originBrick, ivec3 dimensionsBricks) {
  ivec3 local = worldBrick - originBrick;
  return all(greaterThanEqual(local, ivec3(0))) && all(lessThan(local, dimensionsBricks));
}

SSVGI_INLINE bool brickInVolume(ivec3 worldBrick, VoxelVolume volume) {
  return brickInVolume(worldBrick, ivec3(volume.originBrick), ivec3(volume.dimensionsBricks));
}

SSVGI_INLINE uint voxelBit(uvec3 voxelInBrick) { return voxelInBrick.x + 4u * voxelInBrick.y + 16u * voxelInBrick.z; }

// The voxels of a brick with a neighbour (across a face, inside the brick) in `mask` (bit x + 4y + 16z; the two words
// hold z 0–1 and z 2–3): the mask shifted one voxel along each axis either way, bits that would wrap into the next row
// or layer cleared.
SSVGI_INLINE uvec2 voxelsBesideVoxels(uvec2 mask) {
  uvec2 beside = ((mask << 1u) & 0xEEEEEEEEu) | ((mask >> 1u) & 0x77777777u);  // along x, x ≠ 0 / x ≠ 3
  beside |= ((mask << 4u) & 0xFFF0FFF0u) | ((mask >> 4u) & 0x0FFF0FFFu);         // along y, y ≠ 0 / y ≠ 3
  beside |= uvec2(mask.x << 16u, (mask.y << 16u) | (mask.x >> 16u));             // along z, from z − 1
  beside |= uvec2((mask.x >> 16u) | (mask.y << 16u), mask.y >> 16u);             // along z, from z + 1
  return beside;
}

SSVGI_SHARED_END

#endif
