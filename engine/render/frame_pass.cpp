#include "render/frame_pass.h"

#include "core/error.h"

#include <algorithm>

namespace metamer {

FrameResource FrameResource::perFrame(std::string name, VkImage image, uint32_t layers, VkImageAspectFlags aspect) {
    FrameResource r;
    r.name = std::move(name);
    r.image = image;
    r.layers = layers;
    r.aspect = aspect;
    return r;
}

FrameResource FrameResource::perFrame(std::string name, VkBuffer buffer) {
    FrameResource r;
    r.name = std::move(name);
    r.buffer = buffer;
    return r;
}

FrameResource FrameResource::madeFor(std::string name, VkImage image, uint32_t layers, vk::Use use) {
    FrameResource r = perFrame(std::move(name), image, layers,
                               use.depthAspect ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT);
    r.entry = vk::ResourceState{};
    r.exit = vk::settledIn(use);
    return r;
}

FrameResource FrameResource::settled(std::string name, VkImage image, uint32_t layers, vk::Use use) {
    FrameResource r = perFrame(std::move(name), image, layers,
                               use.depthAspect ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT);
    r.entry = r.exit = vk::settledIn(use);
    return r;
}

FrameResource FrameResource::settled(std::string name, VkBuffer buffer, vk::Access access) {
    FrameResource r = perFrame(std::move(name), buffer);
    r.entry = r.exit = vk::settledIn({access});
    return r;
}

size_t Frame::add(FrameResource resource) {
    resources_.push_back(std::move(resource));
    waits_.clear();
    return resources_.size() - 1;
}

void Frame::add(FramePass pass) {
    passes_.push_back(std::move(pass));
    waits_.clear();  // derive() again
}

void Frame::clear() {
    resources_.clear();
    passes_.clear();
    waits_.clear();
    end_.clear();
}

namespace {

using States = std::vector<std::vector<vk::ResourceState>>;  // [resource][layer]

// Adds layer l's barrier to `out`, extending the last one where it is the same barrier on the
// layer before: one barrier per run of layers.
void append(std::vector<PassBarrier>& out, size_t resource, uint32_t l, const vk::Barrier& b) {
    if (!out.empty() && out.back().resource == resource && out.back().firstLayer + out.back().layerCount == l &&
        out.back().barrier == b)
        ++out.back().layerCount;
    else
        out.push_back({resource, l, 1, b});
}

// The barriers of one use on a resource's layers (into `out`, if given); the layers' states
// advanced past the use.
void applyUse(const FrameResource& r, size_t index, const ResourceUse& u, std::vector<vk::ResourceState>& layers,
              std::vector<PassBarrier>* out) {
    const vk::Use use{u.access, u.keepsContents, r.aspect == VK_IMAGE_ASPECT_DEPTH_BIT};
    const uint32_t end = u.layerCount == kAllLayers ? r.layers : u.firstLayer + u.layerCount;
    for (uint32_t l = u.firstLayer; l < end; ++l) {
        if (out)
            if (const std::optional<vk::Barrier> b = vk::barrierFor(layers[l], use, r.isImage())) append(*out, index, l, *b);
        layers[l] = vk::advance(layers[l], use, r.isImage());
    }
}

}  // namespace

void Frame::derive() {
    const size_t n = passes_.size();
    // Every use names a resource of the frame and layers it has, and no pass uses a layer twice.
    for (const FramePass& p : passes_) {
        std::vector<std::vector<bool>> touched(resources_.size());
        for (const ResourceUse& u : p.uses) {
            if (u.resource >= resources_.size())
                failRuntime("frame pass '{}' uses resource {}; the frame holds {}", p.name, u.resource, resources_.size());
            const FrameResource& r = resources_[u.resource];
            const uint32_t count = u.layerCount == kAllLayers ? r.layers - std::min(u.firstLayer, r.layers) : u.layerCount;
            if (u.firstLayer >= r.layers || count == 0 || u.firstLayer + count > r.layers)
                failRuntime("frame pass '{}' uses layers {}…{} of '{}', which has {}", p.name, u.firstLayer,
                            u.firstLayer + count - 1, r.name, r.layers);
            if (!vk::accessFits(u.access, r.isImage()))
                failRuntime("frame pass '{}' uses the {} '{}' as a {}, which only {} take", p.name,
                            r.isImage() ? "image" : "buffer", r.name, vk::accessName(u.access),
                            r.isImage() ? "buffers" : "images");
            touched[u.resource].resize(r.layers, false);
            for (uint32_t l = u.firstLayer; l < u.firstLayer + count; ++l) {
                if (touched[u.resource][l])
                    failRuntime("frame pass '{}' uses layer {} of '{}' twice", p.name, l, r.name);
                touched[u.resource][l] = true;
            }
        }
    }
    // The frame's own resources enter as the frame leaves them: walk it once from nothing to find
    // that, checking that each layer's first use writes it whole.
    States states(resources_.size());
    for (size_t i = 0; i < resources_.size(); ++i)
        states[i].assign(resources_[i].layers, resources_[i].entry.value_or(vk::ResourceState{}));
    States firstWalk = states;
    std::vector<std::vector<bool>> used(resources_.size());
    for (size_t i = 0; i < resources_.size(); ++i) used[i].assign(resources_[i].layers, false);
    for (const FramePass& p : passes_)
        for (const ResourceUse& u : p.uses) {
            const FrameResource& r = resources_[u.resource];
            if (!r.entry) {
                const uint32_t end = u.layerCount == kAllLayers ? r.layers : u.firstLayer + u.layerCount;
                for (uint32_t l = u.firstLayer; l < end; ++l) {
                    if (!used[u.resource][l] && (!vk::accessWrites(u.access) || (r.isImage() && u.keepsContents)))
                        failRuntime("frame pass '{}' needs the contents of '{}'{} ({}), but no earlier pass of the "
                                    "frame writes them and the resource declares no state at the frame's start",
                                    p.name, r.name, r.layers > 1 ? fmt::format(" layer {}", l) : "",
                                    vk::accessName(u.access));
                    used[u.resource][l] = true;
                }
            }
            applyUse(r, u.resource, u, firstWalk[u.resource], nullptr);
        }
    for (size_t i = 0; i < resources_.size(); ++i)
        if (!resources_[i].entry) states[i] = firstWalk[i];
    // The walk that keeps the barriers.
    waits_.assign(n + 1, {});
    for (size_t p = 0; p < n; ++p)
        for (const ResourceUse& u : passes_[p].uses) applyUse(resources_[u.resource], u.resource, u, states[u.resource], &waits_[p]);
    for (size_t i = 0; i < resources_.size(); ++i) {
        const FrameResource& r = resources_[i];
        if (!r.exit) continue;
        for (uint32_t l = 0; l < r.layers; ++l) {
            if (const std::optional<vk::Barrier> b = vk::barrierTo(states[i][l], *r.exit, r.isImage()))
                append(waits_[n], i, l, *b);
            states[i][l] = *r.exit;
        }
    }
    end_ = std::move(states);
}

const std::vector<PassBarrier>& Frame::waits(size_t p) const {
    if (waits_.size() != passes_.size() + 1) failRuntime("Frame::waits before Frame::derive");
    return waits_.at(p);
}

vk::ResourceState Frame::stateAtEnd(size_t resource) const {
    if (waits_.size() != passes_.size() + 1) failRuntime("Frame::stateAtEnd before Frame::derive");
    const std::vector<vk::ResourceState>& layers = end_.at(resource);
    for (const vk::ResourceState& s : layers)
        if (!(s == layers.front()))
            failRuntime("'{}' ends the frame with its layers in different states", resources_[resource].name);
    return layers.front();
}

std::string Frame::describe() const {
    std::string s;
    for (const FramePass& p : passes_) s += (s.empty() ? "" : " → ") + p.name;
    return s;
}

std::vector<std::pair<size_t, size_t>> Frame::drawingSteps() const {
    std::vector<std::pair<size_t, size_t>> steps;
    size_t begin = 0;
    bool drawn = false;  // the current piece holds a pass that draws
    for (size_t p = 0; p < passes_.size(); ++p) {
        if (passes_[p].renderPass == VK_NULL_HANDLE) continue;
        if (drawn) {
            steps.push_back({begin, p});
            begin = p;
        }
        drawn = true;
    }
    steps.push_back({begin, passes_.size()});
    return steps;
}

std::string Frame::describeWaits(size_t p) const {
    std::string text;
    for (const PassBarrier& b : waits(p)) {
        const FrameResource& r = resources_[b.resource];
        const std::string layers = !r.isImage() || r.layers == 1 ? ""
                                   : b.layerCount == 1          ? fmt::format(" layer {}", b.firstLayer)
                                                                : fmt::format(" layers {}–{}", b.firstLayer, b.firstLayer + b.layerCount - 1);
        text += fmt::format("{}{}: {}\n", r.name, layers, vk::describeBarrier(b.barrier, r.isImage()));
    }
    return text;
}

void recordFrame(VkCommandBuffer cmd, const Frame& frame, size_t first, size_t end) {
    end = std::min(end, frame.size());
    auto wait = [&](size_t p) {
        vk::BarrierBatch batch;
        for (const PassBarrier& b : frame.waits(p)) {
            const FrameResource& r = frame.resources()[b.resource];
            if (r.isImage())
                batch.image(r.image, r.aspect, b.firstLayer, b.layerCount, b.barrier);
            else
                batch.buffer(r.buffer, b.barrier);
        }
        batch.record(cmd);
    };
    for (size_t p = first; p < end; ++p) {
        wait(p);
        const FramePass& pass = frame.passes()[p];
        if (pass.renderPass == VK_NULL_HANDLE) {
            if (pass.record) pass.record(cmd);
            continue;
        }
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
    if (end == frame.size()) wait(end);
}

}  // namespace metamer
