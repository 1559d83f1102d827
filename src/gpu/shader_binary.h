#pragma once
#include <cstdint>
#include <span>

namespace ssvgi::gpu {

// A SPIR-V module embedded in the binary at build time (cmake/Shaders.cmake); `name` is its path under shaders/.
struct ShaderBinary {
  const char* name;
  std::span<const uint32_t> words;
};

}  // namespace ssvgi::gpu
