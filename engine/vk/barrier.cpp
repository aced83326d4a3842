#include "vk/barrier.h"

#include <fmt/format.h>

namespace metamer::vk {

namespace {

enum Fits { kImages = 1, kBuffers = 2, kBoth = 3 };

struct AccessInfo {
    const char* name;
    VkImageLayout layout;  // a depth image's sampled layout is DEPTH_STENCIL_READ_ONLY_OPTIMAL (accessLayout)
    VkPipelineStageFlags stages;
    VkAccessFlags reads, writes;
    int fits;  // what it may be applied to
};

constexpr VkPipelineStageFlags kDepthTests =
    VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;

// One row per Access, in its order. A colour attachment that keeps its contents also reads them
// (the load, the blend): barrierFor adds COLOR_ATTACHMENT_READ then.
constexpr AccessInfo kAccesses[] = {
    {"colour attachment", VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, 0,
     VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, kImages},
    {"depth attachment", VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL, kDepthTests,
     VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT, VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, kImages},
    {"sampled", VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT, 0,
     kImages},
    {"uniform", VK_IMAGE_LAYOUT_UNDEFINED, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
     VK_ACCESS_UNIFORM_READ_BIT | VK_ACCESS_SHADER_READ_BIT, 0, kBuffers},
    {"storage read", VK_IMAGE_LAYOUT_UNDEFINED, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT, 0, kBuffers},
    {"vertex input", VK_IMAGE_LAYOUT_UNDEFINED, VK_PIPELINE_STAGE_VERTEX_INPUT_BIT,
     VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT | VK_ACCESS_INDEX_READ_BIT, 0, kBuffers},
    {"transfer source", VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT, 0,
     kBoth},
    {"transfer destination", VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_TRANSFER_BIT, 0,
     VK_ACCESS_TRANSFER_WRITE_BIT, kBoth},
    {"host read", VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT, 0, kBoth},
    // Presentation waits on a semaphore, not on the barrier's stages: nothing after it to scope.
    {"present", VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, 0, 0, kImages},
};
static_assert(sizeof kAccesses / sizeof kAccesses[0] == size_t(Access::Present) + 1, "one row per Access");

const AccessInfo& info(Access a) { return kAccesses[size_t(a)]; }

VkAccessFlags readsOf(Use u) {
    const VkAccessFlags reads = info(u.access).reads;
    return u.access == Access::ColorAttachment && u.keepsContents ? reads | VK_ACCESS_COLOR_ATTACHMENT_READ_BIT : reads;
}

std::string stageNames(VkPipelineStageFlags s) {
    static const std::pair<VkPipelineStageFlags, const char*> names[] = {
        {VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, "top of pipe"},
        {VK_PIPELINE_STAGE_VERTEX_INPUT_BIT, "vertex input"},
        {VK_PIPELINE_STAGE_VERTEX_SHADER_BIT, "vertex shader"},
        {VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT, "early fragment tests"},
        {VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, "fragment shader"},
        {VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT, "late fragment tests"},
        {VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, "colour attachment output"},
        {VK_PIPELINE_STAGE_TRANSFER_BIT, "transfer"},
        {VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, "bottom of pipe"},
        {VK_PIPELINE_STAGE_HOST_BIT, "host"},
    };
    std::string text;
    for (const auto& [bit, name] : names)
        if (s & bit) text += (text.empty() ? "" : ", ") + std::string(name);
    return text.empty() ? "nothing" : text;
}

}  // namespace

const char* accessName(Access access) { return info(access).name; }
bool accessWrites(Access access) { return info(access).writes != 0; }
bool accessFits(Access access, bool image) { return (info(access).fits & (image ? kImages : kBuffers)) != 0; }

VkImageLayout accessLayout(Access access, bool depthAspect) {
    if (access == Access::Sampled && depthAspect) return VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL;
    return info(access).layout;
}

std::optional<Barrier> barrierFor(const ResourceState& s, Use u, bool image) {
    const AccessInfo& a = info(u.access);
    const VkAccessFlags reads = readsOf(u), writes = a.writes;
    const VkImageLayout layout = image ? accessLayout(u.access, u.depthAspect) : VK_IMAGE_LAYOUT_UNDEFINED;
    const bool relayout = image && s.layout != layout;
    // Write after write or read: wait for both (execution for the reads, memory for the write).
    const bool afterOthers = writes != 0 && (s.writeStages != 0 || s.readStages != 0);
    // Read after write: unless this stage has seen the write already.
    const bool unseenWrite = reads != 0 && s.writeAccess != 0 &&
                             ((a.stages & ~s.visibleStages) != 0 || (reads & ~s.visibleAccess) != 0);
    if (!relayout && !afterOthers && !unseenWrite) return std::nullopt;
    Barrier b;
    b.srcStages = s.writeStages | s.readStages;
    b.srcAccess = s.writeAccess;
    b.dstStages = a.stages;
    b.dstAccess = reads | writes;
    if (image) {
        b.oldLayout = u.keepsContents ? s.layout : VK_IMAGE_LAYOUT_UNDEFINED;
        b.newLayout = layout;
    }
    return b;
}

ResourceState advance(const ResourceState& s, Use u, bool image) {
    const AccessInfo& a = info(u.access);
    ResourceState next = s;
    if (image) next.layout = accessLayout(u.access, u.depthAspect);
    if (a.writes != 0) {
        next.writeStages = a.stages;
        next.writeAccess = a.writes;
        next.readStages = 0;
        next.visibleStages = 0;
        next.visibleAccess = 0;
    } else {
        next.readStages |= a.stages;
        // A read that waited for the write (or a write with nothing to wait for) has seen it.
        if (barrierFor(s, u, image) || s.writeAccess == 0) {
            next.visibleStages |= a.stages;
            next.visibleAccess |= readsOf(u);
        }
    }
    return next;
}

ResourceState settledIn(Use u) {
    ResourceState s;
    s.layout = accessLayout(u.access, u.depthAspect);
    s.visibleStages = info(u.access).stages;
    s.visibleAccess = readsOf(u);
    return s;
}

std::optional<Barrier> barrierTo(const ResourceState& s, const ResourceState& target, bool image) {
    const bool relayout = image && s.layout != target.layout;
    // Reads need nothing after the frame: a later frame starts after this one's fence, so only a
    // write not yet seen where the target says it is (or another write than it says) needs a barrier.
    const bool writeServed = s.writeAccess == 0 ||
                             (s.writeStages == target.writeStages && s.writeAccess == target.writeAccess &&
                              (target.visibleStages & ~s.visibleStages) == 0 && (target.visibleAccess & ~s.visibleAccess) == 0);
    if (!relayout && writeServed) return std::nullopt;
    Barrier b;
    b.srcStages = s.writeStages | s.readStages;
    b.srcAccess = s.writeAccess;
    // Whoever comes next believes the target state: scope the stages it will wait on or read in.
    b.dstStages = target.writeStages | target.readStages | target.visibleStages;
    b.dstAccess = target.visibleAccess;
    if (image) {
        b.oldLayout = s.layout;
        b.newLayout = target.layout;
    }
    return b;
}

std::string layoutName(VkImageLayout layout) {
    switch (layout) {
        case VK_IMAGE_LAYOUT_UNDEFINED: return "UNDEFINED";
        case VK_IMAGE_LAYOUT_GENERAL: return "GENERAL";
        case VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL: return "COLOR_ATTACHMENT_OPTIMAL";
        case VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL: return "DEPTH_STENCIL_ATTACHMENT_OPTIMAL";
        case VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL: return "DEPTH_STENCIL_READ_ONLY_OPTIMAL";
        case VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL: return "SHADER_READ_ONLY_OPTIMAL";
        case VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL: return "TRANSFER_SRC_OPTIMAL";
        case VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL: return "TRANSFER_DST_OPTIMAL";
        case VK_IMAGE_LAYOUT_PRESENT_SRC_KHR: return "PRESENT_SRC_KHR";
        default: return fmt::format("layout {}", int(layout));
    }
}

std::string describeBarrier(const Barrier& b, bool image) {
    std::string text = b.srcStages == 0 ? fmt::format("before {} (nothing to wait for)", stageNames(b.dstStages))
                       : b.srcAccess ? fmt::format("after {}, its writes made visible to {}", stageNames(b.srcStages),
                                                   stageNames(b.dstStages))
                                     : fmt::format("after {} (execution only), before {}", stageNames(b.srcStages),
                                                   stageNames(b.dstStages));
    if (image && b.oldLayout != b.newLayout)
        text += fmt::format("; {} → {}", layoutName(b.oldLayout), layoutName(b.newLayout));
    return text;
}

void BarrierBatch::image(VkImage image, VkImageAspectFlags aspect, uint32_t firstLayer, uint32_t layers, const Barrier& b) {
    VkImageMemoryBarrier m{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    m.srcAccessMask = b.srcAccess;
    m.dstAccessMask = b.dstAccess;
    m.oldLayout = b.oldLayout;
    m.newLayout = b.newLayout;
    m.srcQueueFamilyIndex = m.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    m.image = image;
    m.subresourceRange = {aspect, 0, 1, firstLayer, layers};
    images_.push_back(m);
    src_ |= b.srcStages;
    dst_ |= b.dstStages;
}

void BarrierBatch::buffer(VkBuffer buffer, const Barrier& b) {
    VkBufferMemoryBarrier m{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER};
    m.srcAccessMask = b.srcAccess;
    m.dstAccessMask = b.dstAccess;
    m.srcQueueFamilyIndex = m.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    m.buffer = buffer;
    m.size = VK_WHOLE_SIZE;
    buffers_.push_back(m);
    src_ |= b.srcStages;
    dst_ |= b.dstStages;
}

void BarrierBatch::record(VkCommandBuffer cmd) const {
    if (empty()) return;
    // Nothing to wait for (an image's first use): the transition waits on nothing before it.
    const VkPipelineStageFlags src = src_ ? src_ : VkPipelineStageFlags(VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT);
    const VkPipelineStageFlags dst = dst_ ? dst_ : VkPipelineStageFlags(VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
    vkCmdPipelineBarrier(cmd, src, dst,
                         0, 0, nullptr, uint32_t(buffers_.size()), buffers_.empty() ? nullptr : buffers_.data(),
                         uint32_t(images_.size()), images_.empty() ? nullptr : images_.data());
}

}  // namespace metamer::vk
