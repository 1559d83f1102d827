#include "resources.h"

#include <utility>

namespace ssvgi::gpu {

namespace {

VkMemoryPropertyFlags memoryFlags(MemoryUsage usage) {
  switch (usage) {
    case MemoryUsage::DeviceLocal: return VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
    case MemoryUsage::HostUpload:
    case MemoryUsage::HostReadback: return VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  }
  return 0;
}

VkDeviceMemory allocate(Device& device, const VkMemoryRequirements& requirements, VkMemoryPropertyFlags flags) {
  VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  info.allocationSize = requirements.size;
  info.memoryTypeIndex = device.findMemoryType(requirements.memoryTypeBits, flags);
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VK_CHECK(device.vk().vkAllocateMemory(device.device(), &info, nullptr, &memory));
  return memory;
}

VkImageView createView(Device& device, const Image& image, VkImageViewType type, uint32_t baseMip, uint32_t mips,
                       uint32_t baseLayer, uint32_t layers) {
  VkImageViewCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  info.image = image.handle();
  info.viewType = type;
  info.format = image.desc().format;
  info.subresourceRange = {image.aspect(), baseMip, mips, baseLayer, layers};
  VkImageView view = VK_NULL_HANDLE;
  VK_CHECK(device.vk().vkCreateImageView(device.device(), &info, nullptr, &view));
  return view;
}

VkImageCreateInfo imageCreateInfo(const ImageDesc& desc) {
  VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = desc.format;
  info.extent = {desc.width, desc.height, 1};
  info.mipLevels = desc.mipLevels;
  info.arrayLayers = desc.layers;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = desc.usage | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  return info;
}

}  // namespace

VkDeviceSize imageMemoryBytes(Device& device, const ImageDesc& desc) {
  const VkImageCreateInfo info = imageCreateInfo(desc);
  VkImage image = VK_NULL_HANDLE;
  VK_CHECK(device.vk().vkCreateImage(device.device(), &info, nullptr, &image));
  VkMemoryRequirements requirements{};
  device.vk().vkGetImageMemoryRequirements(device.device(), image, &requirements);
  device.vk().vkDestroyImage(device.device(), image, nullptr);
  return requirements.size;
}

Buffer::Buffer(Device& device, const std::string& name, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUsage memory)
    : device_(&device), size_(size), name_(name) {
  if (size == 0) throw GpuError("buffer '" + name + "' has size 0");
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = size;
  info.usage = usage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  VK_CHECK(device.vk().vkCreateBuffer(device.device(), &info, nullptr, &buffer_));
  VkMemoryRequirements requirements{};
  device.vk().vkGetBufferMemoryRequirements(device.device(), buffer_, &requirements);
  memory_ = allocate(device, requirements, memoryFlags(memory));
  VK_CHECK(device.vk().vkBindBufferMemory(device.device(), buffer_, memory_, 0));
  if (memory != MemoryUsage::DeviceLocal)
    VK_CHECK(device.vk().vkMapMemory(device.device(), memory_, 0, VK_WHOLE_SIZE, 0, &mapped_));
  device.setName(buffer_, VK_OBJECT_TYPE_BUFFER, name);
  device.trackAllocation(name, size_);
}

Buffer::~Buffer() { release(); }

Buffer::Buffer(Buffer&& other) noexcept { *this = std::move(other); }

Buffer& Buffer::operator=(Buffer&& other) noexcept {
  if (this != &other) {
    release();
    device_ = std::exchange(other.device_, nullptr);
    buffer_ = std::exchange(other.buffer_, VK_NULL_HANDLE);
    memory_ = std::exchange(other.memory_, VK_NULL_HANDLE);
    size_ = std::exchange(other.size_, 0);
    mapped_ = std::exchange(other.mapped_, nullptr);
    name_ = std::move(other.name_);
    state_ = other.state_;
  }
  return *this;
}

void Buffer::release() {
  if (!buffer_) return;
  device_->untrackAllocation(name_, size_);
  device_->vk().vkDestroyBuffer(device_->device(), buffer_, nullptr);
  device_->vk().vkFreeMemory(device_->device(), memory_, nullptr);
  buffer_ = VK_NULL_HANDLE;
}

Image::Image(Device& device, const ImageDesc& desc) : device_(&device), desc_(desc) {
  const VkImageCreateInfo info = imageCreateInfo(desc);
  VK_CHECK(device.vk().vkCreateImage(device.device(), &info, nullptr, &image_));
  VkMemoryRequirements requirements{};
  device.vk().vkGetImageMemoryRequirements(device.device(), image_, &requirements);
  memory_ = allocate(device, requirements, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  VK_CHECK(device.vk().vkBindImageMemory(device.device(), image_, memory_, 0));
  bytes_ = requirements.size;

  const VkImageViewType arrayType = desc.layers > 1 || desc.arrayView ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : VK_IMAGE_VIEW_TYPE_2D;
  view_ = createView(device, *this, arrayType, 0, desc.mipLevels, 0, desc.layers);
  for (uint32_t layer = 0; layer < desc.layers; ++layer)
    layerViews_.push_back(createView(device, *this, VK_IMAGE_VIEW_TYPE_2D, 0, 1, layer, 1));
  for (uint32_t mip = 0; mip < desc.mipLevels; ++mip)
    mipViews_.push_back(createView(device, *this, arrayType, mip, 1, 0, desc.layers));
  device.setName(image_, VK_OBJECT_TYPE_IMAGE, desc.name);
  device.trackAllocation(desc.name, bytes_);
}

Image::~Image() { release(); }

Image::Image(Image&& other) noexcept { *this = std::move(other); }

Image& Image::operator=(Image&& other) noexcept {
  if (this != &other) {
    release();
    device_ = std::exchange(other.device_, nullptr);
    image_ = std::exchange(other.image_, VK_NULL_HANDLE);
    memory_ = std::exchange(other.memory_, VK_NULL_HANDLE);
    view_ = std::exchange(other.view_, VK_NULL_HANDLE);
    layerViews_ = std::move(other.layerViews_);
    mipViews_ = std::move(other.mipViews_);
    bytes_ = std::exchange(other.bytes_, 0);
    desc_ = std::move(other.desc_);
    state_ = other.state_;
  }
  return *this;
}

void Image::release() {
  if (!image_) return;
  device_->untrackAllocation(desc_.name, bytes_);
  const VkDevice device = device_->device();
  const VulkanFunctions& vk = device_->vk();
  for (VkImageView view : layerViews_) vk.vkDestroyImageView(device, view, nullptr);
  for (VkImageView view : mipViews_) vk.vkDestroyImageView(device, view, nullptr);
  layerViews_.clear();
  mipViews_.clear();
  vk.vkDestroyImageView(device, view_, nullptr);
  vk.vkDestroyImage(device, image_, nullptr);
  vk.vkFreeMemory(device, memory_, nullptr);
  image_ = VK_NULL_HANDLE;
}

VkImageAspectFlags Image::aspect() const {
  return isDepthFormat(desc_.format) ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT;
}

Sampler::Sampler(Device& device, const VkSamplerCreateInfo& info, const std::string& name) : device_(&device) {
  VK_CHECK(device.vk().vkCreateSampler(device.device(), &info, nullptr, &sampler_));
  device.setName(sampler_, VK_OBJECT_TYPE_SAMPLER, name);
}

Sampler::~Sampler() {
  if (sampler_) device_->vk().vkDestroySampler(device_->device(), sampler_, nullptr);
}

Sampler::Sampler(Sampler&& other) noexcept { *this = std::move(other); }

Sampler& Sampler::operator=(Sampler&& other) noexcept {
  if (this != &other) {
    if (sampler_) device_->vk().vkDestroySampler(device_->device(), sampler_, nullptr);
    device_ = std::exchange(other.device_, nullptr);
    sampler_ = std::exchange(other.sampler_, VK_NULL_HANDLE);
  }
  return *this;
}

bool isDepthFormat(VkFormat format) {
  return format == VK_FORMAT_D32_SFLOAT || format == VK_FORMAT_D16_UNORM || format == VK_FORMAT_D24_UNORM_S8_UINT ||
         format == VK_FORMAT_D32_SFLOAT_S8_UINT;
}

}  // namespace ssvgi::gpu
