// Rays through the voxel scene (SPEC §4.4; the talk's "Voxel Trace"): the hierarchical DDA over the occupancy
// hierarchy, and the walk it shares with the flat voxel DDA it must agree with (the baseline of SPEC §7 and the tests'
// oracle, in shaders/bench/flat_voxel_trace.glsl: no library shader traces with it).
//
// Both walk the same sequence of voxels, defined by the ray's crossings of voxel planes: each crossing happens at the
// distance crossingDistance() computes, crossings are made in order of distance, and crossings at the same distance
// (a ray through an edge or a corner) in axis order x, y, z. The flat DDA makes them one at a time; the hierarchical
// DDA jumps from inside an empty cell to the crossing that leaves it and lands in the voxel the flat DDA reaches by
// that crossing. Every crossing comes from the same expression on the same values, so the two agree exactly — the
// same first-hit voxel at the same distance — also for rays through edges and corners, axis-parallel rays and
// origins on cell boundaries.
//
// Coordinates: voxels are counted from the volume's minimum corner (0 .. dimensions · 4 - 1 on each axis); the cell of
// level L containing voxel v is v >> L (level 2 is the brick). The volume's origin is a multiple of kScrollStepBricks
// bricks, so up to level 4 these cells are exactly the world cells of the grid levels; levels 5 and 6 are counted
// from the volume's corner anyway (voxel_interface.h).
#ifndef SSVGI_VOXEL_TRACE_GLSL
#define SSVGI_VOXEL_TRACE_GLSL

#include "gi/voxels/voxel_access.glsl"

struct VoxelHit {
  bool hit;
  float distance;   // metres along the ray to where it enters the hit voxel (0 when it starts inside it);
                    // maxDistance for a miss
  uint brick;       // pool index of the hit voxel's brick; kInvalidBrick for a miss (but one that ended beside a
                    // surface, below)
  uint voxelIndex;  // the voxel's bit in its brick (voxelBit)
  vec3 radiance;    // the voxel's radiance; black for a miss or when the ray meets the voxel from behind
  vec3 normal;      // the voxel's stored unit normal; zero for a miss
  uint reads;       // buffer loads made (brick lookups, occupancy masks, grid words, the hit voxel): the cost statistic
  // For a trace that watches observed space (SPEC §6.4): whether the ray crossed a brick cell that no view has
  // observed and that holds no voxel, or ended at an unobserved voxel (below), before its hit or its end, and where it
  // first entered unobserved space (metres; its `distance` where it crossed none).
  bool unobserved;
  float unobservedDistance;
  // A miss that ended at unobserved voxels beside a surface it moved along or away from (below), not in space that no
  // view has observed: `brick`, `voxelIndex`, `normal` and `radiance` are that surface's, its light as the ray would
  // have met it (black from behind).
  bool endedBesideSurface;
};

const int kVoxelLevel = 0;
const int kBrickLevel = int(kFirstGridLevel);  // a brick is 2^2 voxels wide
const int kTopLevel = int(kOccupancyLevels) - 1;
// Components of a unit direction below this count as zero: the ray never crosses that axis's planes, and no crossing
// distance can overflow (or depend on whether the device flushes denormals).
const float kParallelComponent = 1e-20;
const float kNoCrossing = 3.0e38;

struct VoxelWalk {
  vec3 origin;          // the ray's origin in voxels from the volume's minimum corner
  vec3 voxelsPerMetre;  // the direction in voxels per metre
  vec3 metresPerVoxel;  // its inverse per axis (unused on parallel axes)
  ivec3 step;           // +1 or -1 per axis; 0 where the ray is parallel to the axis
  ivec3 voxel;          // the voxel the walk is in
  float distance;       // metres along the ray to where it entered that voxel
  float maxDistance;
  VolumeLayout volumeLayout;  // the volume's layout, read once
  ivec3 sizeVoxels;           // the volume's size in voxels
};

// Where the ray crosses the plane `coordinate = plane` of an axis, in metres. `precise`: no contraction into a
// different rounding in one of the two traces.
float crossingDistance(VoxelWalk walk, int axis, int plane) {
  if (walk.step[axis] == 0) return kNoCrossing;
  precise float distance = (float(plane) - walk.origin[axis]) * walk.metresPerVoxel[axis];
  return distance;
}

// Whether the ray crosses `plane` of `axis` before the crossing at `eventDistance` of `eventAxis`, in walk order.
bool crossesBefore(VoxelWalk walk, int axis, int plane, float eventDistance, int eventAxis) {
  float distance = crossingDistance(walk, axis, plane);
  return distance < eventDistance || (distance == eventDistance && axis < eventAxis);
}

// The axis of the first of three crossings in walk order (ties go to the lowest axis).
int firstCrossingAxis(vec3 distances) {
  return distances.x <= distances.y && distances.x <= distances.z ? 0 : (distances.y <= distances.z ? 1 : 2);
}

// The plane through which the ray leaves, along one axis, the level-`level` cell holding voxel coordinate `voxel`.
int exitPlane(int voxel, int level, int step) {
  int cellMin = (voxel >> level) << level;
  return step > 0 ? cellMin + (1 << level) : cellMin;
}

// The plane through which the ray enters voxel coordinate `voxel` along one axis.
int entryPlane(int voxel, int step) { return step > 0 ? voxel : voxel + 1; }

// The voxel coordinate along `axis` once the ray has made every crossing that comes before the one at
// `eventDistance` of `eventAxis`, knowing that it has reached `reached` and does not pass `limit` by then. The
// position at that distance is only a guess: rounding may put it a voxel off where the ray passes within a few ulps of
// a voxel plane, never more (coordinates stay below 2^12 voxels, so those ulps are under 10^-3 voxels); the crossings
// themselves decide, one each way. Not a loop: lavapipe runs a loop's body at least once for all its lanes, and these
// corrections come two an axis on every step of the walk (docs/PERFORMANCE.md, "Lavapipe runs every branch of a
// loop").
int coordinateAtCrossing(VoxelWalk walk, int axis, float eventDistance, int eventAxis, int reached, int limit) {
  int step = walk.step[axis];
  if (step == 0) return reached;
  float position = walk.origin[axis] + walk.voxelsPerMetre[axis] * eventDistance;
  int coordinate = int(clamp(floor(position), float(min(reached, limit)), float(max(reached, limit))));
  bool pastIt =
      coordinate != reached && !crossesBefore(walk, axis, entryPlane(coordinate, step), eventDistance, eventAxis);
  bool shortOfIt =
      coordinate != limit && crossesBefore(walk, axis, entryPlane(coordinate + step, step), eventDistance, eventAxis);
  return coordinate + (pastIt ? -step : (shortOfIt ? step : 0));
}

// What a walk reads of the volume's block: read once for an invocation that traces in a loop (the gather's
// visibility tests), else by each trace (volumeLayout says why).
struct VoxelTraceFrame {
  VolumeLayout volumeLayout;
  float voxelSize;  // VoxelVolume
  float brickSize;
};

VoxelTraceFrame voxelTraceFrame() { return VoxelTraceFrame(volumeLayout(), volume.voxelSize, volume.brickSize); }

// Starts a walk at the ray's origin, or where the ray enters the volume when the origin is outside (space outside the
// volume is empty). False when the ray misses the volume within maxDistance. `direction` must be unit length.
bool beginVoxelWalk(VoxelTraceFrame volumeFrame, vec3 origin, vec3 direction, float maxDistance, out VoxelWalk walk) {
  float voxelSize = volumeFrame.voxelSize;
  precise vec3 relativeOrigin = origin - vec3(volumeFrame.volumeLayout.originBrick) * volumeFrame.brickSize;
  walk.origin = relativeOrigin / voxelSize;
  walk.step = ivec3(sign(direction)) * ivec3(greaterThanEqual(abs(direction), vec3(kParallelComponent)));
  walk.voxelsPerMetre = direction / voxelSize;
  walk.metresPerVoxel = voxelSize / mix(direction, vec3(1.0), equal(walk.step, ivec3(0)));
  walk.maxDistance = maxDistance;
  walk.volumeLayout = volumeFrame.volumeLayout;
  walk.sizeVoxels = walk.volumeLayout.dimensions * int(kBrickSizeVoxels);
  ivec3 size = walk.sizeVoxels;

  // The ray enters the volume with the last of its entries into the slabs its origin lies outside of…
  float entry = 0.0;
  int entryAxis = -1;
  for (int axis = 0; axis < 3; ++axis) {
    if (walk.origin[axis] >= 0.0 && walk.origin[axis] < float(size[axis])) continue;
    if (walk.step[axis] == 0 || (walk.origin[axis] < 0.0) != (walk.step[axis] > 0)) return false;
    float distance = crossingDistance(walk, axis, walk.step[axis] > 0 ? 0 : size[axis]);
    if (distance >= entry) {  // equal: the later axis is crossed last
      entry = distance;
      entryAxis = axis;
    }
  }
  // …and leaves it with the first of its exits from the three slabs.
  vec3 exits;
  for (int axis = 0; axis < 3; ++axis) exits[axis] = crossingDistance(walk, axis, walk.step[axis] > 0 ? size[axis] : 0);
  int exitAxis = firstCrossingAxis(exits);
  bool entersBeforeLeaving = entry < exits[exitAxis] || (entry == exits[exitAxis] && entryAxis < exitAxis);
  if (!entersBeforeLeaving || entry > maxDistance) return false;

  for (int axis = 0; axis < 3; ++axis) {
    int last = walk.step[axis] > 0 ? size[axis] - 1 : 0;
    if (axis == entryAxis) {
      walk.voxel[axis] = walk.step[axis] > 0 ? 0 : size[axis] - 1;
    } else {
      int reached = int(clamp(floor(walk.origin[axis]), 0.0, float(size[axis] - 1)));
      walk.voxel[axis] = coordinateAtCrossing(walk, axis, entry, entryAxis, reached, last);
    }
  }
  walk.distance = entry;
  return true;
}

// The brick a walk is in, kept while it stays there so that its lookup and occupancy mask are read once.
struct CachedBrick {
  ivec3 brick;       // volume-local brick coordinate; -1 before the first
  uint index;        // pool index or kInvalidBrick
  uvec2 mask;        // 64-bit occupancy mask, zero without a brick
  uvec2 unobserved;  // for a trace that watches observed space, the brick's unobserved voxels (below); else zero
  uvec2 unobservedBesideSurface;  // those of them with an occupied neighbour in the brick
};

CachedBrick noCachedBrick() { return CachedBrick(ivec3(-1), kInvalidBrick, uvec2(0u), uvec2(0u), uvec2(0u)); }

bool isCached(CachedBrick cached, ivec3 brick) { return all(equal(cached.brick, brick)); }

// Unobserved voxels (SPEC §6.4 at the voxel's scale): the empty voxels of a brick that holds surface which no view
// has seen holding a surface or seen through. A view that meets a wall at a grazing angle, or has seen it only a few
// times, leaves some of its voxels empty (SceneVoxelization fills a voxel only when a sample lands on its surface):
// such a voxel is most likely wall not yet seen, and a probe ray through it would find the sky or the sunlit ground
// behind the wall. A trace that watches observed space meets the surface beside it, ends unknown beside it or goes on
// as through unobserved space (meetsSurfaceBeside, passUnobservedVoxel). Only in a brick holding surface: an empty
// brick of the pool is one being filled or released, and a trace that steps over empty bricks never looks in.
void loadBrick(inout CachedBrick cached, VoxelWalk walk, bool watchesVoxels, inout uint reads) {
  ivec3 brick = walk.voxel >> kBrickLevel;
  if (isCached(cached, brick)) return;
  cached.brick = brick;
  uint index = brickLookup[localCellIndex(brick, 0u, walk.volumeLayout)];
  cached.index = index == kAllocatingBrick ? kInvalidBrick : index;  // mid-allocation: not there yet
  cached.mask = uvec2(0u);
  cached.unobserved = uvec2(0u);
  cached.unobservedBesideSurface = uvec2(0u);
  reads += 1u;
  if (cached.index != kInvalidBrick) {
    cached.mask = bricks[cached.index].occupancy;
    reads += 1u;
    if (watchesVoxels && any(notEqual(cached.mask, uvec2(0u)))) {
      cached.unobserved = ~(bricks[cached.index].observed | cached.mask);
      cached.unobservedBesideSurface = cached.unobserved & voxelsBesideVoxels(cached.mask);
      reads += 1u;
    }
  }
}

ivec3 voxelInBrick(ivec3 voxel) { return voxel & ((1 << kBrickLevel) - 1); }

bool voxelBitSet(uvec2 mask, ivec3 voxelInBrick) { return maskHasVoxel(mask, voxelBit(uvec3(voxelInBrick))); }

// Level 1 from the mask: any of the 2×2×2 voxels (blockBitsInWord).
bool blockOccupied(uvec2 mask, ivec3 voxelInBrick) {
  uvec3 block = uvec3(voxelInBrick >> 1);
  return ((block.z == 0u ? mask.x : mask.y) & blockBitsInWord(block)) != 0u;
}

// The grid word last read at each grid level (2, 3, 4 in x, y, z; 5 or 6 in w, which hold few words): one word holds
// the bits of 32 consecutive cells along X, which a walk often tests one after another.
struct CachedGridWords {
  uvec4 address;
  uvec4 bits;
};

CachedGridWords noCachedGridWords() { return CachedGridWords(uvec4(0xffffffffu), uvec4(0u)); }

// Where the bit of the level-`level` cell holding the walk's voxel lies: in the occupancy grid, and at the same place
// in the observed space's bit volumes (the same layout), so that a step that asks both works it out once.
struct GridBit {
  uvec2 address;  // gridBitAddressOfLocalCell
  int slot;       // the level's place in CachedGridWords
};

GridBit gridBitOf(int level, VoxelWalk walk) {
  return GridBit(gridBitAddressOfLocalCell(uint(level), walk.voxel >> level, walk.volumeLayout),
                 min(level - kBrickLevel, 3));
}

// Whether a cell's bit is set in the occupancy grid or, with `observedSpaceBits`, in the observed space's bit volumes
// (GLSL cannot pass a buffer, so a flag picks it).
bool gridBitSet(bool observedSpaceBits, GridBit bit, inout CachedGridWords cached, inout uint reads) {
  if (cached.address[bit.slot] != bit.address.x) {
    cached.address[bit.slot] = bit.address.x;
    cached.bits[bit.slot] = observedSpaceBits ? observedSpace[bit.address.x] : occupancyGrid[bit.address.x];
    reads += 1u;
  }
  return (cached.bits[bit.slot] & bit.address.y) != 0u;
}

// Whether the brick cell a walk is in holds no voxel and has not been observed (the flat DDA's test; the hierarchical
// one makes it from its grid words).
bool brickUnobserved(VoxelWalk walk, CachedBrick brick, inout CachedGridWords observed, inout uint reads) {
  return all(equal(brick.mask, uvec2(0u))) && !gridBitSet(true, gridBitOf(kBrickLevel, walk), observed, reads);
}

// What a cell of the walk holds for the hierarchical DDA: nothing it must look into, something (an occupied voxel
// in it, or — while a trace watches observed space — an unobserved brick cell or voxel), at the brick level no voxel
// and no observation, or at the voxel level an unobserved voxel.
const uint kCellEmpty = 0u;
const uint kCellOccupied = 1u;
const uint kCellUnobserved = 2u;
const uint kCellUnobservedVoxel = 3u;

// Whether the walk is in an unobserved voxel that counts: any but the one the ray starts in — a probe stands in empty
// space, whether or not a view has seen it so.
bool countsAsUnobservedVoxel(VoxelWalk walk, uvec2 watchedVoxels) {
  return walk.distance > 0.0 && voxelBitSet(watchedVoxels, voxelInBrick(walk.voxel));
}

// The unobserved voxels of the brick a walk watches: all of them until it has entered unobserved space; after that
// only those beside a surface, which may end it (passUnobservedVoxel) — past air it would go on as it is, so it
// need not step through that air voxel by voxel.
uvec2 watchedUnobservedVoxels(CachedBrick brick, bool unobserved) {
  return unobserved ? brick.unobservedBesideSurface : brick.unobserved;
}

// What the level-`level` cell holding the walk's voxel holds: grid levels from the grid (except for the brick
// already at hand), finer ones from the brick's masks. `watchesCells`: unobserved brick cells count (the walk has
// not entered unobserved space yet), and so do unobserved voxels beside no surface; `watchesVoxels`: unobserved voxels
// do.
uint cellContents(VoxelWalk walk, int level, bool watchesCells, bool watchesVoxels, inout CachedBrick brick,
                  inout CachedGridWords grid, inout CachedGridWords observed, inout uint reads) {
  bool gridLevel = level >= kBrickLevel;
  // A walk at a finer level can step straight into the next brick, which no test at the brick level has seen.
  bool newBrick = !isCached(brick, walk.voxel >> kBrickLevel);
  if (!gridLevel) loadBrick(brick, walk, watchesVoxels, reads);
  bool brickEmpty = all(equal(brick.mask, uvec2(0u)));
  // The cell's bit in the grids; at a finer level its brick's, which the observed space below asks about.
  GridBit cellBit = gridBitOf(gridLevel ? level : kBrickLevel, walk);
  bool occupied =
      gridLevel && (level == kBrickLevel && !newBrick ? !brickEmpty : gridBitSet(false, cellBit, grid, reads));
  // Whether the cell is unobserved, asked at one place for both kinds of level — at a grid level of an empty cell, at
  // a finer one of a brick just entered that holds no voxel — because on lavapipe every place in a loop that reads a
  // buffer costs a read, lane by lane, on every step of the loop, whether or not a lane takes it.
  bool asksObserved = watchesCells && (gridLevel ? !occupied : newBrick && brickEmpty);
  bool unobservedCell = asksObserved && !gridBitSet(true, cellBit, observed, reads);
  if (gridLevel) {
    if (occupied) return kCellOccupied;
    if (!unobservedCell) return kCellEmpty;
    return level == kBrickLevel ? kCellUnobserved : kCellOccupied;
  }
  if (unobservedCell) return kCellUnobserved;
  ivec3 inBrick = voxelInBrick(walk.voxel);
  uvec2 watchedVoxels = watchedUnobservedVoxels(brick, !watchesCells);
  if (level == kVoxelLevel) {
    if (voxelBitSet(brick.mask, inBrick)) return kCellOccupied;
    return countsAsUnobservedVoxel(walk, watchedVoxels) ? kCellUnobservedVoxel : kCellEmpty;
  }
  return blockOccupied(brick.mask | watchedVoxels, inBrick) ? kCellOccupied : kCellEmpty;
}

// Moves the walk past the level-`level` cell it is in: to the voxel the ray reaches by the first crossing of the
// cell's boundary. Every crossing before that one is inside the cell, so on the other axes the voxel stays within
// the cell. False when that crossing is past maxDistance or out of the volume — on any axis: a cell of a local level
// at the volume's far faces reaches past it, and a ray may leave the volume through another face on its way across.
bool stepOverCell(inout VoxelWalk walk, int level) {
  ivec3 cellMin = (walk.voxel >> level) << level;
  ivec3 cellMax = cellMin + ((1 << level) - 1);
  vec3 exits;
  for (int axis = 0; axis < 3; ++axis)
    exits[axis] = crossingDistance(walk, axis, exitPlane(walk.voxel[axis], level, walk.step[axis]));
  int exitAxis = firstCrossingAxis(exits);
  float distance = exits[exitAxis];
  if (distance > walk.maxDistance) return false;
  ivec3 next;
  for (int axis = 0; axis < 3; ++axis) {
    int limit = walk.step[axis] > 0 ? cellMax[axis] : cellMin[axis];
    next[axis] = axis == exitAxis ? limit + walk.step[axis]
                                  : coordinateAtCrossing(walk, axis, distance, exitAxis, walk.voxel[axis], limit);
  }
  if (any(lessThan(next, ivec3(0))) || any(greaterThanEqual(next, walk.sizeVoxels))) return false;
  walk.voxel = next;
  walk.distance = distance;
  return true;
}

VoxelHit voxelMiss(float maxDistance, uint reads) {
  return VoxelHit(false, maxDistance, kInvalidBrick, 0u, vec3(0.0), vec3(0.0), reads, false, maxDistance, false);
}

// Whether a trace watches observed space (SPEC §6.4) — the probes' rays, whose misses through space no view has
// observed are not the sky — or takes every brick cell without voxels for empty (a visibility test between two
// points, most debug views). A watching trace goes on through unobserved brick cells: a surface it meets beyond is a
// surface the views did see, and the rays that pass a pillar's blind spot to a sunlit wall find the wall. It ends,
// unknown, where it leaves a brick that holds surface after passing an unobserved voxel of it beside a surface
// (loadBrick, passUnobservedVoxel) without meeting a surface there; past unobserved air of the brick it goes on.
const bool kWatchObservedSpace = true;
const bool kIgnoreObservedSpace = false;

VoxelHit withObservation(VoxelHit hit, bool unobserved, float unobservedDistance) {
  hit.unobserved = unobserved;
  hit.unobservedDistance = unobserved ? unobservedDistance : hit.distance;
  return hit;
}

// An unobserved voxel next to a surface, on a side the ray moves towards, is most likely that surface not yet seen — a
// hole a grazing view left in a wall or a floor — so the ray meets that surface there, with its light (black from
// behind), as it would have without the hole: taken for unknown, a hole in a shaded wall would stand for the mean
// light of the probe's surfaces, sunlit ones included. Of several such neighbours, the one across the axis the ray
// moves along fastest.
bool meetsSurfaceBeside(VoxelWalk walk, CachedBrick brick, vec3 direction, inout uint reads, out VoxelHit met) {
  ivec3 inBrick = voxelInBrick(walk.voxel);
  int found = -1;
  float fastest = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    ivec3 neighbour = inBrick;
    neighbour[axis] += walk.step[axis];
    bool inside = walk.step[axis] != 0 && neighbour[axis] >= 0 && neighbour[axis] < int(kBrickSizeVoxels);
    if (inside && abs(direction[axis]) > fastest && voxelBitSet(brick.mask, neighbour)) {
      fastest = abs(direction[axis]);
      found = int(voxelBit(uvec3(neighbour)));
    }
  }
  if (found < 0) return false;
  Voxel voxel = voxels[brick.index * kVoxelsPerBrick + uint(found)];
  reads += 1u;
  vec3 normal = voxelNormal(voxel);
  vec3 radiance = dot(normal, direction) > 0.0 ? vec3(0.0) : unpackR11G11B10F(voxel.radiance);
  met = VoxelHit(true, walk.distance, brick.index, uint(found), radiance, normal, reads, false, walk.distance, false);
  return true;
}

// An unobserved voxel a walk passes without meeting a surface ahead: the walk goes on to look for a surface in the
// same brick — the air in front of a floor that no view has seen at the right angle hides nothing, most likely, from a
// ray that meets the floor beyond it. Where it leaves the brick without one, it depends on what the voxels it passed
// there lie beside. Beside a surface of the brick (on a side the ray moves away from or along), such a voxel is most
// likely that surface not yet seen as well — the rim of a hole, the junction of a wall and a floor —: the walk ends
// unknown beside it, with the light the ray would have met there, the surface's as seen from the ray's side (black
// from behind). Beside none, they are air no view has seen, as an unobserved brick cell is: the walk goes on,
// unobserved from them, so that a surface it meets beyond is a surface the views saw and a miss is not the sky. (An
// unobserved voxel once ended the ray standing for the mean light of the probe's surfaces: the air at the corners of a
// sunlit fence's holes lit the floor in front of it with the sunlit floor's own light; and standing for that mean
// only beside a surface, `two-rooms` leaked more: docs/QUALITY.md, "What an unobserved voxel stands for".)
struct UnobservedVoxelPassed {
  bool passed;
  ivec3 brick;         // the brick cell they lie in
  float distance;      // where the ray first entered unobserved space (metres)
  bool besideSurface;  // one of them lies beside a surface of the brick:
  uint besideBrick;    // the brick's pool index
  uint besideVoxel;    // and the surface's voxel in it (voxelBit)
};
const UnobservedVoxelPassed kNoUnobservedVoxelPassed =
    UnobservedVoxelPassed(false, ivec3(0), 0.0, false, kInvalidBrick, 0u);

// The occupied neighbour of the walk's voxel inside its brick, across the axis the ray moves along fastest; -1 where
// none is.
int surfaceBeside(VoxelWalk walk, CachedBrick brick, vec3 direction) {
  ivec3 inBrick = voxelInBrick(walk.voxel);
  int found = -1;
  float fastest = -1.0;
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = -1; side <= 1; side += 2) {
      ivec3 neighbour = inBrick;
      neighbour[axis] += side;
      bool inside = neighbour[axis] >= 0 && neighbour[axis] < int(kBrickSizeVoxels);
      if (inside && abs(direction[axis]) > fastest && voxelBitSet(brick.mask, neighbour)) {
        fastest = abs(direction[axis]);
        found = int(voxelBit(uvec3(neighbour)));
      }
    }
  }
  return found;
}

// The walk at an unobserved voxel where it meets no surface ahead (meetsSurfaceBeside).
void passUnobservedVoxel(inout UnobservedVoxelPassed pending, VoxelWalk walk, CachedBrick brick, vec3 direction,
                         bool crossedUnobserved, float unobservedDistance) {
  if (pending.besideSurface) return;
  if (!pending.passed) {
    pending.passed = true;
    pending.brick = walk.voxel >> kBrickLevel;
    pending.distance = crossedUnobserved ? unobservedDistance : walk.distance;
  }
  int beside = surfaceBeside(walk, brick, direction);
  if (beside >= 0) {
    pending.besideSurface = true;
    pending.besideBrick = brick.index;
    pending.besideVoxel = uint(beside);
  }
}

// Whether the walk has left the brick of the unobserved voxels it passed without meeting a surface there: it ends
// there beside a surface (unknownBesideSurface) or goes on past air (goOnPastUnobservedAir).
bool leftUnobservedVoxelsBrick(UnobservedVoxelPassed pending, VoxelWalk walk) {
  return pending.passed && any(notEqual(walk.voxel >> kBrickLevel, pending.brick));
}

// Past unobserved air alone, the walk goes on, unobserved from that air.
void goOnPastUnobservedAir(inout UnobservedVoxelPassed pending, inout bool unobserved, inout float unobservedDistance) {
  if (!unobserved) {
    unobserved = true;
    unobservedDistance = pending.distance;
  }
  pending = kNoUnobservedVoxelPassed;
}

// A walk that ends beside a surface (leftUnobservedVoxelsBrick): no hit, unobserved from where it first entered
// unobserved space, with the surface's voxel, normal and light as the ray would have met it.
VoxelHit unknownBesideSurface(UnobservedVoxelPassed pending, vec3 direction, float maxDistance, uint reads) {
  Voxel voxel = voxels[pending.besideBrick * kVoxelsPerBrick + pending.besideVoxel];
  vec3 normal = voxelNormal(voxel);
  vec3 radiance = dot(normal, direction) > 0.0 ? vec3(0.0) : unpackR11G11B10F(voxel.radiance);
  return VoxelHit(false, maxDistance, pending.besideBrick, pending.besideVoxel, radiance, normal, reads + 1u, true,
                  pending.distance, true);
}

// The end of a walk that met no surface.
VoxelHit walkMissed(UnobservedVoxelPassed pending, vec3 direction, bool unobserved, float unobservedDistance,
                    float maxDistance, uint reads) {
  if (pending.besideSurface) return unknownBesideSurface(pending, direction, maxDistance, reads);
  if (pending.passed) goOnPastUnobservedAir(pending, unobserved, unobservedDistance);
  return withObservation(voxelMiss(maxDistance, reads), unobserved, unobservedDistance);
}

// How far in front of a voxel's surface plane (in voxels) a ray still meets it: the plane's 8-bit quantisation (0.007)
// and the depth buffer's error, with room to spare.
const float kVoxelPlaneTolerance = 0.05;

// Where the ray leaves the voxel it is in, or ends inside it.
float voxelExitDistance(VoxelWalk walk) {
  vec3 exits;
  for (int axis = 0; axis < 3; ++axis)
    exits[axis] = crossingDistance(walk, axis, exitPlane(walk.voxel[axis], kVoxelLevel, walk.step[axis]));
  return min(exits[firstCrossingAxis(exits)], walk.maxDistance);
}

// The ray at the occupied voxel the walk is in: a hit when it meets the voxel's surface — it is on or behind the
// surface's plane where it enters the voxel or where it leaves it — and a miss when it passes through the part of the
// voxel in front of that plane. A surface that fills a voxel only in part (a 2 cm light panel in a 12.5 cm voxel, a
// box top 5 cm under a voxel boundary) then stops rays where it is, not at the voxel's box, which would bring it nearer
// to the probes and make it larger in their view (docs/QUALITY.md, "Where the Cornell error comes from").
VoxelHit voxelHitAt(VoxelWalk walk, CachedBrick cached, vec3 direction, uint reads) {
  uint voxelIndex = voxelBit(uvec3(voxelInBrick(walk.voxel)));
  Voxel voxel = voxels[cached.index * kVoxelsPerBrick + voxelIndex];
  reads += 1u;
  vec3 normal = voxelNormal(voxel);
  uint planeCode = voxelPlaneCode(voxel);
  if (planeCode != 0u) {
    vec3 centre = vec3(walk.voxel) + 0.5;
    float plane = unpackVoxelPlane(planeCode);
    float entering = dot(walk.origin + walk.voxelsPerMetre * walk.distance - centre, normal) - plane;
    float leaving = dot(walk.origin + walk.voxelsPerMetre * voxelExitDistance(walk) - centre, normal) - plane;
    if (min(entering, leaving) > kVoxelPlaneTolerance) return voxelMiss(walk.maxDistance, reads);
  }
  // A ray that meets the surface from behind sees no light, so thin walls do not pass light (SPEC §4.4).
  vec3 radiance = dot(normal, direction) > 0.0 ? vec3(0.0) : unpackR11G11B10F(voxel.radiance);
  return VoxelHit(true, walk.distance, cached.index, voxelIndex, radiance, normal, reads, false, walk.distance, false);
}

// The hierarchical DDA (SPEC §4.4, the talk's "Octree Trace"): while the cell at the current level is empty, step
// over it and go a level up; when it is occupied, go a level down; an occupied voxel ends the trace. One refinement
// of the talk's rule saves reads without skipping any cell: after a step the walk goes up only if the parent cell's
// occupancy is unknown — it is known (occupied) while the walk is still inside a cell it came down from.
// A trace that watches observed space looks for unobserved brick cells (cellContents) until it has crossed one, and
// for unobserved voxels all the way. The walk starts at `startLevel` (below).
VoxelHit walkOccupancyHierarchy(VoxelTraceFrame volumeFrame, vec3 origin, vec3 direction, float maxDistance,
                                bool watchesObservedSpace, int startLevel) {
  VoxelWalk walk;
  if (!beginVoxelWalk(volumeFrame, origin, direction, maxDistance, walk)) return voxelMiss(maxDistance, 0u);
  CachedBrick cached = noCachedBrick();
  CachedGridWords grid = noCachedGridWords();
  CachedGridWords observed = noCachedGridWords();
  uint reads = 0u;
  // The talk starts at the finest level. traceVoxelsHierarchical starts at the coarsest toroidal level (4 m cells):
  // that settles a ray leaving open space with one read and costs an occupied start only the grid words on the way
  // down, which later steps often reuse; a ray that goes on through open space climbs to the local levels as it
  // steps. (From the 16 m level, a room's rays read more words on the way down than they save.)
  // traceVoxelsNearSurfaces starts at the brick level: around a point near surfaces the coarser cells are occupied,
  // and a walk from the top would only step down through them.
  int level = startLevel;
  uint knownOccupiedLevels = 0u;  // bit L: the walk came down from its current level-L cell
  bool unobserved = false;
  float unobservedDistance = maxDistance;
  UnobservedVoxelPassed passed = kNoUnobservedVoxelPassed;
  bool stepsFirst = false;  // the walk is done with the cell it is in
  for (;;) {
    // The walk to the next voxel it must look into: an occupied voxel, or an unobserved one. Looking into a voxel
    // (voxelHitAt, meetsSurfaceBeside) is the heavier part and the rarer one, so it stays out of this loop: lavapipe
    // runs a loop's whole body, every branch, on each step of any of its lanes (SIMD masks, not jumps).
    uint contents = kCellEmpty;
    bool walking = true;
    bool leftPassedBrick = false;
    for (;;) {
      if (stepsFirst) {
        ivec3 previous = walk.voxel;
        if (!stepOverCell(walk, level)) {
          walking = false;
          break;
        }
        // The cells that changed are those of the levels up to the highest bit in which the voxel coordinates
        // changed.
        ivec3 changedBits = previous ^ walk.voxel;
        int highestChangedLevel = findMSB(changedBits.x | changedBits.y | changedBits.z);
        knownOccupiedLevels &= ~((2u << uint(highestChangedLevel)) - 1u);
        if (level < kTopLevel && (knownOccupiedLevels & (1u << uint(level + 1))) == 0u) ++level;
      }
      stepsFirst = true;
      leftPassedBrick = leftUnobservedVoxelsBrick(passed, walk);
      if (leftPassedBrick) break;
      contents = cellContents(walk, level, watchesObservedSpace && !unobserved, watchesObservedSpace, cached, grid,
                              observed, reads);
      if (contents == kCellUnobserved) {
        unobserved = true;
        unobservedDistance = walk.distance;
      } else if (contents == kCellOccupied && level != kVoxelLevel) {
        knownOccupiedLevels |= 1u << uint(level);
        --level;
        stepsFirst = false;
      } else if (contents != kCellEmpty) {
        break;
      }
    }
    if (!walking) break;
    if (leftPassedBrick) {
      if (passed.besideSurface) return unknownBesideSurface(passed, direction, maxDistance, reads);
      goOnPastUnobservedAir(passed, unobserved, unobservedDistance);
      stepsFirst = false;  // the cell it has stepped into is yet to be looked at
    } else if (contents == kCellUnobservedVoxel) {
      VoxelHit met;
      if (meetsSurfaceBeside(walk, cached, direction, reads, met))
        return withObservation(met, unobserved, unobservedDistance);
      passUnobservedVoxel(passed, walk, cached, direction, unobserved, unobservedDistance);
    } else {
      VoxelHit hit = voxelHitAt(walk, cached, direction, reads);
      if (hit.hit) return withObservation(hit, unobserved, unobservedDistance);
      reads = hit.reads;  // in front of the voxel's surface all the way through: on, as past an empty voxel
    }
  }
  return walkMissed(passed, direction, unobserved, unobservedDistance, maxDistance, reads);
}

// The traces this invocation has made and their reads, whichever function made them: the work a pass counts
// (shared/work_counters.h) where it counts it. Two additions a trace, counted or not.
struct TracedWork {
  uint rays;
  uint reads;
};
TracedWork tracedWork = TracedWork(0u, 0u);

VoxelHit countTrace(VoxelHit hit) {
  tracedWork.rays += 1u;
  tracedWork.reads += hit.reads;
  return hit;
}

VoxelHit traceVoxelsHierarchical(vec3 origin, vec3 direction, float maxDistance, bool watchesObservedSpace) {
  return countTrace(
      walkOccupancyHierarchy(voxelTraceFrame(), origin, direction, maxDistance, watchesObservedSpace,
                             int(kFirstLocalGridLevel) - 1));
}

// A trace from a point near surfaces: a probe's ray (ProbePlacement keeps the probes with voxels within their reach),
// a visibility test between a probe and a point it lights or between two probes. It finds what traceVoxelsHierarchical
// finds, in fewer steps.
VoxelHit traceVoxelsNearSurfaces(VoxelTraceFrame volumeFrame, vec3 origin, vec3 direction, float maxDistance,
                                 bool watchesObservedSpace) {
  return countTrace(
      walkOccupancyHierarchy(volumeFrame, origin, direction, maxDistance, watchesObservedSpace, kBrickLevel));
}

VoxelHit traceVoxelsNearSurfaces(vec3 origin, vec3 direction, float maxDistance, bool watchesObservedSpace) {
  return traceVoxelsNearSurfaces(voxelTraceFrame(), origin, direction, maxDistance, watchesObservedSpace);
}

#endif
