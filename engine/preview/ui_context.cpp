#include "preview/ui_context.h"

#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_vulkan.h>

#include <filesystem>

namespace metamer::preview {

namespace {

void checkVk(VkResult r) {
    if (r != VK_SUCCESS) failRuntime("Vulkan (Dear ImGui backend): {}", vk::resultName(r));
}

// A font with the symbols the panel writes (λ, ², ⁻¹, ·, ×, Δ): DejaVu Sans from
// fonts-dejavu-core, else ImGui's built-in font (ASCII; the symbols then show as '?').
void loadFont() {
    ImGuiIO& io = ImGui::GetIO();
    const char* path = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
    if (!std::filesystem::exists(path)) return;
    static const ImWchar ranges[] = {0x0020, 0x00FF,   // Basic Latin, Latin-1 (², ·, ×, °)
                                     0x0370, 0x03FF,   // Greek (λ, Δ)
                                     0x2070, 0x209F,   // superscripts (⁻, ¹)
                                     0x2013, 0x2014,   // dashes
                                     0x2190, 0x2193,   // arrows
                                     0};
    io.Fonts->AddFontFromFileTTF(path, 15.0f, nullptr, ranges);
}

}  // namespace

UiContext::UiContext(vk::Context& ctx, const Window& window, Swapchain& swapchain) : ctx_(ctx), swapchain_(swapchain) {
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;  // no imgui.ini in the user's folder
    ImGui::StyleColorsDark();
    loadFont();

    VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 4};
    VkDescriptorPoolCreateInfo pi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pi.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
    pi.maxSets = 4;
    pi.poolSizeCount = 1;
    pi.pPoolSizes = &size;
    VK_CHECK(vkCreateDescriptorPool(ctx.device(), &pi, nullptr, &pool_));

    ImGui_ImplGlfw_InitForVulkan(window.handle(), true);
    ImGui_ImplVulkan_InitInfo info{};
    info.Instance = ctx.instance();
    info.PhysicalDevice = ctx.physicalDevice();
    info.Device = ctx.device();
    info.QueueFamily = ctx.queueFamily();
    info.Queue = ctx.queue();
    info.DescriptorPool = pool_;
    info.PipelineCache = ctx.pipelineCache();
    info.MinImageCount = swapchain.minImageCount();
    info.ImageCount = swapchain.imageCount();
    info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
    info.CheckVkResultFn = checkVk;
    ImGui_ImplVulkan_Init(&info, swapchain.renderPass());
    imageCount_ = swapchain.imageCount();
    ctx.submitAndWait([](VkCommandBuffer cmd) { ImGui_ImplVulkan_CreateFontsTexture(cmd); });
    ImGui_ImplVulkan_DestroyFontUploadObjects();
}

UiContext::~UiContext() {
    vkDeviceWaitIdle(ctx_.device());
    ImGui_ImplVulkan_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    if (pool_) vkDestroyDescriptorPool(ctx_.device(), pool_, nullptr);
}

void UiContext::newFrame() {
    if (swapchain_.imageCount() != imageCount_) {
        ImGui_ImplVulkan_SetMinImageCount(swapchain_.minImageCount());
        imageCount_ = swapchain_.imageCount();
    }
    ImGui_ImplVulkan_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
}

void UiContext::endFrame() { ImGui::Render(); }

void UiContext::record(VkCommandBuffer cmd) { ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), cmd); }

}  // namespace metamer::preview
