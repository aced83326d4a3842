// The response pass seen through sheets, media and a slab (spectral.frag built with
// FILTERED_RESPONSES, its THROUGH_FILTERS programs only; docs/color.md, "The response pass"):
// which path each pixel and light takes, the per-band sums and the single-crossing tables. Included
// by spectral.frag after its coloured-shadow functions; a scene without transparent objects never
// compiles this (lavapipe compiles a program's dead code too before removing it: +60–80 ms of
// pipeline creation on an opaque scene when it was always in).

// Through filters: this pixel sees nothing transparent in front (viewClear), the light being
// shaded arrives unfiltered here (lightClear); or one sheet or medium channel only (viewSingle,
// lightSingle: channel viewC at depth viewX, lightC at lightX, 0 where clear), whose response is read
// from its single-crossing table (render/crossing_tables.h). The per-band loops then run no
// iterations — a loop bound, not a branch: lavapipe leaves a loop once no pixel of the block is in
// it, while it runs both sides of a branch. needViewTau: the camera's τ is summed per band (viewTau).
bool viewClear, lightClear, viewSingle, lightSingle, needViewTau;
int viewC, lightC;
float viewX, lightX;

// The end of a per-band loop: the detector's last band layer where `perBand`, else none. The
// RESPONSES_WITHOUT_BANDS build runs none — it notes the pixel (needsBands) for the draw that does:
// lavapipe pays for a loop's code at every pixel even where no pixel of the block runs it.
#ifdef RESPONSES_WITHOUT_BANDS
const bool SUMS_BANDS = false;
#else
const bool SUMS_BANDS = true;
#endif
bool needsBands = false;
int bandLayersEnd(bool perBand) {
    needsBands = needsBands || perBand;
    return SUMS_BANDS && perBand ? RESPONSE_END_LAYER : RESPONSE_FIRST_LAYER;
}

// The filtered light's path at this fragment (after visibility()): clear, one channel, or more;
// no channels where it arrives unfiltered (τ = 1), and a map layer that exists.
void classifyFilteredLight() {
    lightClear = true;
    lightSingle = false;
    lightC = 0;
    lightX = 0.0;
    if (filtered) {
        fetchDepthChannels();
        int crossed = 0;
        [[unroll]] for (int i = 0; i < DEPTH_ARRAY; ++i) {
            lightClear = lightClear && depthChannel[i] == 0.0;
            if (i < DEPTH_CHANNELS && depthChannel[i] != 0.0) {
                ++crossed;
                lightC = i;
                lightX = depthChannel[i];
            }
        }
        bool slabFree = true;
        [[unroll]] for (int i = DEPTH_CHANNELS; i < DEPTH_ARRAY; ++i) slabFree = slabFree && depthChannel[i] == 0.0;
        lightSingle = crossed == 1 && slabFree;
        if (!lightSingle) lightX = 0.0;
    } else {
        [[unroll]] for (int i = 0; i < DEPTH_ARRAY; ++i) depthChannel[i] = 0.0;
        shadowLayer = 0;
    }
}

// The response pass seen through sheets, media and a slab (THROUGH_FILTERS): light l's response with
// τ of what the camera sees through — and of what the light crosses, under a coloured shadow —
// taken band by band inside the sum, Σ_j τ_j·(g/π·d_lcj + lobe·s_lcj) over the grid's band layers j
// (interface.h, GpuResponseBlock::spectra). The band passes' own products, summed in another order.
vec4 viewTau[BAND_LAYERS];  // the camera's τ per band layer (main), for every light
// Light l's records of band layer j, weighted and summed against τ into every channel.
void respondLayer(int l, int j, float diffuseWeight, float specularWeight, vec4 tau) {
    const int C = 4 * OUTPUT_COUNT;
    const int diffuseRows = R.spectra.x + 2 * l * C * BAND_LAYERS, specularRows = diffuseRows + C * BAND_LAYERS;
    [[unroll]] for (int c = 0; c < C && c < RESPONSE_CHANNELS; ++c) {
        vec4 terms = diffuseWeight * texelFetch(depthSpectra, diffuseRows + c * BAND_LAYERS + j);
        if (HAS_SPECULAR) terms += specularWeight * texelFetch(depthSpectra, specularRows + c * BAND_LAYERS + j);
        acc[c / 4][c % 4] += dot(terms, tau);
    }
}
// Channel e's table axis (SPEC_CROSSING_HEADER): vec4(1/h, nodes − 1, first node, largest depth or −1).
vec4 crossingAxis(int e) { return CROSSING_HEADER >= 0 ? texelFetch(depthSpectra, CROSSING_HEADER + e) : vec4(0.0, 0.0, 0.0, -1.0); }
// Cubic Hermite on channel e's axis at depth x (render/crossing_tables.h): the first of the two
// nodes' rows (each F then h·F', OC vec4 apiece) and the four basis weights.
int crossingNode(vec4 axis, float x, out vec4 basis) {
    const float u = x * axis.x;
    const int i = min(int(u), int(axis.y) - 1);
    const float t = u - float(i), s = 1.0 - t;
    basis = vec4((1.0 + 2.0 * t) * s * s, t * s * s, t * t * (3.0 - 2.0 * t), t * t * (t - 1.0));
    return int(axis.z) + i;
}
vec4 crossingTableAt(int row, int k, vec4 basis) {
    const int OC = OUTPUT_COUNT;
    return basis.x * texelFetch(depthSpectra, row + k) + basis.y * texelFetch(depthSpectra, row + OC + k) +
           basis.z * texelFetch(depthSpectra, row + 2 * OC + k) + basis.w * texelFetch(depthSpectra, row + 3 * OC + k);
}
// Light l's response through channel e at depth x, from the material's table.
void respondFromTable(int l, int e, float x, float diffuseWeight, float specularWeight) {
    vec4 basis;
    const int node = crossingNode(crossingAxis(e), x, basis);
    const int diffuseRow = R.tables.x + ((2 * l) * CROSSING_NODES + node) * 2 * OUTPUT_COUNT;
    const int specularRow = R.tables.x + ((2 * l + 1) * CROSSING_NODES + node) * 2 * OUTPUT_COUNT;
    [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k) {
        acc[k] += diffuseWeight * crossingTableAt(diffuseRow, k, basis);
        if (HAS_SPECULAR) acc[k] += specularWeight * crossingTableAt(specularRow, k, basis);
    }
}
// Whether channel e's table holds depth x.
bool tabulated(int e, float x) { return x <= crossingAxis(e).w; }

// Where nothing filters light l's path here, its per-scene response (as in an opaque scene).
void respondUnfiltered(int l, float diffuseWeight, float specularWeight) {
    [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k) {
        const int r = l * RESPONSE_VEC4 + k;
        acc[k] += R.diffuse[r] * diffuseWeight;
        if (HAS_SPECULAR) acc[k] += R.specular[r] * specularWeight;
    }
}
// Unfiltered (ambient and hemisphere lights): τ of the camera's channels only.
void respondThroughView(int l, float diffuseWeight, float specularWeight) {
    const int layers = bandLayersEnd(needViewTau);
    for (int j = RESPONSE_FIRST_LAYER; j < layers; ++j) respondLayer(l, j, diffuseWeight, specularWeight, viewTau[j]);
    if (viewClear) respondUnfiltered(l, diffuseWeight, specularWeight);
    if (viewSingle) respondFromTable(l, viewC, viewX, diffuseWeight, specularWeight);
}
// The camera's τ of band layer j, where it was not summed per band: one channel's (or 1).
vec4 viewTauAt(int j) {
    return needViewTau ? viewTau[j] : exp2(viewX * texelFetch(depthSpectra, viewC * BAND_LAYERS + j));
}
// A directional or point light: × τ of its own channels at its transmittance-map texel (zero where
// it arrives unfiltered: τ = 1). One program for both cases, since lavapipe would run both sides of
// a branch between them.
void respondThroughViewAndLight(int l, float diffuseWeight, float specularWeight, bool directional) {
    const bool clear = viewClear && lightClear;
    // One channel crossed by both paths together (the same one, where both cross one): its table.
    const int e = lightSingle ? lightC : viewC;
    const float x = viewX + lightX;
    const bool single = !clear && (viewClear || viewSingle) && (lightClear || lightSingle) &&
                        (!viewSingle || !lightSingle || viewC == lightC) && tabulated(e, x);
    const int layers = bandLayersEnd(!clear && !single);
    for (int j = RESPONSE_FIRST_LAYER; j < layers; ++j)
        respondLayer(l, j, diffuseWeight, specularWeight, viewTauAt(j) * exp2(log2TransmittanceAt(j, directional)));
    if (clear) respondUnfiltered(l, diffuseWeight, specularWeight);
    if (single) respondFromTable(l, e, x, diffuseWeight, specularWeight);
}

// The camera's path at this pixel (view direction v): the channels in front of the surface, the
// slab where it lies in front, then clear, one channel, or τ per band (viewTau).
void classifyView(vec3 v) {
    fetchViewChannels(0);
    bool slabSeen = false;
    float slabCos = 1.0;
    if (VIEW_SLAB_CHANNEL >= 0) {
        // The crossings behind the slab and in front of it, together; the slab's own T where it
        // lies in front of this surface, at the angle of this pixel's ray with its plane.
        const ivec2 pixel = ivec2(gl_FragCoord.xy);
        [[unroll]] for (int j = 0; j < VIEW_LAYERS; ++j) {
            const vec4 front = texelFetch(viewChannels, ivec3(pixel, VIEW_LAYERS + j), 0);
            [[unroll]] for (int i = 0; i < 4; ++i) viewChannel[4 * j + i] += front[i];
        }
        slabSeen = texelFetch(slabDistance, pixel, 0).r < texelFetch(opaqueDistance, pixel, 0).r;
        slabCos = min(abs(dot(R.slabNormal.xyz, v)), 1.0);
    }
    int crossed = 0;
    viewC = 0;
    viewX = 0.0;
    [[unroll]] for (int i = 0; i < VIEW_CHANNELS; ++i)
        if (viewChannel[i] != 0.0) {
            ++crossed;
            viewC = i;
            viewX = viewChannel[i];
        }
    viewClear = !slabSeen && crossed == 0;
    viewSingle = !slabSeen && crossed == 1 && tabulated(viewC, viewX);
    needViewTau = !viewClear && !viewSingle;
    if (!viewSingle) viewX = 0.0;  // (viewTauAt: τ = 1 where the camera's τ is not one channel's)
    const int viewLayers = bandLayersEnd(needViewTau);
    const int slabLayers = bandLayersEnd(slabSeen);
    for (int j = RESPONSE_FIRST_LAYER; j < viewLayers; ++j) viewTau[j] = viewTransmittance(j);
    if (VIEW_SLAB_CHANNEL >= 0)
        for (int j = RESPONSE_FIRST_LAYER; j < slabLayers; ++j)
            viewTau[j] *= slabTransmittance(slabCos, texelFetch(depthSpectra, VIEW_SLAB_CHANNEL * BAND_LAYERS + j),
                                            texelFetch(depthSpectra, (VIEW_SLAB_CHANNEL + 1) * BAND_LAYERS + j));
}

// Through filters: Σ_j τ_j·(w_c·ê/λ)_j, the detector-weighted emission (GpuResponseBlock::spectra.z):
// its sum over the bands where nothing is in front, its table through one channel
// (GpuResponseBlock::tables), per band elsewhere.
void respondEmissionThroughView() {
    if (HAS_FLUORESCENCE && R.spectra.z >= 0) {
        const int C = 4 * OUTPUT_COUNT;
        const int layers = bandLayersEnd(needViewTau);
        for (int j = RESPONSE_FIRST_LAYER; j < layers; ++j)
            [[unroll]] for (int c = 0; c < C && c < RESPONSE_CHANNELS; ++c)
                acc[c / 4][c % 4] += fluorescence * dot(texelFetch(depthSpectra, R.spectra.z + c * BAND_LAYERS + j), viewTau[j]);
        if (viewClear)
            [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k) acc[k] += fluorescence * texelFetch(depthSpectra, R.tables.z + k);
        if (viewSingle) {
            vec4 basis;
            const int row = R.tables.y + crossingNode(crossingAxis(viewC), viewX, basis) * 2 * OUTPUT_COUNT;
            [[unroll]] for (int k = 0; k < OUTPUT_COUNT; ++k) acc[k] += fluorescence * crossingTableAt(row, k, basis);
        }
    }
}
