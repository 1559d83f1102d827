#include "sky_map.h"

#include "shared/renderer_interface.h"
#include "ssvgi_renderer_shaders.h"

namespace ssvgi::renderer {

SkyMap::SkyMap(gpu::Device& device)
    : pipeline_(device, shaders::sky_map_comp),
      image_(device, {"sky map", VK_FORMAT_R16G16B16A16_SFLOAT, kWidth, kHeight, 1, 1,
                      VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT}) {}

void SkyMap::record(gpu::CommandList& commands, const gpu::Buffer& frameConstants) {
  auto scope = commands.scope("renderer: SkyMap");
  commands.dispatch(pipeline_,
                    gpu::Bindings()
                        .buffer(shader::kBindSkyMapFrame, frameConstants)
                        .image(shader::kBindSkyMapOutput, image_),
                    {kWidth, kHeight, 1});
  commands.use(image_, gpu::Usage::ComputeSampled);
}

}  // namespace ssvgi::renderer
