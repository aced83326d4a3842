// The files one render writes, and the one table of what each says about itself. Every way of
// making pixels hands them here: the whole-frame GPU render and the CPU reference as one strip of
// the whole image, the strip renderer (render/strip_render) strip by strip, the preview's Save as
// one strip. Every file is written under a temporary name and renamed into place at commit()
// (io/atomic_file), so an interrupted or failed render leaves no half-written file.
// Tests: tests/cli_test.cpp, tests/strips_test.cpp, tests/interrupted_run_test.cpp.
#pragma once

#include "color/quick_look.h"
#include "color/tonemap.h"
#include "render/tonemap_pass.h"
#include "render/cube_formats.h"
#include "render/render_job_spec.h"
#include "io/image_file.h"
#include "io/spectral_exr.h"
#include "reference/geometry_maps.h"
#include "scene/surface_quantity.h"
#include "represent/representation.h"
#include "spectral/cube.h"
#include "spectral/library.h"

#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace metamer {

// What a render writes (`--write`, or the scene's output.write).
struct OutputFiles {
    bool cube = true;        // <scene>.exr: the spectral radiance cube
    bool png = true;         // <scene>.png: the display image (counts)
    bool xyz = false;        // <scene>.xyz.exr: XYZ as the detector sees it
    bool responses = false;  // <scene>.<detector>.exr: raw detector responses
    bool edges = false;      // <scene>.edges.png: 255 where a pixel's 3×3 neighbourhood sees more
                             // than one surface, 128 where it sees a shadow boundary (CPU backend
                             // only: the goldens' comparison mask)
    // The ground truth (docs/io.md, "Ground truth"), each with <scene>.mask.png beside it:
    bool reflectance = false;   // <scene>.reflectance.<cube>: ρd of the surface seen, per band
    bool illumination = false;  // <scene>.illumination.<cube>: irradiance/π there, W·sr⁻¹·m⁻²·nm⁻¹
    bool ids = false;           // <scene>.ids.exr (object, material) and its legend <scene>.ids.json
    bool depth = false;         // <scene>.depth.exr: metres along the ray
    bool normal = false;        // <scene>.normal.exr: the shading normal in the camera frame
    bool groundTruth() const { return reflectance || illumination || ids || depth || normal; }
};

struct WrittenFile {
    std::filesystem::path path;
    std::string what;  // one line: the quantity and its units
};


// Where each output goes; an empty path is not written.
struct CubeTarget {
    ChosenCubeFormat format;
    std::filesystem::path path;
};
struct OutputTargets {
    std::filesystem::path cube;       // the mode's channel image (reduced modes), or a spectral EXR
    std::vector<CubeTarget> cubes;    // spectral modes: the cube in each chosen container (render/cube_formats.h)
    std::filesystem::path png;        // the display image, or a custom detector's quick look
    std::filesystem::path xyz, responses, edges;
    std::vector<CubeTarget> reflectance, illumination;  // the spectral ground truth, in the cube's containers
    std::filesystem::path ids, legend, depth, normal, mask;
};

// The ground truth of a render, whole images (render/ground_truth.h makes them): the spectral
// maps pixel-interleaved on the render's grid (null: not made), the geometry maps, the ids' legend.
struct GroundTruthImages {
    const float* reflectance = nullptr;
    const float* illumination = nullptr;
    const GeometryMaps* geometry = nullptr;
    std::string legend;  // JSON: the names behind the ids
};

// `metamer render`'s names in `dir` for a scene file's `stem`: <stem>.exr (<stem>.<mode>.exr for a
// reduced mode's channel image), .png, .xyz.exr, .<detector>.exr, .edges.png. `plan` may be null
// (no display outputs); a custom detector (no colorimetric path) gets no XYZ file.
OutputTargets renderTargets(const std::filesystem::path& dir, const std::string& stem, const OutputFiles& files,
                            const Representation& representation, const TonemapPlan* plan,
                            const std::vector<ChosenCubeFormat>& formats = defaultCubeFormats());

// The one rule for the stem a render's files are named by (the scene file's stem, Python's
// `name`): not empty, no leading '.' (a hidden file, or "..": another folder), no '/' (another
// folder), no NUL or control character, at most kMaxOutputStemBytes (the file system's 255 less
// the longest suffix and the temporary name's). Otherwise an input error at `where`.
constexpr size_t kMaxOutputStemBytes = 200;
void requireOutputStem(const std::string& stem, const Where& where);

// What every file of a render carries: the scene, the backend, the grid and its resampling rule,
// the mode.
Attributes renderProvenance(const std::string& scene, const std::string& backend, const Grid& grid,
                            const Representation& representation);

// "camera:nikon_d5100" → "camera-nikon_d5100", "csv:/x/y.csv" → "csv-y": a detector in a file name.
std::string detectorFileName(const std::string& name);

// A render's outputs kept in memory instead of (or before) files, for a caller that wants arrays
// (the Python module, engine/python): RenderOutputs fills what `keep` names, row by row, as it
// would write the files. Pixel-interleaved, row 0 at the top; empty where not kept or not made
// (no display path for a custom detector, no XYZ without a colorimetric one, no edges on the GPU).
struct CapturedOutputs {
    OutputFiles keep{false, false, false, false, false};
    int width = 0, height = 0;
    std::vector<float> cube;  // the mode's channels (bands for spectral modes) per pixel
    size_t cubeChannels = 0;
    std::vector<uint16_t> counts;  // the display image, 3 per pixel
    std::vector<float> xyz;        // 3 per pixel, in the plan's xyzUnits
    std::vector<float> responses;  // responseChannels per pixel, the detector's units
    size_t responseChannels = 0;
    std::vector<uint16_t> edges;   // 0, 128 (shadow boundary) or 255 (surface edge) per pixel
    // The ground truth (OutputFiles::reflectance … normal; the mask with any of them).
    std::vector<float> reflectance, illumination;  // the render grid's bands per pixel
    size_t truthBands = 0;
    // The ids, depth and normal kept (each empty unless `keep` names it) and the mask (with any map).
    GeometryMaps geometry;
    std::string legend;  // the ids' legend, JSON
};

struct OutputOptions {
    bool half = false;                  // the cube in float16 (OpenEXR only)
    std::string compression = "piz";    // the cube's OpenEXR compression
    std::vector<ChosenCubeFormat> formats = defaultCubeFormats();  // the containers (with renderTargets)
};

class RenderOutputs {
public:
    // Opens every target (temporary files). `plan` null: no display outputs. The cube holds
    // `representation`'s channels on its render grid; a spectral cube's bands are on `grid`.
    RenderOutputs(const OutputTargets& targets, int width, int height, const Grid& grid,
                  const Representation& representation, const TonemapPlan* plan, const Attributes& provenance,
                  const OutputOptions& options = {});
    ~RenderOutputs();
    RenderOutputs(const RenderOutputs&) = delete;
    RenderOutputs& operator=(const RenderOutputs&) = delete;

    // Whether the outputs need the cube's pixels, and the display image's; which parts of the
    // display image (the counts also for the clipped-pixel figure when XYZ is written); whether a
    // custom detector's quick look is to be written (from the cube, or from CIE 1931 XYZ).
    bool needsCube() const;
    bool needsQuickLook() const { return quickLook_; }
    bool needsDisplay() const;
    TonemapOutputs displayOutputs() const;

    // Rows [firstRow, firstRow + rows), in order: `cube` (pixel-interleaved, the mode's channels,
    // linear:K already projected) and `image` (the display path's, `rows` rows or more; extra rows
    // are ignored) may be null when not needed.
    void writeRows(int firstRow, int rows, const float* cube, const DisplayImage* image);
    // Whole-image outputs: a custom detector's quick-look PNG (at the png target) and the edge mask.
    void writeQuickLook(const SpectralCube& cube, const SpectrumLibrary& library);
    // The same from the image's radiometric CIE 1931 XYZ, width × height × 3 (the response pass's
    // responses for the cie1931 detector, riemann).
    void writeQuickLookFromXyz(const std::vector<float>& xyz);
    void writeEdges(const std::vector<uint16_t>& edges);
    // The ground-truth files the targets name, from whole images.
    void writeGroundTruth(const GroundTruthImages& truth);
    // Whether any ground-truth file is to be written (the render must then make the maps).
    bool needsGroundTruth() const { return !truthCubes_.empty() || ids_ || depth_ || normal_; }

    // Keeps what `capture->keep` names in `capture` as well as (or instead of) the files; call
    // before the first writeRows. `capture` must outlive this.
    void captureInto(CapturedOutputs* capture);

    // Renames every file into place, with what `beforeCommit` stages (render_job_spec.h), and
    // says what each of the render's holds. `strips` > 1 says so in the lines.
    std::vector<WrittenFile> commit(int strips = 1, int stripRows = 0, const BeforeCommitHook& beforeCommit = {});
    size_t clampedToHalf() const { return clampedToHalf_; }

private:
    void writeQuickLookImage(const QuickLook& q);
    void openGroundTruth();
    // The preview's rows: the display image's counts as the display's linear RGB, and A = 1.
    const float* previewOf(int rows, const DisplayImage* image);

    OutputTargets targets_;
    int width_, height_;
    Grid grid_;
    const Representation& representation_;
    const TonemapPlan* plan_;
    Attributes provenance_;
    OutputOptions options_;
    struct OpenCube {
        CubeTarget target;
        CubeWriteSettings settings;
        std::unique_ptr<CubeWriter> writer;
    };
    std::vector<OpenCube> cubes_;  // the spectral cube, one writer per container
    struct TruthCube {
        SurfaceQuantity quantity;
        OpenCube cube;
    };
    std::vector<TruthCube> truthCubes_;  // the reflectance and illumination maps, one writer per container
    std::unique_ptr<ImageFileWriter> ids_, depth_, normal_, mask_;
    std::unique_ptr<AtomicOutput> legend_;
    std::string maskWhat_;
    bool preview_ = false;         // the cube's EXR carries the display image's linear RGB (docs/io.md, "Preview channels")
    std::vector<float> previewRows_;  // R, G, B, A per pixel of the rows being written
    std::unique_ptr<ImageFileWriter> channels_, png_, xyz_, responses_, edges_;
    CapturedOutputs* capture_ = nullptr;
    bool quickLook_ = false;
    std::string quickLookWhat_, edgesWhat_;
    size_t clampedToHalf_ = 0;
};

}  // namespace metamer
