#include "probe_passes.h"
#include "ssvgi_shaders.h"

namespace ssvgi::gi {

ProbeDilate::ProbeDilate(gpu::Device& device) : pipeline_(device, shaders::probe_dilate_comp) {}

void ProbeDilate::record(gpu::CommandList& commands, const ProbeVolume& probes) {
  auto scope = commands.scope("ssvgi: ProbeDilate");
  const gpu::Bindings bindings = probes.listedProbeBindings(gpu::Bindings());
  // One thread per listed probe: as many as the list may hold, those past its count leave at once.
  commands.dispatch(pipeline_, bindings, {probes.current().probeBudget, 1, 1});
}

}  // namespace ssvgi::gi
