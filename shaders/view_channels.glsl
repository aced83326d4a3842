// The camera's optical-depth channels at this pixel (BINDING_VIEW_CHANNELS, written by the channel
// pass; interface.h, "Optical-depth channels") as a transmittance per band, τ = 2^(Σ c·k): for the
// band passes (spectral.frag: the sheets and media in front of the surface, or behind the nearest
// slab) and the nearest slab's front draw (transmit.frag: those in front of it). Included after
// the including shader has declared VIEW_CHANNELS, BAND_LAYERS, viewChannels and depthSpectra.
const int VIEW_LAYERS = (VIEW_CHANNELS + 3) / 4;
const int VIEW_ARRAY = VIEW_LAYERS > 0 ? 4 * VIEW_LAYERS : 4;  // no array of 0 elements where there are none
float viewChannel[VIEW_ARRAY];

// The channels of set `set` at this pixel: 0 behind the nearest slab (or all, without slabs), 1 in
// front of it.
void fetchViewChannels(int set) {
    [[unroll]] for (int j = 0; j < VIEW_LAYERS; ++j) {
        const vec4 v = texelFetch(viewChannels, ivec3(ivec2(gl_FragCoord.xy), set * VIEW_LAYERS + j), 0);
        [[unroll]] for (int i = 0; i < 4; ++i) viewChannel[4 * j + i] = v[i];
    }
}

// τ of band layer `layer` of the grid (4 bands) from the fetched channels.
vec4 viewTransmittance(int layer) {
    vec4 depth = vec4(0.0);
    [[unroll]] for (int j = 0; j < VIEW_CHANNELS; ++j) depth += viewChannel[j] * texelFetch(depthSpectra, j * BAND_LAYERS + layer);
    return exp2(depth);
}
