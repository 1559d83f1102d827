#include "probe_passes.h"
#include "ssvgi_shaders.h"

namespace ssvgi::gi {

ProbeRelocate::ProbeRelocate(gpu::Device& device) : pipeline_(device, shaders::probe_relocate_comp) {}

void ProbeRelocate::record(gpu::CommandList& commands, const VoxelScene& scene, const ProbeVolume& probes) {
  auto scope = commands.scope("ssvgi: ProbeRelocate");
  const gpu::Bindings bindings = probes.listedProbeBindings(scene.bindings());
  commands.dispatchIndirect(pipeline_, bindings, probes.list(), 0);  // one workgroup per listed probe
}

}  // namespace ssvgi::gi
