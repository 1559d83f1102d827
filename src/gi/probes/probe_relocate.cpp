#include "probe_passes.h"
#include "ssvgi_shaders.h"

namespace ssvgi::gi {

ProbeRelocate::ProbeRelocate(gpu::Device& device) : pipeline_(device, shaders::probe_relocate_comp) {}

void ProbeRelocate::record(gpu::CommandList& commands, const VoxelScene& scene, const ProbeVolume& probes) {
  auto scope = commands.scope("ssvgi: ProbeRelocate");
  const gpu::Bindings bindings = probes.listedProbeBindings(scene.bindings());
  // One thread per listed probe: as many as the list may hold, those past its count leave at once.
  commands.dispatch(pipeline_, bindings, {probes.current().probeBudget, 1, 1});
}

}  // namespace ssvgi::gi
