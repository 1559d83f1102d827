#include "device.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <optional>
#include <sstream>

namespace ssvgi::gpu {

const char* toString(VkResult result) {
  switch (result) {
#define SSVGI_RESULT_CASE(name) \
  case name:                    \
    return #name;
    SSVGI_RESULT_CASE(VK_SUCCESS)
    SSVGI_RESULT_CASE(VK_NOT_READY)
    SSVGI_RESULT_CASE(VK_TIMEOUT)
    SSVGI_RESULT_CASE(VK_INCOMPLETE)
    SSVGI_RESULT_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
    SSVGI_RESULT_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    SSVGI_RESULT_CASE(VK_ERROR_INITIALIZATION_FAILED)
    SSVGI_RESULT_CASE(VK_ERROR_DEVICE_LOST)
    SSVGI_RESULT_CASE(VK_ERROR_MEMORY_MAP_FAILED)
    SSVGI_RESULT_CASE(VK_ERROR_LAYER_NOT_PRESENT)
    SSVGI_RESULT_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
    SSVGI_RESULT_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
    SSVGI_RESULT_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
    SSVGI_RESULT_CASE(VK_ERROR_TOO_MANY_OBJECTS)
    SSVGI_RESULT_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
    SSVGI_RESULT_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
#undef SSVGI_RESULT_CASE
    default:
      return "VkResult(unknown)";
  }
}

void throwVulkanError(VkResult result, const char* call, const char* file, int line) {
  std::ostringstream message;
  message << "Vulkan call failed with " << toString(result) << ": " << call << " (" << file << ":" << line << ")";
  throw GpuError(message.str(), result);
}

namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
// The host renderer uses dynamic rendering (core in 1.3); the GI passes themselves need only Vulkan 1.1 compute.
constexpr uint32_t kRequiredApiVersion = VK_API_VERSION_1_3;

std::string versionString(uint32_t version) {
  return std::to_string(VK_API_VERSION_MAJOR(version)) + "." + std::to_string(VK_API_VERSION_MINOR(version)) + "." +
         std::to_string(VK_API_VERSION_PATCH(version));
}

const char* deviceTypeName(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU";
    default: return "other";
  }
}

// Lower is preferred by "auto".
int typePreference(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
    default: return 4;
  }
}

bool hasLayer(const char* name) {
  uint32_t count = 0;
  vkEnumerateInstanceLayerProperties(&count, nullptr);
  std::vector<VkLayerProperties> layers(count);
  vkEnumerateInstanceLayerProperties(&count, layers.data());
  return std::any_of(layers.begin(), layers.end(), [&](const auto& layer) { return std::strcmp(layer.layerName, name) == 0; });
}

bool hasInstanceExtension(const char* name) {
  uint32_t count = 0;
  vkEnumerateInstanceExtensionProperties(nullptr, &count, nullptr);
  std::vector<VkExtensionProperties> extensions(count);
  vkEnumerateInstanceExtensionProperties(nullptr, &count, extensions.data());
  return std::any_of(extensions.begin(), extensions.end(),
                     [&](const auto& extension) { return std::strcmp(extension.extensionName, name) == 0; });
}

std::optional<uint32_t> graphicsComputeQueueFamily(VkPhysicalDevice physicalDevice) {
  uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(physicalDevice, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(physicalDevice, &count, families.data());
  for (uint32_t i = 0; i < count; ++i) {
    const VkQueueFlags needed = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
    if ((families[i].queueFlags & needed) == needed && families[i].timestampValidBits > 0) return i;
  }
  for (uint32_t i = 0; i < count; ++i) {
    const VkQueueFlags needed = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
    if ((families[i].queueFlags & needed) == needed) return i;
  }
  return std::nullopt;
}

DeviceReport describe(VkPhysicalDevice physicalDevice, uint32_t index) {
  VkPhysicalDeviceProperties properties{};
  vkGetPhysicalDeviceProperties(physicalDevice, &properties);
  VkPhysicalDeviceVulkan13Features features13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &features13};
  if (properties.apiVersion >= VK_API_VERSION_1_1) vkGetPhysicalDeviceFeatures2(physicalDevice, &features);
  const bool api13 = properties.apiVersion >= kRequiredApiVersion;

  DeviceReport report;
  report.index = index;
  report.name = properties.deviceName;
  report.type = deviceTypeName(properties.deviceType);
  report.apiVersion = versionString(properties.apiVersion);
  report.driver = versionString(properties.driverVersion);
  report.capabilities = {
      {"Vulkan 1.3 (host renderer; the GI passes need 1.1)", api13, true},
      {"graphics + compute queue", graphicsComputeQueueFamily(physicalDevice).has_value(), true},
      {"dynamicRendering", api13 && features13.dynamicRendering == VK_TRUE, true},
      {"timestampComputeAndGraphics (per-pass GPU times)", properties.limits.timestampComputeAndGraphics == VK_TRUE, false},
      {"maxComputeWorkGroupInvocations >= 256", properties.limits.maxComputeWorkGroupInvocations >= 256, true},
      {"maxPushConstantsSize >= 128", properties.limits.maxPushConstantsSize >= 128, true},
  };
  return report;
}

VkInstance createInstance(bool validation, bool debugUtils, const std::vector<std::string>& extraExtensions = {}) {
  VkApplicationInfo application{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  application.pApplicationName = "ssvgi";
  application.pEngineName = "ssvgi";
  application.apiVersion = kRequiredApiVersion;

  std::vector<const char*> layers;
  if (validation) layers.push_back(kValidationLayer);
  std::vector<const char*> extensions;
  if (debugUtils) extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  for (const std::string& extension : extraExtensions) extensions.push_back(extension.c_str());

  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  info.pApplicationInfo = &application;
  info.enabledLayerCount = static_cast<uint32_t>(layers.size());
  info.ppEnabledLayerNames = layers.data();
  info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  VkInstance instance = VK_NULL_HANDLE;
  const VkResult result = vkCreateInstance(&info, nullptr, &instance);
  if (result == VK_ERROR_INCOMPATIBLE_DRIVER)
    throw GpuError("no Vulkan driver found (on a machine without a GPU, install mesa-vulkan-drivers for lavapipe)");
  VK_CHECK(result);
  return instance;
}

std::vector<VkPhysicalDevice> physicalDevices(VkInstance instance) {
  uint32_t count = 0;
  VK_CHECK(vkEnumeratePhysicalDevices(instance, &count, nullptr));
  std::vector<VkPhysicalDevice> devices(count);
  VK_CHECK(vkEnumeratePhysicalDevices(instance, &count, devices.data()));
  return devices;
}

}  // namespace

bool DeviceReport::usable() const {
  return std::all_of(capabilities.begin(), capabilities.end(),
                     [](const DeviceCapability& capability) { return capability.present || !capability.required; });
}

std::vector<DeviceReport> listDevices() {
  VkInstance instance = createInstance(false, false);
  std::vector<DeviceReport> reports;
  const auto devices = physicalDevices(instance);
  for (uint32_t i = 0; i < devices.size(); ++i) reports.push_back(describe(devices[i], i));
  vkDestroyInstance(instance, nullptr);
  return reports;
}

Device::Device(const DeviceDesc& desc) {
  if (desc.validation && !hasLayer(kValidationLayer))
    throw GpuError("validation was requested but VK_LAYER_KHRONOS_validation is not installed "
                   "(install vulkan-validationlayers)");
  const bool debugUtils = hasInstanceExtension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  instance_ = createInstance(desc.validation, debugUtils, desc.instanceExtensions);

  if (debugUtils) {
    loadDebugUtils();
    if (desc.validation) {
      auto createMessenger = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
      VkDebugUtilsMessengerCreateInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
      info.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
      info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
      info.pfnUserCallback = &Device::onValidationMessage;
      info.pUserData = this;
      VK_CHECK(createMessenger(instance_, &info, nullptr, &messenger_));
    }
  }

  const auto devices = physicalDevices(instance_);
  if (devices.empty())
    throw GpuError("no Vulkan device found (on a machine without a GPU, install mesa-vulkan-drivers for lavapipe)");
  std::vector<DeviceReport> reports;
  for (uint32_t i = 0; i < devices.size(); ++i) reports.push_back(describe(devices[i], i));

  std::optional<uint32_t> chosen;
  const std::string& selector = desc.selector;
  if (selector == "auto" || selector == "gpu" || selector == "cpu") {
    for (uint32_t i = 0; i < devices.size(); ++i) {
      if (!reports[i].usable()) continue;
      VkPhysicalDeviceProperties properties{};
      vkGetPhysicalDeviceProperties(devices[i], &properties);
      const int preference = typePreference(properties.deviceType);
      const bool acceptable = selector == "auto" || (selector == "gpu" && preference <= 1) ||
                              (selector == "cpu" && properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU);
      if (!acceptable) continue;
      if (!chosen) {
        chosen = i;
      } else {
        VkPhysicalDeviceProperties best{};
        vkGetPhysicalDeviceProperties(devices[*chosen], &best);
        if (preference < typePreference(best.deviceType)) chosen = i;
      }
    }
    if (!chosen) {
      std::string message = "no usable Vulkan device for --device " + selector + "; found:";
      for (const auto& report : reports) {
        message += " [" + std::to_string(report.index) + "] " + report.name + " (" + report.type + ")";
        for (const auto& capability : report.capabilities)
          if (capability.required && !capability.present) message += " missing " + capability.name + ";";
      }
      throw GpuError(message);
    }
  } else {
    char* end = nullptr;
    const unsigned long index = std::strtoul(selector.c_str(), &end, 10);
    if (selector.empty() || *end != '\0')
      throw GpuError("--device must be auto, cpu, gpu or a device index, not '" + selector + "'");
    if (index >= devices.size())
      throw GpuError("--device " + selector + ": there are only " + std::to_string(devices.size()) + " Vulkan devices");
    if (!reports[index].usable()) throw GpuError("--device " + selector + ": " + reports[index].name + " lacks a required feature (see ssvgi info)");
    chosen = static_cast<uint32_t>(index);
  }

  physicalDevice_ = devices[*chosen];
  vkGetPhysicalDeviceProperties(physicalDevice_, &properties_);
  vkGetPhysicalDeviceMemoryProperties(physicalDevice_, &memoryProperties_);
  queueFamily_ = *graphicsComputeQueueFamily(physicalDevice_);
  VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  VkPhysicalDeviceProperties2 properties2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &driver};
  vkGetPhysicalDeviceProperties2(physicalDevice_, &properties2);
  driverInfo_ = std::string(driver.driverName) + " " + driver.driverInfo;

  const float priority = 1.0f;
  VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queueInfo.queueFamilyIndex = queueFamily_;
  queueInfo.queueCount = 1;
  queueInfo.pQueuePriorities = &priority;

  VkPhysicalDeviceVulkan13Features features13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  features13.dynamicRendering = VK_TRUE;
  VkPhysicalDeviceVulkan12Features features12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES, &features13};
  VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &features12};

  std::vector<const char*> extensions;
  for (const std::string& extension : desc.deviceExtensions) extensions.push_back(extension.c_str());
  VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &features};
  info.queueCreateInfoCount = 1;
  info.pQueueCreateInfos = &queueInfo;
  info.enabledExtensionCount = uint32_t(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  const VkResult created = vkCreateDevice(physicalDevice_, &info, nullptr, &device_);
  if (created == VK_ERROR_EXTENSION_NOT_PRESENT) {
    std::string names;
    for (const std::string& extension : desc.deviceExtensions) names += (names.empty() ? "" : ", ") + extension;
    throw GpuError(std::string(properties_.deviceName) + " lacks a device extension of " + names, created);
  }
  VK_CHECK(created);
  vk_ = loadVulkanFunctions(getInstanceProcAddr_, instance_, nullptr, device_);
  vkGetDeviceQueue(device_, queueFamily_, 0, &queue_);

  VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  poolInfo.queueFamilyIndex = queueFamily_;
  VK_CHECK(vkCreateCommandPool(device_, &poolInfo, nullptr, &commandPool_));
  VkCommandBufferAllocateInfo commandBufferInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  commandBufferInfo.commandPool = commandPool_;
  commandBufferInfo.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  commandBufferInfo.commandBufferCount = 1;
  VK_CHECK(vkAllocateCommandBuffers(device_, &commandBufferInfo, &commandBuffer_));
  VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VK_CHECK(vkCreateFence(device_, &fenceInfo, nullptr, &fence_));
}

void Device::loadDebugUtils() {
  setObjectName_ = reinterpret_cast<PFN_vkSetDebugUtilsObjectNameEXT>(
      getInstanceProcAddr_(instance_, "vkSetDebugUtilsObjectNameEXT"));
  beginLabel_ = reinterpret_cast<PFN_vkCmdBeginDebugUtilsLabelEXT>(
      getInstanceProcAddr_(instance_, "vkCmdBeginDebugUtilsLabelEXT"));
  endLabel_ = reinterpret_cast<PFN_vkCmdEndDebugUtilsLabelEXT>(
      getInstanceProcAddr_(instance_, "vkCmdEndDebugUtilsLabelEXT"));
}

Device::Device(const ExternalDevice& external)
    : owned_(false),
      getInstanceProcAddr_(external.getInstanceProcAddr ? external.getInstanceProcAddr : vkGetInstanceProcAddr),
      instance_(external.instance),
      physicalDevice_(external.physicalDevice),
      device_(external.device) {
  if (!instance_ || !physicalDevice_ || !device_) throw GpuError("an external device needs instance, physical device and device");
  vk_ = loadVulkanFunctions(getInstanceProcAddr_, instance_, external.getDeviceProcAddr, device_);
  vk_.vkGetPhysicalDeviceProperties(physicalDevice_, &properties_);
  vk_.vkGetPhysicalDeviceMemoryProperties(physicalDevice_, &memoryProperties_);
  if (external.debugUtils) loadDebugUtils();
}

Device::~Device() {
  if (!owned_) return;
  if (device_) {
    vkDeviceWaitIdle(device_);
    vkDestroyFence(device_, fence_, nullptr);
    vkDestroyCommandPool(device_, commandPool_, nullptr);
    vkDestroyDevice(device_, nullptr);
  }
  if (messenger_) {
    auto destroyMessenger = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    destroyMessenger(instance_, messenger_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
}

std::string Device::description() const {
  return std::string(properties_.deviceName) + " (" + deviceTypeName(properties_.deviceType) + ", Vulkan " +
         versionString(properties_.apiVersion) + ", " + driverInfo_ + ")";
}

// One command buffer, re-recorded by every submit and freed only with its pool. Freeing the command buffer as soon as
// its fence had signalled and allocating the next one (which gets the same handle back) corrupted the heap in about
// one test process in thirty under the Khronos validation layer 1.3.239 on lavapipe, whenever the CPU was
// oversubscribed: the crashes were inside the layer (vkCmdBeginDebugUtilsLabelEXT, vkAllocateDescriptorSets) while
// the layer's own queue thread was still busy with the submission the fence wait had just returned from.
void Device::submitAndWait(const std::function<void(VkCommandBuffer)>& record) {
  if (!queue_) throw GpuError("this device wraps a host's device: it records commands but cannot submit them");
  if (recording_) throw GpuError("Device::submitAndWait was called while recording its own command buffer");
  recording_ = true;
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  try {
    VK_CHECK(vkBeginCommandBuffer(commandBuffer_, &begin));  // resets it (the pool allows it)
    record(commandBuffer_);
    VK_CHECK(vkEndCommandBuffer(commandBuffer_));
  } catch (...) {
    vkResetCommandBuffer(commandBuffer_, 0);  // out of the recording state, for the next submit
    recording_ = false;
    throw;
  }
  recording_ = false;
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &commandBuffer_;
  VK_CHECK(vkQueueSubmit(queue_, 1, &submit, fence_));
  VK_CHECK(vkWaitForFences(device_, 1, &fence_, VK_TRUE, UINT64_MAX));
  VK_CHECK(vkResetFences(device_, 1, &fence_));
}

void Device::setName(VkObjectType type, uint64_t handle, const std::string& name) const {
  if (!setObjectName_) return;
  VkDebugUtilsObjectNameInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
  info.objectType = type;
  info.objectHandle = handle;
  info.pObjectName = name.c_str();
  setObjectName_(device_, &info);
}

void Device::beginLabel(VkCommandBuffer commandBuffer, const char* label) const {
  if (!beginLabel_) return;
  VkDebugUtilsLabelEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT};
  info.pLabelName = label;
  beginLabel_(commandBuffer, &info);
}

void Device::endLabel(VkCommandBuffer commandBuffer) const {
  if (endLabel_) endLabel_(commandBuffer);
}

uint32_t Device::findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required) const {
  for (uint32_t i = 0; i < memoryProperties_.memoryTypeCount; ++i) {
    if ((typeBits & (1u << i)) && (memoryProperties_.memoryTypes[i].propertyFlags & required) == required) return i;
  }
  throw GpuError("no Vulkan memory type with the required properties");
}

void Device::trackAllocation(const std::string& name, VkDeviceSize bytes) { allocations_[name] += bytes; }

void Device::untrackAllocation(const std::string& name, VkDeviceSize bytes) {
  auto it = allocations_.find(name);
  if (it == allocations_.end()) return;
  it->second -= std::min(it->second, bytes);
  if (it->second == 0) allocations_.erase(it);
}

VKAPI_ATTR VkBool32 VKAPI_CALL Device::onValidationMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                           VkDebugUtilsMessageTypeFlagsEXT,
                                                           const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                           void* user) {
  auto* self = static_cast<Device*>(user);
  const bool error = severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  std::fprintf(stderr, "[vulkan %s] %s\n", error ? "error" : "warning", data->pMessage);
  if (error) {
    self->lastValidationError_ = data->pMessage;
    ++self->validationErrors_;
  }
  return VK_FALSE;
}

}  // namespace ssvgi::gpu
