#include "render/outputs.h"

#include "color/quick_look.h"

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
                            const Representation& representation, const TonemapPlan* plan) {
    OutputTargets t;
    std::string tag = representation.mode.name();
    std::replace(tag.begin(), tag.end(), ':', '-');
    if (files.cube) t.cube = dir / (stem + (representation.mode.spectral() ? "" : "." + tag) + ".exr");
    if (files.png && plan) t.png = dir / (stem + ".png");
    if (files.xyz && plan && !responsesOnly(plan)) t.xyz = dir / (stem + ".xyz.exr");
    if (files.responses && plan) t.responses = dir / (stem + "." + detectorFileName(plan->detector.name) + ".exr");
    if (files.edges) t.edges = dir / (stem + ".edges.png");
    return t;
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
    if (!targets_.cube.empty()) {
        if (representation_.mode.spectral()) {
            ExrWriteOptions wo;
            wo.half = options_.half;
            wo.compression = options_.compression;
            wo.extraAttributes = provenance_;
            cube_ = std::make_unique<SpectralExrWriter>(targets_.cube, width_, height_, grid_, wo);
        } else {
            ImageFile f{width_, height_, representation_.channelNames, provenance_};
            f.attributes.push_back({"metamer:representation", representation_.description});
            channels_ = std::make_unique<ImageFileWriter>(targets_.cube, f, 32);
        }
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
            png_ = std::make_unique<ImageFileWriter>(targets_.png, f, plan_->display.bits);
        }
    }
    if (!targets_.xyz.empty() && plan_ && !responsesOnly(plan_)) {
        ImageFile f{width_, height_, {"X", "Y", "Z"}, provenance_};
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

bool RenderOutputs::needsCube() const { return cube_ || channels_; }
bool RenderOutputs::needsDisplay() const { return png_ || xyz_ || responses_; }
TonemapOutputs RenderOutputs::displayOutputs() const {
    return {png_ != nullptr || xyz_ != nullptr, xyz_ != nullptr, responses_ != nullptr};
}

void RenderOutputs::writeRows(int firstRow, int rows, const float* cube, const DisplayImage* image) {
    const size_t pixels = size_t(width_) * size_t(rows);
    if (cube) {
        if (cube_) cube_->writeRows(firstRow, rows, cube);
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
    if (!edges_) return;
    edges_->writeRows(0, height_, edges);
    const size_t n = size_t(std::count(edges.begin(), edges.end(), uint16_t(255)));
    edgesWhat_ = fmt::format("edge mask: {} of {} pixels see more than one surface in their 3×3 neighbourhood", n,
                             edges.size());
}

std::vector<WrittenFile> RenderOutputs::commit(int strips, int stripRows) {
    std::vector<WrittenFile> written;
    const std::string inStrips = strips > 1 ? fmt::format("written in {} strips of {} rows", strips, stripRows) : "";
    auto line = [&](const std::string& what) { return inStrips.empty() ? what : inStrips; };
    if (cube_) {
        clampedToHalf_ = cube_->commit().clampedToHalfMax;
        written.push_back({targets_.cube, line(fmt::format("{}×{} px, {} bands {} nm, W·sr⁻¹·m⁻²·nm⁻¹, {}", width_,
                                                           height_, grid_.bands(), grid_.str(),
                                                           options_.half ? "float16" : "float32"))});
    }
    if (channels_) {
        channels_->commit();
        written.push_back({targets_.cube, line(fmt::format("{} channel radiance ({}), not a spectrum",
                                                           representation_.mode.name(),
                                                           fmt::join(representation_.channelNames, ", ")))});
    }
    if (png_) {
        png_->commit();
        written.push_back({targets_.png, line(quickLook_ ? quickLookWhat_ : "display counts: " + plan_->description)});
    }
    if (xyz_) {
        xyz_->commit();
        written.push_back({targets_.xyz, line("XYZ, " + plan_->xyzUnits)});
    }
    if (responses_) {
        responses_->commit();
        written.push_back({targets_.responses, line(fmt::format("{} responses ({}), {}", plan_->detector.name,
                                                                fmt::join(plan_->detector.channels, ", "),
                                                                plan_->detector.units))});
    }
    if (edges_) {
        edges_->commit();
        written.push_back({targets_.edges, line(edgesWhat_)});
    }
    return written;
}

}  // namespace metamer
