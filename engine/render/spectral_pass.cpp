#include "render/spectral_pass.h"

#include "core/timing.h"
#include "render/camera_matrices.h"
#include "render/spectral_packing.h"
#include "render/spectral_resources.h"
#include "render/target_readback.h"

#include <chrono>
#include <optional>

namespace metamer {

std::string SpectralPassPlan::describe() const {
    if (responses)
        return fmt::format("response pass: {} detector channel(s) in {} RGBA32F layer(s), {}, {}×{} target ({} MiB), "
                           "{} light(s), specular {}, fluorescence {}, ssaa {}",
                           bands, layers,
                           throughFilters.empty() ? "one pass that writes its own depth (no pre-pass)"
                                                  : "a depth pre-pass, the transparent objects' passes, then one pass "
                                                    "in two draws (every pixel without per-band sums, then the full "
                                                    "program where a pixel needs them)",
                           targetWidth, targetHeight, targetBytes >> 20, lightCount,
                           hasSpecular ? "on" : "off", hasFluorescence ? "on" : "off", ssaa) +
               (throughFilters.empty() ? "" : "; " + throughFilters) + (frame.empty() ? "" : "; the frame: " + frame);
    return fmt::format("{} bands in {} RGBA32F layers, a depth pre-pass + {} colour pass(es) of ≤{} attachments, {}×{} target ({} MiB), "
                       "{} light(s){}, specular {}, fluorescence {}, ssaa {}, readback by {}",
                       bands, layers, passes, MAX_OUTPUTS, targetWidth, targetHeight, targetBytes >> 20,
                       lightCount, shadowLayers ? fmt::format(" ({} shadow-map layer(s) of {}²)", shadowLayers, SHADOW_MAP_SIZE) : "",
                       hasSpecular ? "on" : "off",
                       !hasFluorescence ? "off" : fluorescenceSpectra ? "on (per-light spectra)" : "on (rank one)", ssaa,
                       mappedReadback ? "mapping a linear image" : "copy") +
           (frame.empty() ? "" : "; the frame: " + frame) + (interreflection.empty() ? "" : "; " + interreflection);
}

struct SpectralPass::Impl {
    vk::Context& ctx;
    const Scene& scene;
    Grid grid;
    PackedScene packed;
    LocalFrame frame;  // where positions are computed: fixed for the pass, the camera may move in it
    CameraMatrices camera;
    glm::mat4 fullViewProjection{1.0f};
    int rows = 0, columns = 0;
    int tileColumn = 0, tileRow = 0;  // the tile's top-left pixel
    std::unique_ptr<SpectralResources> resources;
    // The scene's interreflection, solved once for the pass (radiosity/scene_radiosity.h).
    std::optional<radiosity::SceneInterreflection> interreflection;
    // The full image's view-projection, scaled and shifted so that the tile fills the target.
    void placeTile() {
        // Columns [c0, c0 + C) of a W-column image span clip-space x in [−1 + 2·c0/W, −1 + 2·(c0 + C)/W],
        // rows likewise in y (y down); scale and shift those ranges onto [−1, 1].
        const double W = scene.camera.width, H = scene.camera.height, C = columns, R = rows;
        glm::mat4 tile(1.0f);
        tile[0][0] = float(W / C);
        tile[3][0] = float((W - 2.0 * tileColumn) / C - 1.0);
        tile[1][1] = float(H / R);
        tile[3][1] = float((H - 2.0 * tileRow) / R - 1.0);
        camera.viewProjection = tile * fullViewProjection;
    }

    Impl(vk::Context& c, const Scene& s) : ctx(c), scene(s) {}
};

SpectralPass::SpectralPass(vk::Context& ctx, const Scene& scene, const SceneOnGrid& spectra,
                           const SpectralPassOptions& options)
    : impl_(std::make_unique<Impl>(ctx, scene)) {
    auto t0 = Clock::now();
    if (options.ssaa < 1 || options.ssaa > 4)
        failInput(Where{"", "--ssaa"}, "supersampling must be 1, 2, 3 or 4 (samples per pixel side), got {}",
                  options.ssaa);
    SpectralPassPlan& p = plan_;
    p.responses = !options.responseWeights.empty();
    p.quantity = options.quantity;
    if (p.responses && p.quantity != SurfaceQuantity::Radiance)
        failRuntime("the response pass draws radiance only; the {} map is drawn in bands", surfaceQuantityName(p.quantity));
    if (p.responses && !options.sampled)
        failRuntime("the response pass's target is read by the tonemap pass only: set SpectralPassOptions::sampled");
    p.bands = p.responses ? int(options.responseWeights.size()) : spectra.grid.bands();
    p.layers = (p.bands + 3) / 4;
    p.passes = (p.layers + MAX_OUTPUTS - 1) / MAX_OUTPUTS;
    p.lightCount = int(scene.lights.size());
    p.hasSpecular = scene.hasSpecular();
    p.hasFluorescence = scene.hasFluorescence();
    p.ssaa = options.ssaa;
    if (options.stripRows < 0 || options.tileColumns < 0)
        failRuntime("strip rows and tile columns must be ≥ 0, got {} and {}", options.stripRows, options.tileColumns);
    int rows = options.stripRows > 0 ? std::min(options.stripRows, scene.camera.height) : scene.camera.height;
    int columns = options.tileColumns > 0 ? std::min(options.tileColumns, scene.camera.width) : scene.camera.width;
    p.targetWidth = uint32_t(columns * options.ssaa);
    p.targetHeight = uint32_t(rows * options.ssaa);
    p.targetBytes = size_t(p.targetWidth) * p.targetHeight * p.layers * 16;
    uint32_t maxDim = ctx.properties().limits.maxFramebufferWidth;
    if (p.targetWidth > maxDim || p.targetHeight > ctx.properties().limits.maxFramebufferHeight)
        failInput(Where{"", "camera"}, "render target {}×{} exceeds the device limit {}×{}", p.targetWidth,
                  p.targetHeight, maxDim, ctx.properties().limits.maxFramebufferHeight);

    Impl& m = *impl_;
    m.grid = spectra.grid;
    if (scene.lights.size() > MAX_LIGHTS)
        failInput(Where{scene.file.string(), "lights"}, "{} lights; the GPU path supports at most {}",
                  scene.lights.size(), MAX_LIGHTS);
    m.frame = localFrameFor(scene, scene.camera);
    // The reflectance map (render/ground_truth.h) is ρd alone: no light, so no indirect light to solve for.
    if (scene.interreflection && options.quantity != SurfaceQuantity::Reflectance) {
        // The response pass would sum the detector over materials and lights only: it cannot draw
        // the indirect light, which the band programs add (render/display_frame.cpp draws bands).
        if (p.responses)
            failRuntime("the response pass cannot show interreflection: render bands (render/display_frame.cpp does)");
        const auto ti = Clock::now();
        m.interreflection = radiosity::solveInterreflection(scene, spectra);
        timings_.interreflection_ms = msSince(ti);
        p.interreflection = m.interreflection->describe();
    }
    m.packed = p.responses ? packResponses(scene, spectra, options.responseWeights, m.frame,
                                           ctx.properties().limits.maxTexelBufferElements)
                           : pack(scene, spectra, p.passes, m.frame, m.interreflection ? &*m.interreflection : nullptr);
    p.fluorescenceSpectra = m.packed.fluorescenceSpectra;
    if (p.responses && scene.hasTransparency())
        p.throughFilters =
            m.packed.crossingHeader >= 0
                ? fmt::format("through transparent objects: single-crossing tables of {} node(s) on {} channel(s) ({:.1f} MiB), "
                              "per-band sums where a pixel crosses more (the second draw)",
                              m.packed.crossingNodes, m.packed.depthChannels,
                              double(m.packed.crossingTexels) * 16.0 / double(1 << 20))
                : "through transparent objects: per-band sums where a pixel crosses anything (the second draw; no "
                  "single-crossing tables: none fit, or none needed)";
    p.shadowLayers = int(m.packed.shadowMaps.layers.size());
    m.camera = cameraMatrices(scene.camera, scene, m.frame);
    m.fullViewProjection = m.camera.viewProjection;
    m.rows = rows;
    m.columns = columns;
    if (options.stripRows > 0 || options.tileColumns > 0) setTile(0, 0);
    m.resources = std::make_unique<SpectralResources>(ctx, scene, spectra, m.packed, plan_, options);
    plan_.frame = m.resources->describeFrame();
    timings_.upload_ms = msSince(t0);
    timings_.shadow_ms = m.resources->shadowMs;
}

SpectralPass::~SpectralPass() = default;

SpectralCube SpectralPass::render() {
    SpectralCube cube;
    render(cube);
    return cube;
}

void SpectralPass::render(SpectralCube& cube) {
    draw();
    readback(cube);
}

int SpectralPass::rows() const { return impl_->rows; }
int SpectralPass::columns() const { return impl_->columns; }

void SpectralPass::setTile(int firstColumn, int firstRow) {
    Impl& m = *impl_;
    m.tileColumn = firstColumn;
    m.tileRow = firstRow;
    m.placeTile();
}

void SpectralPass::setCamera(const Camera& camera) {
    Impl& m = *impl_;
    if (camera.width != m.scene.camera.width || camera.height != m.scene.camera.height)
        failRuntime("SpectralPass::setCamera: the image is {}×{}, the camera asks for {}×{}", m.scene.camera.width,
                    m.scene.camera.height, camera.width, camera.height);
    m.camera = cameraMatrices(camera, m.scene, m.frame);
    m.fullViewProjection = m.camera.viewProjection;
    if (m.rows != m.scene.camera.height || m.columns != m.scene.camera.width) m.placeTile();
}

void SpectralPass::draw(const std::function<void(int done, int passes)>& afterPass) {
    Impl& m = *impl_;
    auto t0 = Clock::now();
    if (!afterPass) {
        m.ctx.submitAndWait([&](VkCommandBuffer cmd) { recordSpectralFrame(cmd, *m.resources, m.camera); });
    } else {
        // One submission per pass that draws (with the clear or copy beside it): the derived
        // barriers order the passes across submissions as within one.
        const auto steps = m.resources->frame.drawingSteps();
        for (size_t i = 0; i < steps.size(); ++i) {
            m.ctx.submitAndWait(
                [&](VkCommandBuffer cmd) { recordSpectralFrame(cmd, *m.resources, m.camera, steps[i].first, steps[i].second); });
            timings_.shading_ms = msSince(t0);
            afterPass(int(i) + 1, int(steps.size()));
        }
    }
    timings_.shading_ms = msSince(t0);
}

int SpectralPass::framePasses() const { return int(impl_->resources->frame.drawingSteps().size()); }

VkImage SpectralPass::targetImage() const { return impl_->resources->color.handle(); }
VkImageView SpectralPass::targetArrayView() { return impl_->resources->color.layerView(~0u); }
const Frame& SpectralPass::frame() const { return impl_->resources->frame; }

vk::ResourceState SpectralPass::targetState() const {
    return impl_->resources->frame.stateAtEnd(impl_->resources->targetResource);
}

void SpectralPass::readback(SpectralCube& cube) {
    Impl& m = *impl_;
    if (plan_.responses) failRuntime("the response pass holds a detector's channels, not a cube to read back");
    auto t1 = Clock::now();
    if (cube.width != m.columns || cube.height != m.rows || !(cube.grid == m.grid) ||
        cube.data.size() != size_t(cube.width) * cube.height * cube.bands())
        cube = SpectralCube(m.columns, m.rows, m.grid);
    readLayered(m.resources->mapTarget(), plan_.ssaa, cube);
    timings_.readback_ms = msSince(t1);
}

}  // namespace metamer
