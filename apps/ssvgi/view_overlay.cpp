#include "view_overlay.h"

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_vulkan.h>
#include <imgui.h>

namespace ssvgi::cli {

namespace {

void checkImGuiVulkanResult(VkResult result) { VK_CHECK(result); }

// Draws over what the image holds (LOAD), in and out of COLOR_ATTACHMENT_OPTIMAL: the layout the barrier tracker
// moves it to for Usage::ColorAttachment and expects it in afterwards.
VkRenderPass createRenderPass(const gpu::OwnedDevice& device) {
  VkAttachmentDescription attachment{};
  attachment.format = ImGuiOverlay::kTargetFormat;
  attachment.samples = VK_SAMPLE_COUNT_1_BIT;
  attachment.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
  attachment.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  attachment.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  attachment.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  attachment.initialLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  attachment.finalLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  const VkAttachmentReference reference{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  VkSubpassDescription subpass{};
  subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  subpass.colorAttachmentCount = 1;
  subpass.pColorAttachments = &reference;
  VkRenderPassCreateInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
  info.attachmentCount = 1;
  info.pAttachments = &attachment;
  info.subpassCount = 1;
  info.pSubpasses = &subpass;
  VkRenderPass renderPass = VK_NULL_HANDLE;
  VK_CHECK(vkCreateRenderPass(device.device(), &info, nullptr, &renderPass));
  return renderPass;
}

// The font atlas's descriptor set is the only one ImGui allocates.
VkDescriptorPool createDescriptorPool(const gpu::OwnedDevice& device) {
  const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1};
  VkDescriptorPoolCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  info.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
  info.maxSets = 1;
  info.poolSizeCount = 1;
  info.pPoolSizes = &size;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  VK_CHECK(vkCreateDescriptorPool(device.device(), &info, nullptr, &pool));
  return pool;
}

}  // namespace

ImGuiOverlay::ImGuiOverlay(gpu::OwnedDevice& device, GLFWwindow* window)
    : device_(device), renderPass_(createRenderPass(device)), descriptorPool_(createDescriptorPool(device)) {
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // the panels' layout is the viewer's, not a file's in the working folder
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForVulkan(window, true);

  ImGui_ImplVulkan_InitInfo info{};
  info.Instance = device.instance();
  info.PhysicalDevice = device.physicalDevice();
  info.Device = device.device();
  info.QueueFamily = device.queueFamily();
  info.Queue = device.queue();
  info.DescriptorPool = descriptorPool_;
  info.MinImageCount = 2;  // its vertex buffers per frame in flight; the viewer waits for every frame
  info.ImageCount = 2;
  info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
  info.CheckVkResultFn = checkImGuiVulkanResult;
  ImGui_ImplVulkan_Init(&info, renderPass_);
  device.submitAndWait([](VkCommandBuffer commandBuffer) { ImGui_ImplVulkan_CreateFontsTexture(commandBuffer); });
  ImGui_ImplVulkan_DestroyFontUploadObjects();
}

ImGuiOverlay::~ImGuiOverlay() {
  vkDeviceWaitIdle(device_.device());
  ImGui_ImplVulkan_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  vkDestroyFramebuffer(device_.device(), framebuffer_, nullptr);
  vkDestroyDescriptorPool(device_.device(), descriptorPool_, nullptr);
  vkDestroyRenderPass(device_.device(), renderPass_, nullptr);
}

void ImGuiOverlay::newFrame() {
  ImGui_ImplVulkan_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
}

void ImGuiOverlay::setTarget(const gpu::Image& target) {
  vkDestroyFramebuffer(device_.device(), framebuffer_, nullptr);
  const VkImageView view = target.view();
  VkFramebufferCreateInfo info{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
  info.renderPass = renderPass_;
  info.attachmentCount = 1;
  info.pAttachments = &view;
  info.width = target.desc().width;
  info.height = target.desc().height;
  info.layers = 1;
  VK_CHECK(vkCreateFramebuffer(device_.device(), &info, nullptr, &framebuffer_));
  target_ = &target;
}

void ImGuiOverlay::record(gpu::CommandList& commands) {
  ImGui::Render();
  commands.use(*target_, gpu::Usage::ColorAttachment);
  commands.flushBarriers();
  const auto scope = commands.scope("viewer: ImGui");
  VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  begin.renderPass = renderPass_;
  begin.framebuffer = framebuffer_;
  begin.renderArea.extent = {target_->desc().width, target_->desc().height};
  vkCmdBeginRenderPass(commands.handle(), &begin, VK_SUBPASS_CONTENTS_INLINE);
  ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), commands.handle());
  vkCmdEndRenderPass(commands.handle());
}

}  // namespace ssvgi::cli
