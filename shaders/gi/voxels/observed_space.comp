#version 450
// ObservedSpace: marks the brick cells a view has observed (SPEC §6.4, "unknown is not sky"; voxel_interface.h). One
// thread per pixel in stride × stride (the offset inside the block moves every frame, so over stride² frames every
// pixel is visited) walks the brick cells along the pixel's ray from the near plane to the surface it shows, or —
// where nothing was drawn — out of the volume: the view saw through them. The cell of the surface it shows is left as
// it was, whether or not the view writes voxels: a surface on a cell's face may be held by the voxels of the cell on
// its other side (heldSurfacePoint), and a thick wall's inner face seen on a cell boundary would mark the wall's own
// cell, which no view sees into, as known empty — a probe ray crossing it before any voxel is there would find the
// sky beyond the wall. Where the surface's voxels are, the trace reads them at the voxel's scale (Brick::observed).
// Only the cell in front of a surface held beyond it is marked (surfaceHeldBeyond).
#define SSVGI_OBSERVED_SPACE_WRITABLE
#include "gi/gi_frame.glsl"
#include "gi/voxels/voxel_access.glsl"
#include "gi/work_counting.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = kBindFirstPassSlot) uniform sampler2D depthBuffer;

layout(push_constant) uniform Push { uint pixelStride; };
// Whether the view's projection is orthographic (ObservedSpace::record tells by GiFrame::viewProjection): a pipeline
// of its own, since lavapipe would run seesThroughCell on every step of every perspective view's walk, taken or not.
layout(constant_id = 0) const bool kOrthographic = false;

// The depth at which a pixel where nothing was drawn is followed: a perspective view's far plane (depth 0) lies at
// infinity, and this one lies beyond any volume (near plane / 1e-6); an orthographic view's is its far plane.
const float kNothingDrawnDepth = 1e-6;

bool brickCellObserved(ivec3 worldBrick, VolumeLayout volumeLayout) {
  uvec2 address = gridBitAddressInVolume(kFirstGridLevel, worldBrick, volumeLayout);
  return (observedSpace[address.x] & address.y) != 0u;
}

// Marks a brick cell observed. The walk that observes the last brick cell of a level-3 cell marks that one too, and so
// on for level 4. (Two walks that observe a cell's last two bricks at once may both miss it; the trace then goes
// down to the bricks, which is only slower.)
void markObserved(ivec3 worldBrick, VolumeLayout volumeLayout) {
  uvec2 address = gridBitAddressInVolume(kFirstGridLevel, worldBrick, volumeLayout);
  if ((atomicOr(observedSpace[address.x], address.y) & address.y) != 0u) return;
  for (uint level = kFirstGridLevel + 1u; level < kFirstLocalGridLevel; ++level) {
    ivec3 cell = worldBrick >> (level - kFirstGridLevel);
    for (int child = 0; child < 8; ++child) {
      uvec2 childAddress =
          gridBitAddressInVolume(level - 1u, cell * 2 + ivec3(child & 1, (child >> 1) & 1, child >> 2), volumeLayout);
      if ((observedSpace[childAddress.x] & childAddress.y) == 0u) return;
    }
    uvec2 parent = gridBitAddressInVolume(level, cell, volumeLayout);
    atomicOr(observedSpace[parent.x], parent.y);
  }
}

// An orthographic view's footprint of a brick cell — its corners' bounding rectangle in pixels and its farthest
// point's depth — less those of the cell's minimum corner: the same for every cell, as the projection is affine.
struct CellFootprint {
  vec2 low;
  vec2 high;
  float farthestDepth;
  // Which texels around it seesThroughCell looks at: those whose centres lie within `margin` texels of it (a
  // hundredth more for rounding), every `stride`-th along each axis.
  vec2 margin;
  ivec2 stride;
  // What seesThroughCell reads of the frame, read once rather than on every step of the walk (voxel_access.glsl's
  // VolumeLayout says why).
  mat4 viewProjection;
  float brickSize;
};

CellFootprint orthographicCellFootprint(vec2 size) {
  vec4 origin = frame.viewProjection * vec4(0.0, 0.0, 0.0, 1.0);
  vec2 originPixel = ssvgiNdcToPixel(origin.xy, size);
  CellFootprint footprint =
      CellFootprint(vec2(1e30), vec2(-1e30), 1e30, vec2(0.0), ivec2(1), frame.viewProjection, volume.brickSize);
  for (int corner = 0; corner < 8; ++corner) {
    vec3 point = vec3(corner & 1, (corner >> 1) & 1, corner >> 2) * volume.brickSize;
    vec4 clip = frame.viewProjection * vec4(point, 1.0);
    vec2 pixel = ssvgiNdcToPixel(clip.xy, size) - originPixel;
    footprint.low = min(footprint.low, pixel);
    footprint.high = max(footprint.high, pixel);
    footprint.farthestDepth = min(footprint.farthestDepth, clip.z - origin.z);
  }
  // A texel's width in metres along the view's rows and columns: 2 / (NDC per metre × pixels).
  mat4 projection = frame.viewProjection;
  vec2 ndcPerMetre = vec2(length(vec3(projection[0][0], projection[1][0], projection[2][0])),
                          length(vec3(projection[0][1], projection[1][1], projection[2][1])));
  vec2 texelMetres = 2.0 / (ndcPerMetre * size);
  float voxelSize = volume.voxelSize;
  footprint.margin = max(texelMetres - voxelSize, 0.0) / texelMetres + 0.01;
  footprint.stride = max(ivec2(voxelSize / texelMetres), ivec2(1));
  return footprint;
}

// Whether an orthographic view sees through a whole brick cell: every texel around the cell's footprint shows a
// surface beyond the cell's farthest point. Such a view (the sun's, the overhead view) looks down past roofs' rims
// from afar: a ray that crosses a cell in part, beside the wall under a rim, observes only that part, and the rest may
// hide the wall. A texel's depth is that of the line through its centre, so the texels looked at are those whose
// centres lie within the footprint grown by a texel's width less a voxel's, at most a voxel apart: of a wall a voxel
// thick under a roof flush with its outer face, the first centre past the rim, which shows the roof, is then always
// among them. (A wider texel that straddles the rim may see past it while it covers the wall's top, and the next one
// lie more than half a texel off the footprint; jittered, a view comes to that offset in time, and a cell once
// observed stays so.) Texels no wider than a voxel count only where their centres lie in the footprint: one that
// straddles its edge shows what lies beyond as often as what lies within, and counting more would leave the cells
// beside every wall unobserved.
bool seesThroughCell(ivec3 worldBrick, vec2 size, CellFootprint footprint) {
  vec4 corner = footprint.viewProjection * vec4(vec3(worldBrick) * footprint.brickSize, 1.0);
  vec2 cornerPixel = ssvgiNdcToPixel(corner.xy, size);
  vec2 low = cornerPixel + footprint.low, high = cornerPixel + footprint.high;
  float farthestDepth = corner.z + footprint.farthestDepth;
  // Texel i's centre lies at i + 0.5.
  ivec2 first = clamp(ivec2(ceil(low - footprint.margin - 0.5)), ivec2(0), ivec2(size) - 1);
  ivec2 last = clamp(ivec2(floor(high + footprint.margin - 0.5)), ivec2(0), ivec2(size) - 1);
  if (any(lessThan(last, first))) return true;
  for (int y = first.y; y <= last.y; y += footprint.stride.y)
    for (int x = first.x; x <= last.x; x += footprint.stride.x)
      if (texelFetch(depthBuffer, ivec2(x, y), 0).r > farthestDepth) return false;
  return true;
}

// Whether the surface a walk ends at (in brick units) lies on a face of the cell the walk ends in, within a hair, and
// its voxels lie beyond that face (heldSurfacePoint, with the face's normal towards the view): the cell then holds
// none of that surface, only the air the view saw through in front of it — above a floor on the grid, the layer where
// probes stand, which an orthographic view would otherwise never observe (every texel of its footprint shows the
// floor, nearer than the cell's farthest corner).
bool surfaceHeldBeyond(ivec3 cell, vec3 surface, ivec3 stepDirection) {
  float hair = 0.02 * volume.voxelSize * volume.bricksPerMetre;
  for (int axis = 0; axis < 3; ++axis) {
    int step = stepDirection[axis];
    if (step == 0 || abs(surface[axis] - float(cell[axis] + max(step, 0))) > hair) continue;
    vec3 normal = vec3(0.0);
    normal[axis] = float(-step);
    return worldBrickOf(heldSurfacePoint(surface * volume.brickSize, normal)) != cell;
  }
  return false;
}

// A walk's place among the brick cells and what it steps with (main).
struct CellWalk {
  ivec3 cell;
  vec3 nextCrossing;  // the segment's parameter t where it crosses into the next cell along each axis
  ivec3 stepDirection;
  vec3 crossingStep;
  float last;  // the parameter t where the walk ends
  ivec3 lowest;
  ivec3 highest;  // the volume's cells, inclusive
};

// Steps into the next cell; false where the walk ends first (its end, or the volume's edge).
bool stepToNextCell(inout CellWalk walk) {
  vec3 crossing = walk.nextCrossing;
  int axis = crossing.x <= crossing.y && crossing.x <= crossing.z ? 0 : (crossing.y <= crossing.z ? 1 : 2);
  if (crossing[axis] > walk.last) return false;
  walk.cell[axis] += walk.stepDirection[axis];
  if (walk.cell[axis] < walk.lowest[axis] || walk.cell[axis] > walk.highest[axis]) return false;
  walk.nextCrossing[axis] += walk.crossingStep[axis];
  return true;
}

void main() {
  uint offset = frame.frameIndex % (pixelStride * pixelStride);
  uvec2 pixel = gl_GlobalInvocationID.xy * pixelStride + uvec2(offset % pixelStride, offset / pixelStride);
  if (any(greaterThanEqual(pixel, frame.size))) return;
  float depth = texelFetch(depthBuffer, ivec2(pixel), 0).r;
  vec2 size = vec2(frame.size);
  // The segment in brick units, clipped to the volume.
  float bricksPerMetre = volume.bricksPerMetre;
  vec3 start = reconstructPosition(frame.inverseViewProjection, vec2(pixel), size, 1.0) * bricksPerMetre;
  vec3 end = reconstructPosition(frame.inverseViewProjection, vec2(pixel), size, max(depth, kNothingDrawnDepth)) *
             bricksPerMetre;
  // The walk ends a hundredth of a voxel (heldSurfacePoint's hair) short of a surface: one on a cell's face may be held
  // on either side of it, and the cell in front, where the walk then ends, is left as it was too — unless the surface
  // is held on its far side (surfaceHeldBeyond).
  vec3 surface = end;
  if (depth > 0.0) end -= normalize(end - start) * (0.01 * volume.voxelSize * bricksPerMetre);
  vec3 segment = end - start;
  vec3 volumeMin = vec3(volume.originBrick);
  vec3 volumeMax = volumeMin + vec3(volumeDimensions());
  vec3 inverse = 1.0 / mix(segment, vec3(1.0), equal(segment, vec3(0.0)));
  vec3 entries = vec3(-1.0), exits = vec3(2.0);
  for (int axis = 0; axis < 3; ++axis) {
    if (segment[axis] == 0.0) {
      if (start[axis] < volumeMin[axis] || start[axis] >= volumeMax[axis]) return;
      continue;
    }
    bool increasing = segment[axis] > 0.0;
    entries[axis] = ((increasing ? volumeMin[axis] : volumeMax[axis]) - start[axis]) * inverse[axis];
    exits[axis] = ((increasing ? volumeMax[axis] : volumeMin[axis]) - start[axis]) * inverse[axis];
  }
  float first = max(0.0, max(max(entries.x, entries.y), entries.z));
  float last = min(1.0, min(min(exits.x, exits.y), exits.z));
  if (first > last) return;

  // A voxel DDA over brick cells (Amanatides & Woo), in the segment's parameter t ∈ [first, last].
  CellWalk walk;
  walk.lowest = volume.originBrick;
  walk.highest = walk.lowest + volumeDimensions() - 1;
  walk.cell = clamp(ivec3(floor(start + segment * first)), walk.lowest, walk.highest);
  walk.stepDirection = ivec3(sign(segment));
  walk.nextCrossing = (vec3(walk.cell + max(walk.stepDirection, ivec3(0))) - start) * inverse;
  walk.nextCrossing = mix(walk.nextCrossing, vec3(2.0), equal(walk.stepDirection, ivec3(0)));
  walk.crossingStep = abs(inverse);
  walk.last = last;
  ivec3 lastCell = clamp(ivec3(floor(start + segment * last)), walk.lowest, walk.highest);
  int maxSteps = volumeDimensions().x + volumeDimensions().y + volumeDimensions().z;
  // The surface's own cell is left as it was (above).
  bool endsAtSurface = depth > 0.0 && last == 1.0;
  // A perspective view's rays from inside the scene mark every cell they cross: its pixels are small where it looks
  // past a rim close by, and a cell's footprint is unbounded near its eye.
  CellFootprint footprint = orthographicCellFootprint(size);
  VolumeLayout layoutOfVolume = volumeLayout();
  uint crossedCells = 0u;
  // A cell once observed stays so: only the last cell and those not yet observed are looked at. The walk passes the
  // others in a loop of their own, which holds no look: lavapipe runs a loop's whole body while any of its lanes is in
  // it, and an orthographic view's look reads a dozen texels or more, a mark a dozen words.
  int stepCount = 0;
  for (;;) {
    bool atCellToLookAt = false;
    bool cellObserved = true;
    for (; stepCount < maxSteps; ++stepCount) {
      cellObserved = brickCellObserved(walk.cell, layoutOfVolume);
      atCellToLookAt = !cellObserved || all(equal(walk.cell, lastCell));
      if (atCellToLookAt) break;
      ++crossedCells;
      if (!stepToNextCell(walk)) break;
    }
    if (!atCellToLookAt) break;
    bool atLastCell = all(equal(walk.cell, lastCell));
    if (atLastCell && endsAtSurface) {
      if (surfaceHeldBeyond(walk.cell, surface, walk.stepDirection)) markObserved(walk.cell, layoutOfVolume);
      break;
    }
    if (!cellObserved && (!kOrthographic || seesThroughCell(walk.cell, size, footprint)))
      markObserved(walk.cell, layoutOfVolume);
    ++crossedCells;
    if (atLastCell || !stepToNextCell(walk)) break;
    ++stepCount;
  }
  if (countsWork()) {
    atomicAdd(work.observedSpaceRays, 1u);
    atomicAdd(work.observedSpaceCells, crossedCells);
  }
}
