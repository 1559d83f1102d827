#include "commands.h"

#include "gpu_host/owned_device.h"

#include <cstdio>

namespace ssvgi::cli {

CommandRunner addInfoCommand(CLI::App& app) {
  app.add_subcommand("info", "List the Vulkan devices and the features ssvgi needs, each marked present or missing");
  return [] {
    const auto devices = gpu::listDevices();
    if (devices.empty()) {
      std::fprintf(stderr, "ssvgi: no Vulkan device found (on a machine without a GPU, install mesa-vulkan-drivers)\n");
      return 1;
    }
    bool anyUsable = false;
    for (const auto& device : devices) {
      std::printf("[%u] %s (%s, Vulkan %s, driver %s): %s\n", device.index, device.name.c_str(), device.type.c_str(),
                  device.apiVersion.c_str(), device.driver.c_str(), device.usable() ? "usable" : "NOT usable");
      for (const auto& capability : device.capabilities)
        std::printf("    %-8s %s%s\n", capability.present ? "present" : "MISSING", capability.name.c_str(),
                    capability.required ? "" : " (optional)");
      anyUsable |= device.usable();
    }
    return anyUsable ? 0 : 1;
  };
}

}  // namespace ssvgi::cli
