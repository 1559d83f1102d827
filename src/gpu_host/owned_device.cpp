#include "owned_device.h"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <optional>

namespace ssvgi::gpu {

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

// What the validation layer reported, where its callback can reach it before the device exists.
struct ValidationLog {
  std::atomic<uint32_t> errors{0};
  std::string lastError;
};

VKAPI_ATTR VkBool32 VKAPI_CALL onValidationMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                  VkDebugUtilsMessageTypeFlagsEXT,
                                                  const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  auto* log = static_cast<ValidationLog*>(user);
  const bool error = severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  std::fprintf(stderr, "[vulkan %s] %s\n", error ? "error" : "warning", data->pMessage);
  if (error) {
    log->lastError = data->pMessage;
    ++log->errors;
  }
  return VK_FALSE;
}

// The physical device the selector picks among the usable ones; throws DeviceSelectionError when there is none.
uint32_t selectDevice(const std::string& selector, const std::vector<VkPhysicalDevice>& devices,
                      const std::vector<DeviceReport>& reports) {
  if (selector == "auto" || selector == "gpu" || selector == "cpu") {
    std::optional<uint32_t> chosen;
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
      std::string reason = "no usable Vulkan device of this kind; found:";
      for (const auto& report : reports) {
        reason += " [" + std::to_string(report.index) + "] " + report.name + " (" + report.type + ")";
        for (const auto& capability : report.capabilities)
          if (capability.required && !capability.present) reason += " missing " + capability.name + ";";
      }
      throw DeviceSelectionError(selector, reason);
    }
    return *chosen;
  }
  char* end = nullptr;
  const unsigned long index = std::strtoul(selector.c_str(), &end, 10);
  if (selector.empty() || *end != '\0')
    throw DeviceSelectionError(selector, "must be auto, cpu, gpu or a device index");
  if (index >= devices.size())
    throw DeviceSelectionError(selector, "there are only " + std::to_string(devices.size()) + " Vulkan devices");
  if (!reports[index].usable()) throw DeviceSelectionError(selector, reports[index].name + " lacks a required feature");
  return static_cast<uint32_t>(index);
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

// Destroys whatever creation got to, so that a failure half-way leaks nothing.
struct OwnedDevice::Created {
  VkInstance instance = VK_NULL_HANDLE;
  bool debugUtils = false;
  VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
  ValidationLog validation;
  VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
  std::string driverInfo;
  uint32_t queueFamily = 0;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;

  Created() = default;
  Created(const Created&) = delete;
  Created& operator=(const Created&) = delete;
  ~Created() {
    if (device) vkDestroyDevice(device, nullptr);
    if (messenger) {
      auto destroyMessenger = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
      destroyMessenger(instance, messenger, nullptr);
    }
    if (instance) vkDestroyInstance(instance, nullptr);
  }
};

std::unique_ptr<OwnedDevice::Created> OwnedDevice::create(const DeviceDesc& desc) {
  if (desc.validation && !hasLayer(kValidationLayer))
    throw GpuError("validation was requested but VK_LAYER_KHRONOS_validation is not installed "
                   "(install vulkan-validationlayers)");
  auto created = std::make_unique<Created>();
  created->debugUtils = hasInstanceExtension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  created->instance = createInstance(desc.validation, created->debugUtils, desc.instanceExtensions);
  const VkInstance instance = created->instance;

  if (created->debugUtils && desc.validation) {
    auto createMessenger = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
    VkDebugUtilsMessengerCreateInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    info.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
    info.pfnUserCallback = &onValidationMessage;
    info.pUserData = &created->validation;
    VK_CHECK(createMessenger(instance, &info, nullptr, &created->messenger));
  }

  const auto devices = physicalDevices(instance);
  if (devices.empty())
    throw GpuError("no Vulkan device found (on a machine without a GPU, install mesa-vulkan-drivers for lavapipe)");
  std::vector<DeviceReport> reports;
  for (uint32_t i = 0; i < devices.size(); ++i) reports.push_back(describe(devices[i], i));
  const VkPhysicalDevice physicalDevice = devices[selectDevice(desc.selector, devices, reports)];
  created->physicalDevice = physicalDevice;
  created->queueFamily = *graphicsComputeQueueFamily(physicalDevice);
  VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  VkPhysicalDeviceProperties2 properties2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &driver};
  vkGetPhysicalDeviceProperties2(physicalDevice, &properties2);
  created->driverInfo = std::string(driver.driverName) + " " + driver.driverInfo;

  const float priority = 1.0f;
  VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queueInfo.queueFamilyIndex = created->queueFamily;
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
  const VkResult result = vkCreateDevice(physicalDevice, &info, nullptr, &created->device);
  if (result == VK_ERROR_EXTENSION_NOT_PRESENT) {
    std::string names;
    for (const std::string& extension : desc.deviceExtensions) names += (names.empty() ? "" : ", ") + extension;
    throw GpuError(std::string(properties2.properties.deviceName) + " lacks a device extension of " + names, result);
  }
  VK_CHECK(result);
  vkGetDeviceQueue(created->device, created->queueFamily, 0, &created->queue);
  return created;
}

OwnedDevice::OwnedDevice(const DeviceDesc& desc) : OwnedDevice(create(desc)) {}

// The base wraps the created handles as a host's; if that throws, `created` still destroys them.
OwnedDevice::OwnedDevice(std::unique_ptr<Created> created)
    : Device(ExternalDevice{created->instance, created->physicalDevice, created->device, created->debugUtils}),
      created_(std::move(created)) {
  VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  poolInfo.queueFamilyIndex = created_->queueFamily;
  VK_CHECK(vkCreateCommandPool(device(), &poolInfo, nullptr, &commandPool_));
  VkCommandBufferAllocateInfo commandBufferInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  commandBufferInfo.commandPool = commandPool_;
  commandBufferInfo.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  commandBufferInfo.commandBufferCount = 1;
  VK_CHECK(vkAllocateCommandBuffers(device(), &commandBufferInfo, &commandBuffer_));
  VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VK_CHECK(vkCreateFence(device(), &fenceInfo, nullptr, &fence_));
}

OwnedDevice::~OwnedDevice() {
  vkDeviceWaitIdle(device());
  vkDestroyFence(device(), fence_, nullptr);
  vkDestroyCommandPool(device(), commandPool_, nullptr);
}  // then created_ destroys the device and the instance

VkQueue OwnedDevice::queue() const { return created_->queue; }
uint32_t OwnedDevice::queueFamily() const { return created_->queueFamily; }

std::string OwnedDevice::description() const {
  return std::string(properties().deviceName) + " (" + deviceTypeName(properties().deviceType) + ", Vulkan " +
         versionString(properties().apiVersion) + ", " + created_->driverInfo + ")";
}

// One command buffer, re-recorded by every submit and freed only with its pool. Freeing the command buffer as soon as
// its fence had signalled and allocating the next one (which gets the same handle back) corrupted the heap under the
// Khronos validation layer on lavapipe when the CPU was oversubscribed (docs/ARCHITECTURE.md, "Tests"): the crashes
// were inside the layer (vkCmdBeginDebugUtilsLabelEXT, vkAllocateDescriptorSets) while the layer's own queue thread
// was still busy with the submission the fence wait had just returned from.
void OwnedDevice::submitAndWait(const std::function<void(VkCommandBuffer)>& record) {
  if (recording_) throw GpuError("OwnedDevice::submitAndWait was called while recording its own command buffer");
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
  VK_CHECK(vkQueueSubmit(created_->queue, 1, &submit, fence_));
  VK_CHECK(vkWaitForFences(device(), 1, &fence_, VK_TRUE, UINT64_MAX));
  VK_CHECK(vkResetFences(device(), 1, &fence_));
}

uint32_t OwnedDevice::validationErrorCount() const { return created_->validation.errors.load(); }
const std::string& OwnedDevice::lastValidationError() const { return created_->validation.lastError; }

}  // namespace ssvgi::gpu
