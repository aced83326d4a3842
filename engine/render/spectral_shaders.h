// The spectral frame's shaders as compiled into the binary (build/shaders/*.spv.h, glslang at
// build time): spectral.frag and transmit.frag once per colour-attachment count, opaque_distance.frag,
// spectral.vert and its vertex input, and the INDIRECT builds of both. One place that includes the SPIR-V arrays, so each is in the
// binary once. Used by render/spectral_pipelines.cpp and render/shadow_transmittance.cpp.
// Tests: through render/spectral_pass.h's (every GPU test).
#pragma once

#include "vk/pipeline.h"

#include <cstddef>
#include <cstdint>

namespace metamer {

struct SpirvCode {
    const uint32_t* code;
    size_t bytes;
};

SpirvCode spectralFragment(uint32_t attachments);  // spectral.frag with OUTPUT_COUNT attachments (1..8)
// spectral.frag with FILTERED_RESPONSES (the response pass through sheets, media and a slab; 1 or 2).
SpirvCode spectralFilteredResponsesFragment(uint32_t attachments);
// The same with RESPONSES_WITHOUT_BANDS: no per-band sums; one more attachment (R32F) takes the
// depth of the pixels that need them, 0 elsewhere, for the draw that sums them.
SpirvCode spectralResponsesWithoutBandsFragment(uint32_t attachments);
// The band programs that add interreflection's indirect light (built with INDIRECT; interface.h).
SpirvCode spectralIndirectFragment(uint32_t attachments);
SpirvCode spectralIndirectVertex();
SpirvCode transmitFragment(uint32_t attachments);  // transmit.frag likewise
SpirvCode opaqueDistanceFragment();
SpirvCode spectralVertex();

// spectral.vert's vertex input: one interleaved buffer of gpu::SpectralVertex; with `indirect`,
// a second of INDIRECT_RECORD_VEC4 vec4 per vertex (binding 1) for the INDIRECT programs.
void spectralVertexInput(vk::GraphicsPipelineDesc& d, bool indirect = false);

}  // namespace metamer
