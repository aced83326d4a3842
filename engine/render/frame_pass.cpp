#include "render/frame_pass.h"

namespace metamer {

void recordFramePass(VkCommandBuffer cmd, const FramePass& pass) {
    VkRenderPassBeginInfo rb{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    rb.renderPass = pass.renderPass;
    rb.framebuffer = pass.framebuffer;
    rb.renderArea = {{0, 0}, pass.extent};
    rb.clearValueCount = uint32_t(pass.clears.size());
    rb.pClearValues = pass.clears.empty() ? nullptr : pass.clears.data();
    vkCmdBeginRenderPass(cmd, &rb, VK_SUBPASS_CONTENTS_INLINE);
    if (pass.record) pass.record(cmd);
    vkCmdEndRenderPass(cmd);
}

std::string describeFramePasses(const std::vector<FramePass>& passes) {
    std::string s;
    for (const FramePass& p : passes) s += (s.empty() ? "" : " → ") + p.name;
    return s;
}

}  // namespace metamer
