#include "rendering_options.h"

namespace ssvgi::cli {

void addRenderingOptions(CLI::App& command, RenderingOptions& options) {
  command.add_option("--gi", options.gi, "Indirect light from ssvgi: on or off (off: no ambient light at all)")
      ->capture_default_str()
      ->check(CLI::IsMember({"on", "off"}));
  addGiOptions(command, options.giOptions);
  command.add_option("--exposure", options.exposure, "Multiplier on radiance before tonemapping")
      ->capture_default_str()
      ->check(kNonNegativeNumber);
}

renderer::RendererSettings rendererSettings(const RenderingOptions& options, const ResolvedScene& resolved, bool runGi) {
  renderer::RendererSettings settings;
  settings.width = resolved.width;
  settings.height = resolved.height;
  settings.exposure = options.exposure;
  if (options.gi == "on" || runGi) settings.gi = giSettings(options.giOptions, resolved.scene);
  settings.giLighting = options.gi == "on";
  settings.extraViews = options.giOptions.extraViews;
  settings.litFrameDirectOnly = options.giOptions.litFrame == "direct";
  settings.giMemoryBudgetBytes = memoryBudgetBytes(options.giOptions);
  return settings;
}

const std::map<std::string, ssvgi::DebugView>& debugViewsByName() {
  static const std::map<std::string, ssvgi::DebugView> views = {{"voxels", ssvgi::DebugView::Voxels},
                                                                {"bricks", ssvgi::DebugView::Bricks},
                                                                {"probes", ssvgi::DebugView::Probes},
                                                                {"confidence", ssvgi::DebugView::Confidence},
                                                                {"observed", ssvgi::DebugView::ObservedSpace}};
  return views;
}

}  // namespace ssvgi::cli
