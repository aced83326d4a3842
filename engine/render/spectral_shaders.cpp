#include "render/spectral_shaders.h"

#include "core/error.h"
#include "interface.h"

#include "spectral.frag.1.spv.h"
#include "spectral.frag.2.spv.h"
#include "spectral.frag.3.spv.h"
#include "spectral.frag.4.spv.h"
#include "spectral.frag.5.spv.h"
#include "spectral.frag.6.spv.h"
#include "spectral.frag.7.spv.h"
#include "spectral.frag.8.spv.h"
#include "opaque_distance.frag.spv.h"
#include "transmit.frag.1.spv.h"
#include "transmit.frag.2.spv.h"
#include "transmit.frag.3.spv.h"
#include "transmit.frag.4.spv.h"
#include "transmit.frag.5.spv.h"
#include "transmit.frag.6.spv.h"
#include "transmit.frag.7.spv.h"
#include "transmit.frag.8.spv.h"
#include "spectral.vert.spv.h"
#include "spectral.frag.1.indirect.spv.h"
#include "spectral.frag.2.indirect.spv.h"
#include "spectral.frag.3.indirect.spv.h"
#include "spectral.frag.4.indirect.spv.h"
#include "spectral.frag.5.indirect.spv.h"
#include "spectral.frag.6.indirect.spv.h"
#include "spectral.frag.7.indirect.spv.h"
#include "spectral.frag.8.indirect.spv.h"
#include "spectral.vert.indirect.spv.h"
#include "spectral.frag.1.filtered_responses.spv.h"
#include "spectral.frag.2.filtered_responses.spv.h"
#include "spectral.frag.1.responses_without_bands.spv.h"
#include "spectral.frag.2.responses_without_bands.spv.h"

namespace metamer {

namespace {

// spectral.frag built for 1..8 colour attachments (index = count - 1).
const SpirvCode kSpectralFrag[MAX_OUTPUTS] = {
    {kSpirv_spectral_frag_1, sizeof(kSpirv_spectral_frag_1)}, {kSpirv_spectral_frag_2, sizeof(kSpirv_spectral_frag_2)},
    {kSpirv_spectral_frag_3, sizeof(kSpirv_spectral_frag_3)}, {kSpirv_spectral_frag_4, sizeof(kSpirv_spectral_frag_4)},
    {kSpirv_spectral_frag_5, sizeof(kSpirv_spectral_frag_5)}, {kSpirv_spectral_frag_6, sizeof(kSpirv_spectral_frag_6)},
    {kSpirv_spectral_frag_7, sizeof(kSpirv_spectral_frag_7)}, {kSpirv_spectral_frag_8, sizeof(kSpirv_spectral_frag_8)},
};
// spectral.frag's INDIRECT builds likewise.
const SpirvCode kSpectralIndirectFrag[MAX_OUTPUTS] = {
    {kSpirv_spectral_frag_1_indirect, sizeof(kSpirv_spectral_frag_1_indirect)},
    {kSpirv_spectral_frag_2_indirect, sizeof(kSpirv_spectral_frag_2_indirect)},
    {kSpirv_spectral_frag_3_indirect, sizeof(kSpirv_spectral_frag_3_indirect)},
    {kSpirv_spectral_frag_4_indirect, sizeof(kSpirv_spectral_frag_4_indirect)},
    {kSpirv_spectral_frag_5_indirect, sizeof(kSpirv_spectral_frag_5_indirect)},
    {kSpirv_spectral_frag_6_indirect, sizeof(kSpirv_spectral_frag_6_indirect)},
    {kSpirv_spectral_frag_7_indirect, sizeof(kSpirv_spectral_frag_7_indirect)},
    {kSpirv_spectral_frag_8_indirect, sizeof(kSpirv_spectral_frag_8_indirect)},
};
// spectral.frag's FILTERED_RESPONSES builds (the response pass through filters: 1 or 2 attachments,
// a detector's ≤ 8 channels).
const SpirvCode kSpectralFilteredResponsesFrag[2] = {
    {kSpirv_spectral_frag_1_filtered_responses, sizeof(kSpirv_spectral_frag_1_filtered_responses)},
    {kSpirv_spectral_frag_2_filtered_responses, sizeof(kSpirv_spectral_frag_2_filtered_responses)},
};
// Its RESPONSES_WITHOUT_BANDS builds (the first of the response pass's two draws through filters).
const SpirvCode kSpectralResponsesWithoutBandsFrag[2] = {
    {kSpirv_spectral_frag_1_responses_without_bands, sizeof(kSpirv_spectral_frag_1_responses_without_bands)},
    {kSpirv_spectral_frag_2_responses_without_bands, sizeof(kSpirv_spectral_frag_2_responses_without_bands)},
};
// transmit.frag likewise.
const SpirvCode kTransmitFrag[MAX_OUTPUTS] = {
    {kSpirv_transmit_frag_1, sizeof(kSpirv_transmit_frag_1)}, {kSpirv_transmit_frag_2, sizeof(kSpirv_transmit_frag_2)},
    {kSpirv_transmit_frag_3, sizeof(kSpirv_transmit_frag_3)}, {kSpirv_transmit_frag_4, sizeof(kSpirv_transmit_frag_4)},
    {kSpirv_transmit_frag_5, sizeof(kSpirv_transmit_frag_5)}, {kSpirv_transmit_frag_6, sizeof(kSpirv_transmit_frag_6)},
    {kSpirv_transmit_frag_7, sizeof(kSpirv_transmit_frag_7)}, {kSpirv_transmit_frag_8, sizeof(kSpirv_transmit_frag_8)},
};

uint32_t variantIndex(uint32_t attachments) {
    if (attachments < 1 || attachments > MAX_OUTPUTS)
        failRuntime("no fragment shader variant for {} colour attachments (1 … {})", attachments, MAX_OUTPUTS);
    return attachments - 1;
}

// The response pass's builds exist for its 1 or 2 attachments only.
SpirvCode responsePassBuild(const SpirvCode (&builds)[2], uint32_t attachments, const char* what) {
    if (attachments < 1 || attachments > 2)
        failRuntime("no {} fragment shader for {} colour attachments (1 or 2)", what, attachments);
    return builds[attachments - 1];
}

}  // namespace

SpirvCode spectralFragment(uint32_t attachments) { return kSpectralFrag[variantIndex(attachments)]; }
SpirvCode spectralFilteredResponsesFragment(uint32_t attachments) {
    return responsePassBuild(kSpectralFilteredResponsesFrag, attachments, "response-pass-through-filters");
}
SpirvCode spectralResponsesWithoutBandsFragment(uint32_t attachments) {
    return responsePassBuild(kSpectralResponsesWithoutBandsFrag, attachments, "response-pass-without-bands");
}
SpirvCode transmitFragment(uint32_t attachments) { return kTransmitFrag[variantIndex(attachments)]; }
SpirvCode opaqueDistanceFragment() { return {kSpirv_opaque_distance_frag, sizeof(kSpirv_opaque_distance_frag)}; }
SpirvCode spectralVertex() { return {kSpirv_spectral_vert, sizeof(kSpirv_spectral_vert)}; }
SpirvCode spectralIndirectFragment(uint32_t attachments) { return kSpectralIndirectFrag[variantIndex(attachments)]; }
SpirvCode spectralIndirectVertex() { return {kSpirv_spectral_vert_indirect, sizeof(kSpirv_spectral_vert_indirect)}; }

// spectral.vert's vertex input: one interleaved buffer of gpu::SpectralVertex.
void spectralVertexInput(vk::GraphicsPipelineDesc& d, bool indirect) {
    using V = gpu::SpectralVertex;
    d.bindings = {{0, sizeof(V), VK_VERTEX_INPUT_RATE_VERTEX}};
    d.attributes = {{VERTEX_POSITION, 0, VK_FORMAT_R32G32B32_SFLOAT, uint32_t(offsetof(V, position))},
                    {VERTEX_NORMAL, 0, VK_FORMAT_R32G32B32_SFLOAT, uint32_t(offsetof(V, normal))},
                    {VERTEX_UV, 0, VK_FORMAT_R32G32_SFLOAT, uint32_t(offsetof(V, uv))},
                    {VERTEX_TANGENT, 0, VK_FORMAT_R32G32B32A32_SFLOAT, uint32_t(offsetof(V, tangent))}};
    if (!indirect) return;
    d.bindings.push_back({1, INDIRECT_RECORD_VEC4 * 16, VK_VERTEX_INPUT_RATE_VERTEX});
    for (uint32_t k = 0; k < INDIRECT_RECORD_VEC4; ++k)
        d.attributes.push_back({VERTEX_INDIRECT + k, 1, VK_FORMAT_R32G32B32A32_SFLOAT, 16 * k});
}

}  // namespace metamer
