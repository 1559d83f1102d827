#version 450
// PrimaryHits: the surface each pixel sees and its direct light, once per image (nothing here is random). The primary
// ray goes through the pixel centre with the renderer's own matrices and starts on the near plane, where the
// rasterizer clips, so both see the same surface point: albedo, normal and depth match the G-buffer's. E_direct comes
// from the delta lights with exact shadow rays.
#include "reference/scene_tracing.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = kBindPrimaryRayOrigin, rgba32f) writeonly uniform image2D rayOrigins;
layout(binding = kBindPrimaryNormal, rgba32f) writeonly uniform image2D normals;
layout(binding = kBindPrimaryAlbedo, rgba32f) writeonly uniform image2D albedos;
layout(binding = kBindPrimaryRadiance, rgba32f) writeonly uniform image2D primaryRadiance;
layout(binding = kBindPrimaryDirect, rgba32f) writeonly uniform image2D directIrradiances;
layout(binding = kBindPrimaryDistance, r32f) writeonly uniform image2D viewDistances;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, ivec2(frame.viewportSize.xy)))) return;

  vec4 nearPoint = frame.inverseViewProjection * vec4(ssvgiPixelToNdc(vec2(pixel), frame.viewportSize.xy), 1.0, 1.0);
  vec3 origin = nearPoint.xyz / nearPoint.w;
  vec3 direction = normalize(origin - frame.cameraPosition.xyz);
  RayHit hit;
  if (!traceNearest(origin, direction, hit)) {
    imageStore(rayOrigins, pixel, vec4(0.0));
    imageStore(normals, pixel, vec4(0.0));
    imageStore(albedos, pixel, vec4(0.0));
    imageStore(primaryRadiance, pixel, vec4(evaluateSky(frame.sky, direction), 0.0));
    imageStore(directIrradiances, pixel, vec4(0.0));
    imageStore(viewDistances, pixel, vec4(0.0));
    return;
  }
  Surface surface = surfaceAt(direction, hit);
  vec3 rayOrigin = offsetRayOrigin(surface.position, surface.geometricNormal);
  imageStore(rayOrigins, pixel, vec4(rayOrigin, 1.0));
  imageStore(normals, pixel, vec4(surface.normal, 0.0));
  imageStore(albedos, pixel, vec4(surface.albedo, 1.0));
  imageStore(primaryRadiance, pixel, vec4(surface.emission, 0.0));
  imageStore(directIrradiances, pixel, vec4(directIrradiance(surface.position, surface.normal, rayOrigin), 1.0));
  imageStore(viewDistances, pixel, vec4(distance(surface.position, frame.cameraPosition.xyz)));
}
