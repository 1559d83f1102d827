#include "probe_passes.h"
#include "ssvgi_shaders.h"

namespace ssvgi::gi {

ProbeDilate::ProbeDilate(gpu::Device& device) : pipeline_(device, shaders::probe_dilate_comp) {}

void ProbeDilate::record(gpu::CommandList& commands, const ProbeVolume& probes) {
  auto scope = commands.scope("ssvgi: ProbeDilate");
  const gpu::Bindings bindings = probes.listedProbeBindings(gpu::Bindings());
  commands.dispatchIndirect(pipeline_, bindings, probes.list(), 0);  // one workgroup per listed probe
}

}  // namespace ssvgi::gi
