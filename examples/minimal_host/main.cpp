// The smallest host of ssvgi: its own Vulkan instance and device, a scene it draws itself, a few frames of GI, and a
// check of what comes back. docs/INTEGRATION.md walks through it step by step (SPEC §3, the frame contract).
//
// The scene: a camera at the origin looking down -Z at a wall 4 m away that fills the view, facing the camera, under
// a uniform sky of radiance 1 W/(sr·m²). Every pixel sees the wall at the same depth (a plane facing the camera has
// reversed-Z depth near / distance everywhere), normal and radiance, so the host "draws" it with transfer clears. The wall's point sees only the sky in front of it, so its
// irradiance is π (W/m²); the check asks ssvgi's E to be finite, non-zero and within 25 % of that (lavapipe:
// 3.31, 5 % above).
//
// Exit code 0: the output was as expected and the validation layer (when installed) reported no error.
#include <ssvgi/ssvgi.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

namespace {

constexpr uint32_t kWidth = 64, kHeight = 48;
constexpr uint32_t kFrames = 12;
constexpr float kNear = 0.1f;           // metres; reversed-Z with an infinite far plane (SPEC §2)
constexpr float kWallDistance = 4.0f;   // metres in front of the camera
constexpr float kWallRadiance = 0.5f;   // W/(sr·m²), all of the light leaving the wall (what the host composited)
constexpr float kSkyRadiance = 1.0f;    // W/(sr·m²), uniform
constexpr float kPi = 3.14159265358979f;

uint32_t validationErrors = 0;

VKAPI_ATTR VkBool32 VKAPI_CALL onValidationMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                   VkDebugUtilsMessageTypeFlagsEXT,
                                                   const VkDebugUtilsMessengerCallbackDataEXT* data, void*) {
  if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
    ++validationErrors;
    std::fprintf(stderr, "validation error: %s\n", data->pMessage);
  }
  return VK_FALSE;
}

bool check(VkResult result, const char* call) {
  if (result == VK_SUCCESS) return true;
  std::fprintf(stderr, "minimal_host: %s failed (VkResult %d)\n", call, int(result));
  return false;
}
#define CHECK(call) \
  if (!check((call), #call)) return 1

bool hasLayer(const char* name) {
  uint32_t count = 0;
  vkEnumerateInstanceLayerProperties(&count, nullptr);
  std::vector<VkLayerProperties> layers(count);
  vkEnumerateInstanceLayerProperties(&count, layers.data());
  for (const VkLayerProperties& layer : layers)
    if (std::strcmp(layer.layerName, name) == 0) return true;
  return false;
}

// An image of the host's with its memory, made for what the example does with it: cleared, sampled by ssvgi.
struct HostImage {
  VkImage image = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;
};

uint32_t memoryType(VkPhysicalDevice physicalDevice, uint32_t typeBits, VkMemoryPropertyFlags flags) {
  VkPhysicalDeviceMemoryProperties properties;
  vkGetPhysicalDeviceMemoryProperties(physicalDevice, &properties);
  for (uint32_t i = 0; i < properties.memoryTypeCount; ++i)
    if ((typeBits & (1u << i)) && (properties.memoryTypes[i].propertyFlags & flags) == flags) return i;
  return UINT32_MAX;
}

bool createImage(VkPhysicalDevice physicalDevice, VkDevice device, VkFormat format, VkImageAspectFlags aspect,
                 HostImage& out) {
  VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = format;
  info.extent = {kWidth, kHeight, 1};
  info.mipLevels = 1;
  info.arrayLayers = 1;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.usage = VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
  if (vkCreateImage(device, &info, nullptr, &out.image) != VK_SUCCESS) return false;
  VkMemoryRequirements requirements;
  vkGetImageMemoryRequirements(device, out.image, &requirements);
  VkMemoryAllocateInfo allocation{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  allocation.allocationSize = requirements.size;
  allocation.memoryTypeIndex =
      memoryType(physicalDevice, requirements.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  if (vkAllocateMemory(device, &allocation, nullptr, &out.memory) != VK_SUCCESS) return false;
  if (vkBindImageMemory(device, out.image, out.memory, 0) != VK_SUCCESS) return false;
  VkImageViewCreateInfo viewInfo{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  viewInfo.image = out.image;
  viewInfo.viewType = VK_IMAGE_VIEW_TYPE_2D;
  viewInfo.format = format;
  viewInfo.subresourceRange = {aspect, 0, 1, 0, 1};
  return vkCreateImageView(device, &viewInfo, nullptr, &out.view) == VK_SUCCESS;
}

void destroyImage(VkDevice device, HostImage& image) {
  vkDestroyImageView(device, image.view, nullptr);
  vkDestroyImage(device, image.image, nullptr);
  vkFreeMemory(device, image.memory, nullptr);
}

// What the host renders each frame and ssvgi reads: SPEC §3's depth and normal, and the lit colour.
struct FrameImages {
  HostImage depth, normal, color;
};

VkImageMemoryBarrier imageBarrier(VkImage image, VkImageAspectFlags aspect, VkImageLayout from, VkImageLayout to,
                                  VkAccessFlags srcAccess, VkAccessFlags dstAccess) {
  VkImageMemoryBarrier barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  barrier.srcAccessMask = srcAccess;
  barrier.dstAccessMask = dstAccess;
  barrier.oldLayout = from;
  barrier.newLayout = to;
  barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.image = image;
  barrier.subresourceRange = {aspect, 0, 1, 0, 1};
  return barrier;
}

// "Draws" the wall into one set: its depth, normal and radiance are the same at every pixel. Leaves the images in
// SHADER_READ_ONLY_OPTIMAL, their writes visible to compute shaders, as ssvgi::SampledImage asks.
void drawWall(VkCommandBuffer commandBuffer, const FrameImages& images) {
  const VkImageAspectFlags color = VK_IMAGE_ASPECT_COLOR_BIT, depth = VK_IMAGE_ASPECT_DEPTH_BIT;
  // UNDEFINED: the set's old contents (two frames old) are not needed.
  const VkImageMemoryBarrier toTransfer[] = {
      imageBarrier(images.depth.image, depth, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0,
                   VK_ACCESS_TRANSFER_WRITE_BIT),
      imageBarrier(images.normal.image, color, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0,
                   VK_ACCESS_TRANSFER_WRITE_BIT),
      imageBarrier(images.color.image, color, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0,
                   VK_ACCESS_TRANSFER_WRITE_BIT)};
  // The source stage is compute: ssvgi read this set as the lit frame in the previous dispatch.
  vkCmdPipelineBarrier(commandBuffer, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0,
                       nullptr, 0, nullptr, 3, toTransfer);

  const VkImageSubresourceRange colorRange{color, 0, 1, 0, 1}, depthRange{depth, 0, 1, 0, 1};
  const VkClearDepthStencilValue wallDepth{kNear / kWallDistance, 0};  // reversed-Z infinite: near / distance
  vkCmdClearDepthStencilImage(commandBuffer, images.depth.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &wallDepth, 1,
                              &depthRange);
  const VkClearColorValue wallNormal{{0.0f, 0.0f, 1.0f, 0.0f}};  // world +Z, towards the camera
  vkCmdClearColorImage(commandBuffer, images.normal.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &wallNormal, 1,
                       &colorRange);
  const VkClearColorValue wallColor{{kWallRadiance, kWallRadiance, kWallRadiance, 1.0f}};
  vkCmdClearColorImage(commandBuffer, images.color.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &wallColor, 1,
                       &colorRange);

  const VkImageMemoryBarrier toShader[] = {
      imageBarrier(images.depth.image, depth, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                   VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT),
      imageBarrier(images.normal.image, color, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                   VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT),
      imageBarrier(images.color.image, color, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                   VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT)};
  vkCmdPipelineBarrier(commandBuffer, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 0,
                       nullptr, 0, nullptr, 3, toShader);
}

// The camera (SPEC §2): at the origin, looking down -Z, reversed-Z with an infinite far plane, column-major.
ssvgi::View cameraView() {
  const float focal = 1.0f / std::tan(0.5f * 60.0f * kPi / 180.0f);  // 60° vertical field of view
  ssvgi::View view;
  view.viewProjection = {focal * kHeight / kWidth, 0, 0, 0,   //
                         0, focal, 0, 0,                      //
                         0, 0, 0, -1,                         // clip w = distance along -Z
                         0, 0, kNear, 0};                     // clip z = near, so depth = near / distance
  view.position = {0.0f, 0.0f, 0.0f};
  view.width = kWidth;
  view.height = kHeight;
  return view;
}

// Copies ssvgi's output (rgba16f) into a host-visible buffer, and gives it back in the layout ssvgi left it in.
void recordReadback(VkCommandBuffer commandBuffer, const ssvgi::OutputImage& output, VkBuffer buffer) {
  const VkImageAspectFlags color = VK_IMAGE_ASPECT_COLOR_BIT;
  const VkImageMemoryBarrier toTransfer = imageBarrier(output.image, color, output.layout,
                                                       VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                                                       VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT);
  vkCmdPipelineBarrier(commandBuffer, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0,
                       nullptr, 0, nullptr, 1, &toTransfer);
  VkBufferImageCopy region{};
  region.imageSubresource = {color, 0, 0, 1};
  region.imageExtent = {output.width, output.height, 1};
  vkCmdCopyImageToBuffer(commandBuffer, output.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, buffer, 1, &region);
  const VkImageMemoryBarrier back = imageBarrier(output.image, color, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                                                 output.layout, 0, VK_ACCESS_SHADER_READ_BIT);
  vkCmdPipelineBarrier(commandBuffer, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 0,
                       nullptr, 0, nullptr, 1, &back);
  VkBufferMemoryBarrier toHost{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER};
  toHost.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  toHost.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  toHost.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  toHost.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  toHost.buffer = buffer;
  toHost.size = VK_WHOLE_SIZE;
  vkCmdPipelineBarrier(commandBuffer, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 0, nullptr, 1,
                       &toHost, 0, nullptr);
}

float halfToFloat(uint16_t half) {
  const uint32_t sign = half >> 15, exponent = (half >> 10) & 31u, mantissa = half & 1023u;
  float value;
  if (exponent == 0) value = std::ldexp(float(mantissa), -24);
  else if (exponent == 31) value = mantissa ? NAN : INFINITY;
  else value = std::ldexp(float(mantissa + 1024u), int(exponent) - 25);
  return sign ? -value : value;
}

}  // namespace

int main() {
  // 1. The host's Vulkan: an instance (1.1 is all ssvgi needs), validation when installed, VK_EXT_debug_utils for it.
  const bool validation = hasLayer("VK_LAYER_KHRONOS_validation");
  if (!validation) std::printf("minimal_host: VK_LAYER_KHRONOS_validation is not installed; running without it\n");
  VkApplicationInfo application{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  application.pApplicationName = "ssvgi minimal host";
  application.apiVersion = VK_API_VERSION_1_1;
  const char* layer = "VK_LAYER_KHRONOS_validation";
  const char* debugUtils = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
  VkInstanceCreateInfo instanceInfo{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  instanceInfo.pApplicationInfo = &application;
  instanceInfo.enabledLayerCount = validation ? 1 : 0;
  instanceInfo.ppEnabledLayerNames = &layer;
  instanceInfo.enabledExtensionCount = validation ? 1 : 0;
  instanceInfo.ppEnabledExtensionNames = &debugUtils;
  VkInstance instance;
  CHECK(vkCreateInstance(&instanceInfo, nullptr, &instance));
  VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
  if (validation) {
    auto createMessenger = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
    VkDebugUtilsMessengerCreateInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    info.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
    info.pfnUserCallback = onValidationMessage;
    CHECK(createMessenger(instance, &info, nullptr, &messenger));
  }

  // The first device with a compute queue: ssvgi records compute and transfer commands only.
  uint32_t deviceCount = 0;
  vkEnumeratePhysicalDevices(instance, &deviceCount, nullptr);
  std::vector<VkPhysicalDevice> physicalDevices(deviceCount);
  vkEnumeratePhysicalDevices(instance, &deviceCount, physicalDevices.data());
  VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
  uint32_t queueFamily = 0;
  for (VkPhysicalDevice candidate : physicalDevices) {
    uint32_t familyCount = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(candidate, &familyCount, nullptr);
    std::vector<VkQueueFamilyProperties> families(familyCount);
    vkGetPhysicalDeviceQueueFamilyProperties(candidate, &familyCount, families.data());
    for (uint32_t i = 0; i < familyCount && !physicalDevice; ++i)
      if (families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) physicalDevice = candidate, queueFamily = i;
    if (physicalDevice) break;
  }
  if (!physicalDevice) {
    std::fprintf(stderr, "minimal_host: no Vulkan device with a compute queue\n");
    return 1;
  }
  const float priority = 1.0f;
  VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queueInfo.queueFamilyIndex = queueFamily;
  queueInfo.queueCount = 1;
  queueInfo.pQueuePriorities = &priority;
  VkDeviceCreateInfo deviceInfo{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  deviceInfo.queueCreateInfoCount = 1;
  deviceInfo.pQueueCreateInfos = &queueInfo;
  VkDevice device;
  CHECK(vkCreateDevice(physicalDevice, &deviceInfo, nullptr, &device));
  VkQueue queue;
  vkGetDeviceQueue(device, queueFamily, 0, &queue);

  VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  poolInfo.queueFamilyIndex = queueFamily;
  VkCommandPool pool;
  CHECK(vkCreateCommandPool(device, &poolInfo, nullptr, &pool));
  VkCommandBufferAllocateInfo commandBufferInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  commandBufferInfo.commandPool = pool;
  commandBufferInfo.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  commandBufferInfo.commandBufferCount = 1;
  VkCommandBuffer commandBuffer;
  CHECK(vkAllocateCommandBuffers(device, &commandBufferInfo, &commandBuffer));
  VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkFence fence;
  CHECK(vkCreateFence(device, &fenceInfo, nullptr, &fence));

  // Two sets of the host's images, alternating, so that last frame's (the lit frame) is intact while this frame's
  // is drawn.
  FrameImages sets[2];
  for (FrameImages& images : sets) {
    if (!createImage(physicalDevice, device, VK_FORMAT_D32_SFLOAT, VK_IMAGE_ASPECT_DEPTH_BIT, images.depth) ||
        !createImage(physicalDevice, device, VK_FORMAT_R16G16B16A16_SFLOAT, VK_IMAGE_ASPECT_COLOR_BIT, images.normal) ||
        !createImage(physicalDevice, device, VK_FORMAT_R16G16B16A16_SFLOAT, VK_IMAGE_ASPECT_COLOR_BIT, images.color)) {
      std::fprintf(stderr, "minimal_host: could not create the frame's images\n");
      return 1;
    }
  }

  // 2. The context, once, with the host's device and its entry points (here the loader's, which the host links).
  ssvgi::ContextDesc contextDesc;
  contextDesc.instance = instance;
  contextDesc.physicalDevice = physicalDevice;
  contextDesc.device = device;
  contextDesc.vkGetInstanceProcAddr = vkGetInstanceProcAddr;
  contextDesc.vkGetDeviceProcAddr = vkGetDeviceProcAddr;
  contextDesc.debugUtilsEnabled = validation;
  contextDesc.settings = ssvgi::settingsForTier(ssvgi::QualityTier::Low);
  contextDesc.maxWidth = kWidth;
  contextDesc.maxHeight = kHeight;
  contextDesc.framesInFlight = 1;  // this host waits for each frame
  ssvgi::Result<std::unique_ptr<ssvgi::Context>> created = ssvgi::Context::create(contextDesc);
  if (!created.ok()) {
    std::fprintf(stderr, "minimal_host: ssvgi::Context::create: %s\n", created.error().message.c_str());
    return 1;
  }
  std::unique_ptr<ssvgi::Context> context = std::move(created.value());

  const VkDeviceSize readbackBytes = VkDeviceSize((kWidth + 1) / 2) * ((kHeight + 1) / 2) * 4 * sizeof(uint16_t);
  VkBufferCreateInfo bufferInfo{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bufferInfo.size = readbackBytes;
  bufferInfo.usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  VkBuffer readback;
  CHECK(vkCreateBuffer(device, &bufferInfo, nullptr, &readback));
  VkMemoryRequirements requirements;
  vkGetBufferMemoryRequirements(device, readback, &requirements);
  VkMemoryAllocateInfo allocation{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  allocation.allocationSize = requirements.size;
  allocation.memoryTypeIndex =
      memoryType(physicalDevice, requirements.memoryTypeBits,
                 VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
  VkDeviceMemory readbackMemory;
  CHECK(vkAllocateMemory(device, &allocation, nullptr, &readbackMemory));
  CHECK(vkBindBufferMemory(device, readback, readbackMemory, 0));

  // The sky's radiance as SH2 (ssvgi.h, FrameDesc::skyRadianceSh): a uniform sky has only Y00, L · 4π · Y00 = L · 2√π.
  std::array<float, 12> skySh{};
  skySh[0] = skySh[4] = skySh[8] = kSkyRadiance * 2.0f * std::sqrt(kPi);

  // 3. Every frame: draw, give ssvgi this frame's depth and normal and last frame's lit colour, depth and normal,
  // record its dispatch into the host's command buffer, submit.
  ssvgi::OutputImage output;
  for (uint32_t frame = 0; frame < kFrames; ++frame) {
    const FrameImages& current = sets[frame & 1u];
    const FrameImages& lit = sets[(frame + 1) & 1u];
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    CHECK(vkBeginCommandBuffer(commandBuffer, &begin));
    drawWall(commandBuffer, current);

    ssvgi::FrameDesc frameDesc;
    frameDesc.frameIndex = frame;
    frameDesc.camera = cameraView();
    frameDesc.depth.view = current.depth.view;
    frameDesc.normal.view = current.normal.view;
    frameDesc.hasLitFrame = frame > 0;  // nothing was lit before the first frame
    frameDesc.litCamera = cameraView();
    frameDesc.litColor.view = lit.color.view;
    frameDesc.litDepth.view = lit.depth.view;
    frameDesc.litNormal.view = lit.normal.view;
    frameDesc.skyRadianceSh = skySh;
    if (const ssvgi::Error error = context->dispatch(frameDesc, commandBuffer)) {
      std::fprintf(stderr, "minimal_host: ssvgi dispatch: %s\n", error.message.c_str());
      return 1;
    }
    // A real host's composite samples output() here: final = direct + emissive + albedo/π · E. This one keeps its
    // wall's radiance fixed and reads E back after the last frame.
    output = context->output();
    if (frame + 1 == kFrames) recordReadback(commandBuffer, output, readback);

    CHECK(vkEndCommandBuffer(commandBuffer));
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &commandBuffer;
    CHECK(vkQueueSubmit(queue, 1, &submit, fence));
    CHECK(vkWaitForFences(device, 1, &fence, VK_TRUE, UINT64_MAX));
    CHECK(vkResetFences(device, 1, &fence));
  }

  // 4. The result: E at every texel finite and non-zero, about π; its alpha the depth the host drew.
  const ssvgi::Stats stats = context->stats();  // after the wait: the last frame's counters and GPU times
  void* mapped = nullptr;
  CHECK(vkMapMemory(device, readbackMemory, 0, VK_WHOLE_SIZE, 0, &mapped));
  const auto* texels = static_cast<const uint16_t*>(mapped);
  double sum = 0.0;
  uint32_t bad = 0;
  const uint32_t count = output.width * output.height;
  for (uint32_t i = 0; i < count; ++i) {
    const float depth = halfToFloat(texels[4 * i + 3]);
    for (uint32_t channel = 0; channel < 3; ++channel) {
      const float irradiance = halfToFloat(texels[4 * i + channel]);
      if (!std::isfinite(irradiance) || !(irradiance > 0.0f)) ++bad;
      sum += irradiance;
    }
    if (!(std::abs(depth - kNear / kWallDistance) <= 1e-4f)) ++bad;
  }
  const double mean = sum / (3.0 * count);
  std::printf("minimal_host: %u×%u output, mean E %.3f W/m² (a wall under a uniform sky: π), %u bad values; "
              "%u voxels valid, %u probes updated, GI memory %.1f MiB; %u validation errors\n",
              output.width, output.height, mean, bad, stats.voxelsValid, stats.probesUpdatedLastFrame,
              double(stats.totalBytes) / (1024.0 * 1024.0), validationErrors);
  const bool passed = count > 0 && bad == 0 && std::abs(mean / kPi - 1.0) < 0.25 && validationErrors == 0;

  // 5. Tear down: the context first (the GPU is idle), then the host's objects.
  context.reset();
  vkDestroyBuffer(device, readback, nullptr);
  vkFreeMemory(device, readbackMemory, nullptr);
  for (FrameImages& images : sets) {
    destroyImage(device, images.depth);
    destroyImage(device, images.normal);
    destroyImage(device, images.color);
  }
  vkDestroyFence(device, fence, nullptr);
  vkDestroyCommandPool(device, pool, nullptr);
  vkDestroyDevice(device, nullptr);
  if (messenger) {
    auto destroyMessenger = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
    destroyMessenger(instance, messenger, nullptr);
  }
  vkDestroyInstance(instance, nullptr);
  if (validationErrors != 0) std::fprintf(stderr, "minimal_host: validation reported errors\n");
  if (!passed) std::fprintf(stderr, "minimal_host: FAILED\n");
  return passed && validationErrors == 0 ? 0 : 1;
}
