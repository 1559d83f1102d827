#include "probe_passes.h"
#include "ssvgi_shaders.h"

namespace ssvgi::gi {

ProbeTrace::ProbeTrace(gpu::Device& device)
    : pipeline_(device, shaders::probe_trace_comp, {VK_FALSE}),
      keepingReservoirs_(device, shaders::probe_trace_comp, {VK_TRUE}) {}

void ProbeTrace::record(gpu::CommandList& commands, const VoxelScene& scene, const ProbeVolume& probes,
                        VkImageView skyMap, VkSampler skyMapSampler) {
  // SPEC §4 step 8's UpdateReservoirs runs inside this pass (probe_trace.comp says why), under its label.
  auto scope = commands.scope("ssvgi: ProbeTrace");
  const gpu::Bindings bindings =
      probes.listedProbeBindings(scene.bindings())
          .buffer(shader::kBindProbeReservoirs, probes.reservoirs())
          .buffer(shader::kBindProbeChanges, probes.changes())
          .buffer(shader::kBindProbeChangeTally, probes.changeTally())
          .externalSampled(shader::kBindProbeSkyMap, skyMap, skyMapSampler);
  const gpu::ComputePipeline& pipeline = probes.current().keepsReservoirs != 0 ? keepingReservoirs_ : pipeline_;
  commands.dispatchIndirect(pipeline, bindings, probes.list(), 0);  // one workgroup per listed probe
}

}  // namespace ssvgi::gi
