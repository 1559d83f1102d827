#include "probe_passes.h"
#include "ssvgi_shaders.h"

namespace ssvgi::gi {

ProbeDilate::ProbeDilate(gpu::Device& device) : pipeline_(device, shaders::probe_dilate_comp) {}

void ProbeDilate::record(gpu::CommandList& commands, const ProbeVolume& probes) {
  auto scope = commands.scope("ssvgi: ProbeDilate");
  const gpu::Bindings bindings = gpu::Bindings()
                                     .buffer(shader::kBindProbeUpdate, probes.update())
                                     .buffer(shader::kBindProbes, probes.probes())
                                     .buffer(shader::kBindProbeList, probes.list());
  commands.dispatchIndirect(pipeline_, bindings, probes.list(), 0);  // one workgroup per listed probe
}

}  // namespace ssvgi::gi
