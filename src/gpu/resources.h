#pragma once
#include "device.h"

#include <string>
#include <vector>

namespace ssvgi::gpu {

// How a resource is used by the next command. The barrier tracker (barriers.h) turns a change of usage into the
// pipeline barrier it needs; pipelines derive their usages from the shader's own declarations (readonly, sampler…).
enum class Usage {
  ComputeRead,        // storage buffer/image read in a compute shader
  ComputeWrite,       // storage buffer/image written (possibly also read) in a compute shader
  ComputeSampled,     // sampled image in a compute shader
  GraphicsRead,       // storage/uniform buffer read in a vertex or fragment shader
  FragmentSampled,    // sampled image in a fragment shader
  VertexInput,        // vertex or index buffer
  IndirectArgument,   // indirect dispatch/draw arguments
  ColorAttachment,
  DepthAttachment,
  TransferSource,
  TransferDestination,
  HostRead,           // read back by the CPU after the submission completes
};

// Per-resource record of the last write and the reads since, so that only the barriers that are needed are emitted.
struct ResourceState {
  VkPipelineStageFlags writeStages = 0;
  VkAccessFlags writeAccess = 0;
  VkPipelineStageFlags readStages = 0;  // readers since the last write (a next write must wait for them)
  VkAccessFlags readAccess = 0;
  VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
};

enum class MemoryUsage {
  DeviceLocal,   // GPU only
  HostUpload,    // host-visible, written by the CPU (staging, per-frame constants), persistently mapped
  HostReadback,  // host-visible, read by the CPU, persistently mapped
};

class Buffer {
 public:
  Buffer() = default;
  Buffer(Device& device, const std::string& name, VkDeviceSize size, VkBufferUsageFlags usage,
         MemoryUsage memory = MemoryUsage::DeviceLocal);
  ~Buffer();
  Buffer(Buffer&& other) noexcept;
  Buffer& operator=(Buffer&& other) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  VkBuffer handle() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  const std::string& name() const { return name_; }
  void* mapped() const { return mapped_; }  // host-visible buffers only
  ResourceState& state() const { return state_; }
  explicit operator bool() const { return buffer_ != VK_NULL_HANDLE; }

 private:
  void release();
  Device* device_ = nullptr;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize size_ = 0;
  void* mapped_ = nullptr;
  std::string name_;
  mutable ResourceState state_;
};

struct ImageDesc {
  std::string name;
  VkFormat format = VK_FORMAT_R32G32B32A32_SFLOAT;
  uint32_t width = 1;
  uint32_t height = 1;
  uint32_t mipLevels = 1;
  uint32_t layers = 1;
  VkImageUsageFlags usage = VK_IMAGE_USAGE_STORAGE_BIT;
  bool arrayView = false;  // view() is a 2D array even with one layer (for shaders that declare an array)
};

// The bytes an Image of `desc` holds (Stats::memory counts its memory requirements), found without allocating any:
// the driver decides its alignment and padding.
VkDeviceSize imageMemoryBytes(Device& device, const ImageDesc& desc);

class Image {
 public:
  Image() = default;
  Image(Device& device, const ImageDesc& desc);
  ~Image();
  Image(Image&& other) noexcept;
  Image& operator=(Image&& other) noexcept;
  Image(const Image&) = delete;
  Image& operator=(const Image&) = delete;

  VkImage handle() const { return image_; }
  VkImageView view() const { return view_; }                        // all mips and layers
  VkImageView layerView(uint32_t layer) const { return layerViews_.at(layer); }  // one layer (2D), for attachments
  VkImageView mipView(uint32_t mip) const { return mipViews_.at(mip); }          // one mip (all layers), for storage
  const ImageDesc& desc() const { return desc_; }
  VkImageAspectFlags aspect() const;
  ResourceState& state() const { return state_; }
  explicit operator bool() const { return image_ != VK_NULL_HANDLE; }

 private:
  void release();
  Device* device_ = nullptr;
  VkImage image_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkImageView view_ = VK_NULL_HANDLE;
  std::vector<VkImageView> layerViews_;
  std::vector<VkImageView> mipViews_;
  VkDeviceSize bytes_ = 0;
  ImageDesc desc_;
  mutable ResourceState state_;
};

class Sampler {
 public:
  Sampler() = default;
  Sampler(Device& device, const VkSamplerCreateInfo& info, const std::string& name);
  ~Sampler();
  Sampler(Sampler&& other) noexcept;
  Sampler& operator=(Sampler&& other) noexcept;
  Sampler(const Sampler&) = delete;
  Sampler& operator=(const Sampler&) = delete;
  VkSampler handle() const { return sampler_; }

 private:
  Device* device_ = nullptr;
  VkSampler sampler_ = VK_NULL_HANDLE;
};

bool isDepthFormat(VkFormat format);

}  // namespace ssvgi::gpu
