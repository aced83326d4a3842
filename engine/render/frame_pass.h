// A frame as data: the images and buffers its passes share (FrameResource) and its passes in order
// (FramePass), each naming what it does with which resource (ResourceUse: an access from
// vk/barrier.h on some of an image's layers). The barriers between passes are not written by hand:
// Frame::derive walks the declared uses once and stores, per pass, what it waits for (waits(p));
// recordFrame records those barriers before each pass, then the pass — a render pass with its
// draws, or commands outside one (a clear, a copy) — and at the end what leaves each resource as
// declared. The spectral frame (render/spectral_recording.cpp), the shadow maps (render/shadow_pass.cpp),
// the coloured shadows' maps (render/shadow_transmittance.cpp), texture uploads and the tonemap pass
// (render/tonemap_pass.cpp) are Frames.
// Tests: engine/render/frame_pass_test.cpp (derived barriers); every GPU test (validation layers on).
#pragma once

#include "vk/barrier.h"

#include <vulkan/vulkan.h>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace metamer {

// An image or a buffer a frame's passes use.
struct FrameResource {
    std::string name;  // "spectral target", "depth", "readback buffer"
    VkImage image = VK_NULL_HANDLE;    // an image, or …
    VkBuffer buffer = VK_NULL_HANDLE;  // … a buffer
    uint32_t layers = 1;
    VkImageAspectFlags aspect = VK_IMAGE_ASPECT_COLOR_BIT;
    // Its state when the frame starts. None: the frame's own — made and used within each recording
    // of a frame recorded again and again, so it enters each as the last one left it; its first use
    // must then not need its contents. A resource made once elsewhere (a texture, the shadow maps)
    // enters settled where it rests; a new image enters UNDEFINED (the default state).
    std::optional<vk::ResourceState> entry;
    // The state the frame must leave it in (an image made for later frames; a borrowed one handed
    // back as it came). None: as its last use left it.
    std::optional<vk::ResourceState> exit;

    bool isImage() const { return image != VK_NULL_HANDLE; }

    // The frame's own image or buffer (entry: as the previous recording left it).
    static FrameResource perFrame(std::string name, VkImage image, uint32_t layers = 1,
                                  VkImageAspectFlags aspect = VK_IMAGE_ASPECT_COLOR_BIT);
    static FrameResource perFrame(std::string name, VkBuffer buffer);
    // A new image the frame makes for later frames: enters UNDEFINED, leaves settled in `use`
    // (its writes visible to that use), as the shadow maps and textures are made.
    static FrameResource madeFor(std::string name, VkImage image, uint32_t layers, vk::Use use);
    // Made before the frame and only read in it: enters and leaves settled in `use`.
    static FrameResource settled(std::string name, VkImage image, uint32_t layers, vk::Use use);
    static FrameResource settled(std::string name, VkBuffer buffer, vk::Access access);
};

constexpr uint32_t kAllLayers = ~0u;

// What a pass does with one resource.
struct ResourceUse {
    size_t resource = 0;  // index into Frame::resources
    vk::Access access = vk::Access::Sampled;
    uint32_t firstLayer = 0, layerCount = kAllLayers;
    // False when the pass needs nothing of what was there (a cleared or wholly written attachment,
    // a clear): the image may then come from UNDEFINED.
    bool keepsContents = true;
};

struct FramePass {
    std::string name;            // "depth pre-pass", "band pass 2", "shadow map layer 3", "tonemap"
    std::string specialization;  // how its shader is specialized, in words ("LOBE_WRITE; a pipeline per material kind")
    std::vector<ResourceUse> uses;
    // A render pass (attachments in the layouts of their uses: vk::accessLayout), or none: then
    // `record` runs outside a render pass (a clear, a copy, nothing for a host read).
    VkRenderPass renderPass = VK_NULL_HANDLE;
    VkFramebuffer framebuffer = VK_NULL_HANDLE;
    VkExtent2D extent{0, 0};
    std::vector<VkClearValue> clears;             // one per attachment, colours first
    std::function<void(VkCommandBuffer)> record;  // its commands (inside the render pass, if any)
};

// One derived barrier: on `resource`'s layers [firstLayer, firstLayer + layerCount) (a buffer: 0, 1).
struct PassBarrier {
    size_t resource = 0;
    uint32_t firstLayer = 0, layerCount = 1;
    vk::Barrier barrier;
};

class Frame {
public:
    // Adds a resource; its index, for ResourceUse::resource.
    size_t add(FrameResource resource);
    void add(FramePass pass);

    // Derives every pass's barriers from the declared uses (after the last add). A use of a
    // resource the frame does not hold, a layer range outside it, or a frame-owned resource whose
    // first use needs contents nobody wrote is a runtime error naming the pass and the resource.
    void derive();

    // What pass p waits for before it starts; p == passes().size(): what the frame does after its
    // last pass (resources left as their exit states say).
    const std::vector<PassBarrier>& waits(size_t p) const;
    // waits(p) in words, one line per barrier: "depth: after early fragment tests, late fragment tests,
    // its writes made visible to early fragment tests, late fragment tests"
    std::string describeWaits(size_t p) const;
    // A resource's state after the whole frame (for a later frame that borrows it).
    vk::ResourceState stateAtEnd(size_t resource) const;

    const std::vector<FramePass>& passes() const { return passes_; }
    const std::vector<FrameResource>& resources() const { return resources_; }
    size_t size() const { return passes_.size(); }
    bool empty() const { return passes_.empty(); }
    void clear();
    // "a → b → c": the passes' names in order.
    std::string describe() const;
    // The frame cut where a pass-by-pass submission cuts it: each pass that draws (has a render
    // pass) with the passes without one before it, the last also with those after it, so that a
    // progress count counts the passes that draw. [begin, end) each; one piece if none draws.
    std::vector<std::pair<size_t, size_t>> drawingSteps() const;

private:
    std::vector<FrameResource> resources_;
    std::vector<FramePass> passes_;
    std::vector<std::vector<PassBarrier>> waits_;  // passes_.size() + 1 entries once derived
    std::vector<std::vector<vk::ResourceState>> end_;  // per resource, per layer
};

// Records passes [first, end) of a derived frame: each one's waits, then the pass; with the last
// pass, the frame's closing barriers. A frame submitted pass by pass records the same commands.
void recordFrame(VkCommandBuffer cmd, const Frame& frame, size_t first = 0, size_t end = SIZE_MAX);

}  // namespace metamer
