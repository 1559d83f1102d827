#pragma once
#include "gpu/resources.h"
#include "owned_device.h"

#include <cstddef>
#include <cstring>
#include <span>
#include <vector>

namespace ssvgi::gpu {

// Blocking transfers through a staging buffer, for loading scenes and reading results back (not for per-frame use):
// each submits on the device's own queue and waits.
void uploadBuffer(OwnedDevice& device, const Buffer& buffer, std::span<const std::byte> data, VkDeviceSize offset = 0);
std::vector<std::byte> readBuffer(OwnedDevice& device, const Buffer& buffer);
// Tightly packed texels of one layer, mip 0. After the upload the image is ready to be sampled in any shader stage.
void uploadImage(OwnedDevice& device, const Image& image, std::span<const std::byte> texels, uint32_t layer = 0);
std::vector<std::byte> readImage(OwnedDevice& device, const Image& image, uint32_t layer = 0);

template <typename T>
std::vector<T> readBufferAs(OwnedDevice& device, const Buffer& buffer) {
  const auto bytes = readBuffer(device, buffer);
  std::vector<T> values(bytes.size() / sizeof(T));
  std::memcpy(values.data(), bytes.data(), values.size() * sizeof(T));
  return values;
}

}  // namespace ssvgi::gpu
