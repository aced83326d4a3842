// Shared device objects (vk/device_objects): one handle per key, reused; a handle lives while it
// is held or cached; what a pipeline was made with lives as long as it does.
#include "vk/device_objects.h"

#include "support/gpu.h"

#include <gtest/gtest.h>

using namespace metamer;
using namespace metamer::test;

namespace {

VkRenderPass makeRenderPass(VkDevice d) {
    VkAttachmentDescription a{};
    a.format = VK_FORMAT_R32G32B32A32_SFLOAT;
    a.samples = VK_SAMPLE_COUNT_1_BIT;
    a.loadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    a.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    a.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    a.finalLayout = VK_IMAGE_LAYOUT_GENERAL;
    VkAttachmentReference ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkSubpassDescription sub{};
    sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    sub.colorAttachmentCount = 1;
    sub.pColorAttachments = &ref;
    VkRenderPassCreateInfo rp{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    rp.attachmentCount = 1;
    rp.pAttachments = &a;
    rp.subpassCount = 1;
    rp.pSubpasses = &sub;
    VkRenderPass r = VK_NULL_HANDLE;
    VK_CHECK(vkCreateRenderPass(d, &rp, nullptr, &r));
    return r;
}

}  // namespace

TEST(DeviceObjects, OneHandlePerKeyKeptWhileHeldOrCachedAndItsDependenciesWithIt) {
    const uint32_t before = gpu().validationErrors();
    VkDevice d = gpu().device();
    {
        vk::DeviceObjects objects(d, 2);
        int made = 0;
        auto make = [&] {
            ++made;
            return makeRenderPass(d);
        };
        const auto a = objects.renderPass("a", make);
        EXPECT_EQ(objects.renderPass("a", make), a);  // reused, not made again
        EXPECT_EQ(made, 1);
        auto b = objects.renderPass("b", make);
        EXPECT_NE(b, a);
        EXPECT_EQ(made, 2);
        EXPECT_EQ(objects.made(), 2u);
        EXPECT_EQ(objects.reused(), 1u);
        // A third key pushes the least recently used ("a") out of the cache; its holder keeps it.
        std::weak_ptr<VkRenderPass_T> watchA = a;
        objects.renderPass("c", make);
        EXPECT_FALSE(watchA.expired());
        EXPECT_NE(objects.renderPass("a", make), a);  // made again: it was no longer cached
        EXPECT_EQ(made, 4);
        // What something was made with lives as long as it does.
        std::weak_ptr<VkRenderPass_T> watchB = b;
        auto layoutUser = objects.pipelineLayout(
            "layout",
            [&] {
                VkPipelineLayoutCreateInfo pl{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
                VkPipelineLayout h = VK_NULL_HANDLE;
                VK_CHECK(vkCreatePipelineLayout(d, &pl, nullptr, &h));
                return h;
            },
            {b});
        objects.clear();
        b.reset();
        EXPECT_FALSE(watchB.expired());  // the layout, still held here, holds it
        layoutUser.reset();
        EXPECT_TRUE(watchB.expired());   // and lets go with it
    }
    EXPECT_NO_VALIDATION_ERRORS(before);  // every handle destroyed once (the layers report leaks at the end)
}

TEST(DeviceObjects, KeysOfSpecializationBytesAreHex) {
    const uint32_t v[2] = {1, 0xabcdef00};
    EXPECT_EQ(vk::keyBytes(v, sizeof v), "0100000000efcdab");
}

// What a render may reuse from an earlier one (a scene's shadow maps): made once per key, the
// same object returned while it is among the `keep` most recent, made again after, and a holder's
// copy stays alive when the cache lets it go.
TEST(DeviceObjects, ReusablesAreMadeOncePerKeyAndTheMostRecentAreKept) {
    vk::DeviceObjects objects(gpu().device());
    int made = 0;
    auto make = [&] { return std::static_pointer_cast<void>(std::make_shared<int>(++made)); };
    const std::shared_ptr<void> a = objects.reusable("a", make, 2);
    EXPECT_EQ(objects.reusable("a", make, 2), a);
    const std::shared_ptr<void> b = objects.reusable("b", make, 2);
    EXPECT_NE(b, a);
    EXPECT_EQ(objects.reusable("a", make, 2), a);  // a is now the most recent, b the other kept
    objects.reusable("c", make, 2);                // b falls out
    EXPECT_EQ(made, 3);
    EXPECT_EQ(objects.reusable("a", make, 2), a);
    EXPECT_NE(objects.reusable("b", make, 2), b);  // made again
    EXPECT_EQ(made, 4);
    EXPECT_EQ(*std::static_pointer_cast<int>(b), 2);  // the holder's copy lives on
    // Keys are compared whole: a key that differs in its last byte is another object.
    std::string k1(1 << 20, 'x'), k2 = k1;
    k2.back() = 'y';
    EXPECT_NE(objects.reusable(k1, make, 4), objects.reusable(k2, make, 4));
}
