#include "render/outputs.h"

#include "color/display_rgb.h"
#include "color/quick_look.h"
#include "io/atomic_file.h"
#include "render/display_colour_space.h"

#include <fmt/ranges.h>

#include <algorithm>

namespace metamer {

namespace {

bool responsesOnly(const TonemapPlan* plan) { return plan && plan->mode == TonemapMode::ResponsesOnly; }

// The first `rows` rows of a display image's per-pixel vector.
template <typename T>
std::vector<T> firstRows(const std::vector<T>& v, size_t pixels, size_t perPixel) {
    return std::vector<T>(v.begin(), v.begin() + std::ptrdiff_t(pixels * perPixel));
}

}  // namespace

std::string detectorFileName(const std::string& name) {
    std::string s = name.rfind("csv:", 0) == 0 ? "csv-" + std::filesystem::path(name.substr(4)).stem().string() : name;
    std::replace(s.begin(), s.end(), ':', '-');
    return s;
}

OutputTargets renderTargets(const std::filesystem::path& dir, const std::string& stem, const OutputFiles& files,
                            const Representation& representation, const TonemapPlan* plan,
                            const std::vector<ChosenCubeFormat>& formats) {
    OutputTargets t;
    std::string tag = representation.mode.name();
    std::replace(tag.begin(), tag.end(), ':', '-');
    const bool spectral = representation.mode.spectral();
    if (files.cube && !spectral) t.cube = dir / (stem + "." + tag + ".exr");
    if (files.cube && spectral)
        for (const ChosenCubeFormat& f : formats) t.cubes.push_back({f, dir / (stem + f.format->extension)});
    if (files.png && plan) t.png = dir / (stem + ".png");
    if (files.xyz && plan && !responsesOnly(plan)) t.xyz = dir / (stem + ".xyz.exr");
    if (files.responses && plan) t.responses = dir / (stem + "." + detectorFileName(plan->detector.name) + ".exr");
    if (files.edges) t.edges = dir / (stem + ".edges.png");
    return t;
}

void requireOutputStem(const std::string& stem, const Where& where) {
    const char* why = nullptr;
    if (stem.empty()) why = "is empty";
    else if (stem.front() == '.') why = "starts with '.' (a hidden file, or a path out of the folder)";
    else if (stem.find('/') != std::string::npos) why = "holds a '/' (a path into another folder)";
    else if (std::any_of(stem.begin(), stem.end(), [](char c) { return (unsigned char)c < 0x20 || c == 0x7f; }))
        why = "holds a NUL or control character";
    else if (stem.size() > kMaxOutputStemBytes) why = "is too long";
    if (!why) return;
    failInput(where, "'{}' {}: the output files are named by it; expected a file name without its extension: "
              "not empty, no leading '.', no '/', NUL or control characters, at most {} bytes",
              stem, why, kMaxOutputStemBytes);
}

Attributes renderProvenance(const std::string& scene, const std::string& backend, const Grid& grid,
                            const Representation& representation) {
    return {{"metamer:scene", scene},
            {"metamer:backend", backend},
            {"metamer:grid", grid.str()},
            {"metamer:resampling", resamplingName(grid.resampling)},
            {"metamer:mode", representation.mode.name()}};
}

RenderOutputs::RenderOutputs(const OutputTargets& targets, int width, int height, const Grid& grid,
                             const Representation& representation, const TonemapPlan* plan,
                             const Attributes& provenance, const OutputOptions& options)
    : targets_(targets),
      width_(width),
      height_(height),
      grid_(grid),
      representation_(representation),
      plan_(plan),
      provenance_(provenance),
      options_(options) {
    // The table of what each file says about itself, beyond the provenance every file carries.
    // A spectral EXR named directly (the preview's Save) is one more container.
    if (!targets_.cube.empty() && representation_.mode.spectral())
        targets_.cubes.insert(targets_.cubes.begin(), CubeTarget{defaultCubeFormats().front(), targets_.cube});
    else if (!targets_.cube.empty()) {
        ImageFile f{width_, height_, representation_.channelNames, provenance_};
        f.attributes.push_back({"metamer:representation", representation_.description});
        channels_ = std::make_unique<ImageFileWriter>(targets_.cube, f, 32);
    }
    // The display image's linear RGB beside the bands, where the render writes a display image (a
    // colorimetric display path): its counts make the preview, so every way of writing a render
    // (whole, in strips, the preview's Save, Python's save) gives the same preview.
    preview_ = plan_ && !responsesOnly(plan_) && !targets_.png.empty();
    std::optional<ExrChromaticities> previewPrimaries;
    if (preview_) {
        const DisplayPrimaries p = displayPrimaries(plan_->display);
        auto xy = [](const glm::dvec2& v) { return std::array<double, 2>{v.x, v.y}; };
        previewPrimaries = ExrChromaticities{xy(p.red), xy(p.green), xy(p.blue), xy(p.white)};
    }
    for (const CubeTarget& t : targets_.cubes) {
        CubeWriteSettings settings{t.format.options, provenance_, options_.half, options_.compression, previewPrimaries};
        std::unique_ptr<CubeWriter> writer = t.format.format->open(t.path, width_, height_, grid_, settings);
        cubes_.push_back({t, std::move(settings), std::move(writer)});
    }
    if (!targets_.png.empty() && plan_) {
        if (responsesOnly(plan_)) {
            if (!representation_.mode.spectral())
                failInput(Where{"", "--detector"}, "a custom detector needs spectra; the {} mode has none",
                          representation_.mode.name());
            quickLook_ = true;  // written whole by writeQuickLook
        } else {
            ImageFile f{width_, height_, {"R", "G", "B"}, provenance_};
            f.attributes.push_back({"ImageDescription", "metamer display image: " + plan_->description});
            tagDisplayColourSpace(f, plan_->display);
            png_ = std::make_unique<ImageFileWriter>(targets_.png, f, plan_->display.bits);
        }
    }
    if (!targets_.xyz.empty() && plan_ && !responsesOnly(plan_)) {
        // OpenEXR's convention for XYZ: X, Y, Z in R, G, B, with the chromaticities that say so.
        ImageFile f{width_, height_, {"R", "G", "B"}, provenance_};
        f.chromaticities = xyzChromaticities();
        f.attributes.push_back({"metamer:channels", "R, G, B hold CIE X, Y, Z (chromaticities: OpenEXR's XYZ convention)"});
        f.attributes.push_back({"metamer:xyz", plan_->xyzUnits});
        f.attributes.push_back({"metamer:integration", integrationName(plan_->detector.integration)});
        f.attributes.push_back({"metamer:display", plan_->description});
        xyz_ = std::make_unique<ImageFileWriter>(targets_.xyz, f, 32);
    }
    if (!targets_.responses.empty() && plan_) {
        ImageFile f{width_, height_, plan_->detector.channels, provenance_};
        f.attributes.push_back({"metamer:detector", plan_->detector.name});
        f.attributes.push_back({"metamer:units", plan_->detector.units});
        f.attributes.push_back({"metamer:integration", integrationName(plan_->detector.integration)});
        responses_ = std::make_unique<ImageFileWriter>(targets_.responses, f, 32);
    }
    if (!targets_.edges.empty()) {
        ImageFile f{width_, height_, {"Y"}, provenance_};
        edges_ = std::make_unique<ImageFileWriter>(targets_.edges, f, 8);
    }
}

RenderOutputs::~RenderOutputs() = default;

void RenderOutputs::captureInto(CapturedOutputs* capture) {
    capture_ = capture;
    CapturedOutputs& c = *capture_;
    c.width = width_;
    c.height = height_;
    const size_t pixels = size_t(width_) * size_t(height_);
    // Only what this render can make: display outputs need a plan, counts and XYZ a colorimetric one.
    const bool colorimetric = plan_ && !responsesOnly(plan_);
    c.keep.png = c.keep.png && colorimetric;
    c.keep.xyz = c.keep.xyz && colorimetric;
    c.keep.responses = c.keep.responses && plan_;
    if (c.keep.cube) {
        c.cubeChannels = size_t(representation_.channels());
        c.cube.assign(pixels * c.cubeChannels, 0.0f);
    }
    if (c.keep.png) c.counts.assign(pixels * 3, 0);
    if (c.keep.xyz) c.xyz.assign(pixels * 3, 0.0f);
    if (c.keep.responses) {
        c.responseChannels = plan_->detector.channels.size();
        c.responses.assign(pixels * c.responseChannels, 0.0f);
    }
}

bool RenderOutputs::needsCube() const {
    return !cubes_.empty() || channels_ || (capture_ && capture_->keep.cube);
}
bool RenderOutputs::needsDisplay() const {
    return png_ || xyz_ || responses_ || (capture_ && (capture_->keep.png || capture_->keep.xyz || capture_->keep.responses));
}
TonemapOutputs RenderOutputs::displayOutputs() const {
    const bool counts = png_ || (capture_ && capture_->keep.png), xyz = xyz_ || (capture_ && capture_->keep.xyz),
               responses = responses_ || (capture_ && capture_->keep.responses);
    return {counts || xyz, xyz, responses};
}

void RenderOutputs::writeRows(int firstRow, int rows, const float* cube, const DisplayImage* image) {
    const size_t pixels = size_t(width_) * size_t(rows);
    if (capture_) {
        // Rows [firstRow, firstRow + rows) of each kept array, from the same pixels as the files.
        CapturedOutputs& c = *capture_;
        const size_t first = size_t(firstRow) * size_t(width_);
        auto keep = [&](auto& into, const auto* from, size_t perPixel) {
            if (!into.empty() && from) std::copy(from, from + pixels * perPixel, into.begin() + std::ptrdiff_t(first * perPixel));
        };
        keep(c.cube, cube, c.cubeChannels);
        if (image) {
            keep(c.counts, image->counts.empty() ? nullptr : image->counts.data(), 3);
            keep(c.xyz, image->xyz.empty() ? nullptr : image->xyz.data(), 3);
            keep(c.responses, image->responses.empty() ? nullptr : image->responses.data(), c.responseChannels);
        }
    }
    if (cube) {
        const float* preview = preview_ && !cubes_.empty() ? previewOf(rows, image) : nullptr;
        for (OpenCube& c : cubes_) c.writer->writeRows(firstRow, rows, cube, preview);
        if (channels_) {
            const size_t channels = size_t(representation_.channels());
            channels_->writeRows(firstRow, rows, std::vector<float>(cube, cube + pixels * channels));
        }
    }
    if (image) {
        if (png_) png_->writeRows(firstRow, rows, firstRows(image->counts, pixels, 3));
        if (xyz_) xyz_->writeRows(firstRow, rows, firstRows(image->xyz, pixels, 3));
        if (responses_) responses_->writeRows(firstRow, rows, firstRows(image->responses, pixels, size_t(image->channels)));
    }
}

const float* RenderOutputs::previewOf(int rows, const DisplayImage* image) {
    const size_t pixels = size_t(width_) * size_t(rows);
    if (!image || image->counts.size() < pixels * 3)
        failRuntime("cannot write '{}': the display image's rows {} are missing for its preview channels",
                    targets_.cubes.front().path.string(), rows);
    previewRows_.resize(pixels * 4);
    for (size_t i = 0; i < pixels; ++i) {
        const glm::dvec3 rgb =
            linearRgbOfCounts(plan_->display, {image->counts[3 * i], image->counts[3 * i + 1], image->counts[3 * i + 2]});
        for (int c = 0; c < 3; ++c) previewRows_[4 * i + size_t(c)] = float(rgb[c]);
        previewRows_[4 * i + 3] = 1.0f;
    }
    return previewRows_.data();
}

void RenderOutputs::writeQuickLook(const SpectralCube& cube, const SpectrumLibrary& library) {
    if (!quickLook_) return;
    writeQuickLookImage(quickLook(cube, library));
}

void RenderOutputs::writeQuickLookFromXyz(const std::vector<float>& xyz) {
    if (!quickLook_) return;
    std::vector<glm::dvec3> v(xyz.size() / 3);
    for (size_t i = 0; i < v.size(); ++i) v[i] = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
    writeQuickLookImage(quickLookFromXyz(width_, height_, v, grid_));
}

void RenderOutputs::writeQuickLookImage(const QuickLook& q) {
    ImageFile f{width_, height_, {"R", "G", "B"}, {{"ImageDescription", q.description}, {"oiio:ColorSpace", "sRGB"}}};
    png_ = std::make_unique<ImageFileWriter>(targets_.png, f, 8);
    png_->writeRows(0, height_, q.counts);
    quickLookWhat_ = fmt::format("quick look, CIE 1931 → sRGB with auto exposure: detector {} has no display path",
                                 plan_->detector.name);
}

void RenderOutputs::writeEdges(const std::vector<uint16_t>& edges) {
    if (capture_ && capture_->keep.edges) capture_->edges = edges;
    if (!edges_) return;
    edges_->writeRows(0, height_, edges);
    const size_t n = size_t(std::count(edges.begin(), edges.end(), uint16_t(255)));
    const size_t shadow = size_t(std::count(edges.begin(), edges.end(), uint16_t(128)));
    edgesWhat_ = fmt::format("edge mask: {} of {} pixels see more than one surface in their 3×3 neighbourhood (255), "
                             "{} more a shadow boundary (128)",
                             n, edges.size(), shadow);
}

std::vector<WrittenFile> RenderOutputs::commit(int strips, int stripRows, const BeforeCommitHook& beforeCommit) {
    // Every file completed first, then all renamed together: the run replaces its previous set
    // of files or, when anything fails, leaves it as it was (io/atomic_file.h, commitTogether).
    std::vector<WrittenFile> written;
    std::vector<AtomicOutput*> files;
    auto add = [&](std::vector<AtomicOutput*> f) { files.insert(files.end(), f.begin(), f.end()); };
    const std::string inStrips = strips > 1 ? fmt::format("written in {} strips of {} rows", strips, stripRows) : "";
    auto line = [&](const std::string& what) { return inStrips.empty() ? what : inStrips; };
    const std::string cubeWhat = fmt::format("{}×{} px, {} bands {} nm, W·sr⁻¹·m⁻²·nm⁻¹, float32", width_, height_,
                                             grid_.bands(), grid_.str());
    for (OpenCube& c : cubes_) {
        add(c.writer->finish());
        if (c.target.format.format->describe) {
            written.push_back({c.target.path, line(c.target.format.format->describe(c.target.path, c.settings, cubeWhat))});
            continue;
        }
        clampedToHalf_ = c.writer->clampedValues();  // the spectral EXR: float16 or float32
        written.push_back({c.target.path, line(fmt::format("{}×{} px, {} bands {} nm, W·sr⁻¹·m⁻²·nm⁻¹, {}", width_,
                                                           height_, grid_.bands(), grid_.str(),
                                                           options_.half ? "float16" : "float32"))});
    }
    if (channels_) {
        add(channels_->finish());
        written.push_back({targets_.cube, line(fmt::format("{} channel radiance ({}), not a spectrum",
                                                           representation_.mode.name(),
                                                           fmt::join(representation_.channelNames, ", ")))});
    }
    if (png_) {
        add(png_->finish());
        written.push_back({targets_.png, line(quickLook_ ? quickLookWhat_ : "display counts: " + plan_->description)});
    }
    if (xyz_) {
        add(xyz_->finish());
        written.push_back({targets_.xyz, line("XYZ, " + plan_->xyzUnits)});
    }
    if (responses_) {
        add(responses_->finish());
        written.push_back({targets_.responses, line(fmt::format("{} responses ({}), {}", plan_->detector.name,
                                                                fmt::join(plan_->detector.channels, ", "),
                                                                plan_->detector.units))});
    }
    if (edges_) {
        add(edges_->finish());
        written.push_back({targets_.edges, line(edgesWhat_)});
    }
    std::vector<StagingFolder*> staged;
    if (beforeCommit) staged = beforeCommit(files);
    commitTogether(files, staged);
    return written;
}

}  // namespace metamer
