// Pipeline barriers derived from what commands do with an image or a buffer. An Access names one
// kind of use (a colour attachment, a sampled image, a transfer's source, the host's read …); the
// table in barrier.cpp gives each its layout, pipeline stages and memory accesses. A ResourceState
// remembers what happened to one image layer (or a buffer) so far: its layout, the last write not
// yet made visible everywhere, and the reads since. barrierFor(state, use) answers whether the use
// must wait, and for what — read after write, write after read or write, a layout change — and
// advance() moves the state past the use. render/frame_pass.h walks a frame's declared passes with
// these; nothing outside vk/ fills a VkImageMemoryBarrier.
// Tests: engine/vk/barrier_test.cpp; every GPU test (validation layers on).
#pragma once

#include <vulkan/vulkan.h>

#include <optional>
#include <string>
#include <vector>

namespace metamer::vk {

// What a use does, each with its stages and layout (barrier.cpp, kAccesses). A new kind of use is
// one row there.
enum class Access {
    ColorAttachment,  // a render pass's colour attachment: written (read too when loaded or blended)
    DepthAttachment,  // a render pass's depth attachment: tested and written
    Sampled,          // read by fragment shaders through a sampler or texelFetch (depth images read-only)
    UniformRead,      // a uniform or uniform texel buffer read by fragment shaders
    StorageRead,      // a storage buffer read by fragment shaders
    VertexInput,      // vertex and index buffers
    TransferSrc,      // a copy's source
    TransferDst,      // a copy's or clear's destination
    HostRead,         // read by the host after the submission's fence (a mapped image stays GENERAL)
    Present,          // handed to the presentation engine
};

// The access's name in words ("colour attachment", "sampled", …), for descriptions and errors.
const char* accessName(Access access);
// Whether the access writes (a later use must wait for it) and the layout an image must be in.
bool accessWrites(Access access);
bool accessFits(Access access, bool image);  // an image's access (a layout, attachments) or a buffer's
VkImageLayout accessLayout(Access access, bool depthAspect = false);

// One use of an image layer or a buffer by a command. `keepsContents`: the use needs what was
// there before (a load, a blend, any read); false for a clear or an attachment whose every pixel
// is written, which lets the image come from UNDEFINED.
struct Use {
    Access access = Access::Sampled;
    bool keepsContents = true;
    bool depthAspect = false;
};

// What has happened to one image layer or buffer so far, as a barrier needs it.
struct ResourceState {
    VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;  // images only
    VkPipelineStageFlags writeStages = 0;  // the last write …
    VkAccessFlags writeAccess = 0;
    VkPipelineStageFlags readStages = 0;    // … the reads since, which a later write must wait for …
    VkPipelineStageFlags visibleStages = 0;  // … and where that write has been made visible already
    VkAccessFlags visibleAccess = 0;
    bool operator==(const ResourceState&) const = default;
};

// A resource's state right after `use` and a barrier that made it visible: how a frame leaves an
// image it made for later frames (the shadow maps: sampled, their depth writes visible to the
// fragment shaders that will read them), or where a resource made elsewhere rests.
ResourceState settledIn(Use use);

// The source and destination scopes of one barrier, and the layouts of an image's transition.
struct Barrier {
    VkImageLayout oldLayout = VK_IMAGE_LAYOUT_UNDEFINED, newLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    VkPipelineStageFlags srcStages = 0, dstStages = 0;
    VkAccessFlags srcAccess = 0, dstAccess = 0;
    bool operator==(const Barrier&) const = default;
};

// The barrier `use` needs after `state`, or none: a read waits for an unseen write, a write for the
// last write and the reads since, an image for a layout change (from UNDEFINED when the use keeps
// nothing). `image`: whether layouts apply.
std::optional<Barrier> barrierFor(const ResourceState& state, Use use, bool image);
// The state after `use` (with or without the barrier barrierFor asked for).
ResourceState advance(const ResourceState& state, Use use, bool image);
// The barrier that takes `state` to `target` (a frame's exit), or none when nothing needs it: a
// layout change, or a write not yet visible where the target says. Reads need none (the next frame
// starts after this one's fence).
std::optional<Barrier> barrierTo(const ResourceState& state, const ResourceState& target, bool image);

// "after colour attachment output, its writes made visible to fragment shader; COLOR_ATTACHMENT_OPTIMAL →
// SHADER_READ_ONLY_OPTIMAL"
std::string describeBarrier(const Barrier& b, bool image);
std::string layoutName(VkImageLayout layout);

// Barriers gathered for one vkCmdPipelineBarrier: stages are the union of theirs.
class BarrierBatch {
public:
    void image(VkImage image, VkImageAspectFlags aspect, uint32_t firstLayer, uint32_t layers, const Barrier& b);
    void buffer(VkBuffer buffer, const Barrier& b);
    bool empty() const { return images_.empty() && buffers_.empty(); }
    void record(VkCommandBuffer cmd) const;

private:
    VkPipelineStageFlags src_ = 0, dst_ = 0;
    std::vector<VkImageMemoryBarrier> images_;
    std::vector<VkBufferMemoryBarrier> buffers_;
};

}  // namespace metamer::vk
