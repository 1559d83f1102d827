#pragma once
// The options of the commands that show the host renderer's image of a scene (render, view): the GI on or off, its
// options, the exposure, the debug views; and the renderer settings they make, so that both render alike.
#include "scene_options.h"

#include "renderer.h"
#include "ssvgi/ssvgi.h"

#include <CLI/CLI.hpp>

#include <map>
#include <string>

namespace ssvgi::cli {

inline constexpr float kFrameSeconds = 1.0f / 30.0f;  // animation time step per rendered frame

struct RenderingOptions {
  std::string gi = "on";
  GiOptions giOptions;
  float exposure = 1.0f;
};

void addRenderingOptions(CLI::App& command, RenderingOptions& options);

// The renderer's settings for the resolved scene; `runGi`: run ssvgi even when its light is not composited (--gi off),
// for its debug views.
renderer::RendererSettings rendererSettings(const RenderingOptions& options, const ResolvedScene& resolved, bool runGi);

// ssvgi's debug views by their --debug names.
const std::map<std::string, ssvgi::DebugView>& debugViewsByName();

}  // namespace ssvgi::cli
