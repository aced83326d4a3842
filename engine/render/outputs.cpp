#include "render/outputs.h"

#include "color/display_rgb.h"
#include "color/quick_look.h"
#include "io/atomic_file.h"
#include "render/display_colour_space.h"

#include <fmt/ranges.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>

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
    // The spectral maps in the cube's containers, by the cube's own rule for their names.
    for (const ChosenCubeFormat& f : formats) {
        if (files.reflectance) t.reflectance.push_back({f, dir / (stem + ".reflectance" + f.format->extension)});
        if (files.illumination) t.illumination.push_back({f, dir / (stem + ".illumination" + f.format->extension)});
    }
    if (files.ids) {
        t.ids = dir / (stem + ".ids.exr");
        t.legend = dir / (stem + ".ids.json");
    }
    if (files.depth) t.depth = dir / (stem + ".depth.exr");
    if (files.normal) t.normal = dir / (stem + ".normal.exr");
    if (files.groundTruth()) t.mask = dir / (stem + ".mask.png");
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
    openGroundTruth();
}

RenderOutputs::~RenderOutputs() = default;

void RenderOutputs::openGroundTruth() {
    // What each map is, said in every file of it (docs/io.md, "Ground truth").
    auto with = [&](std::vector<std::pair<std::string, std::string>> extra) {
        Attributes a = provenance_;
        a.insert(a.end(), extra.begin(), extra.end());
        return a;
    };
    const std::string sample = "metamer:sample";
    const std::string centre = "each pixel's central sample, ray cast through the reference's BVH";
    auto openCubes = [&](const std::vector<CubeTarget>& targets, SurfaceQuantity q, const std::string& what) {
        for (const CubeTarget& t : targets) {
            CubeWriteSettings settings{t.format.options, with({{"metamer:ground_truth", what}}), false, options_.compression,
                                       std::nullopt,
                                       q == SurfaceQuantity::Reflectance ? SpectralComponent::Reflective
                                                                         : SpectralComponent::Emissive};
            std::unique_ptr<CubeWriter> writer = t.format.format->open(t.path, width_, height_, grid_, settings);
            truthCubes_.push_back({q, OpenCube{t, std::move(settings), std::move(writer)}});
        }
    };
    openCubes(targets_.reflectance, SurfaceQuantity::Reflectance,
              "reflectance: the diffuse reflectance factor of the surface seen, per band (relative); 0 at the background");
    openCubes(targets_.illumination, SurfaceQuantity::Illumination,
              "illumination: the spectral irradiance at the surface seen / pi (W·sr⁻¹·m⁻²·nm⁻¹), the radiance a "
              "perfect white diffuser would send there; 0 at the background");
    // A geometry map (ray cast at each pixel's central sample), when its target is named.
    auto openMap = [&](const std::filesystem::path& path, std::vector<std::string> channels, const std::string& what,
                       int bits) -> std::unique_ptr<ImageFileWriter> {
        if (path.empty()) return nullptr;
        ImageFile f{width_, height_, std::move(channels), with({{"metamer:ground_truth", what}, {sample, centre}})};
        return std::make_unique<ImageFileWriter>(path, f, bits);
    };
    ids_ = openMap(targets_.ids, {"object", "material"},
                   "object and material ids: indices into the legend " + targets_.legend.filename().string() +
                       ", integers held exactly as float32, -1 at the background",
                   32);
    if (ids_) legend_ = std::make_unique<AtomicOutput>(targets_.legend);
    depth_ = openMap(targets_.depth, {"Z"},
                     "depth: metres from the camera along the ray (orthographic: from the image plane), 0 at the "
                     "background",
                     32);
    normal_ = openMap(targets_.normal, {"N.X", "N.Y", "N.Z"},
                      "normal: the unit shading normal in the camera frame (x right, y up, z towards the camera), 0 at "
                      "the background",
                      32);
    mask_ = openMap(targets_.mask, {"Y"},
                    "mask: bits 1 background, 2 fluorescent, 4 specular share over 1 %, 8 transparent in front, 16 "
                    "self-luminous, 32 edge; 0 where radiance = reflectance × illumination",
                    8);
}

void RenderOutputs::writeGroundTruth(const GroundTruthImages& truth) {
    const size_t pixels = size_t(width_) * size_t(height_);
    if (capture_) {  // kept as arrays, as the files would hold them
        CapturedOutputs& c = *capture_;
        const size_t bands = size_t(grid_.bands());
        c.truthBands = bands;
        if (c.keep.reflectance && truth.reflectance) c.reflectance.assign(truth.reflectance, truth.reflectance + pixels * bands);
        if (c.keep.illumination && truth.illumination)
            c.illumination.assign(truth.illumination, truth.illumination + pixels * bands);
        if (truth.geometry) {
            const GeometryMaps& from = *truth.geometry;
            GeometryMaps& g = c.geometry;
            g.width = from.width;
            g.height = from.height;
            if (c.keep.ids) {
                g.object = from.object;
                g.material = from.material;
                c.legend = truth.legend;
            }
            if (c.keep.depth) g.depth_m = from.depth_m;
            if (c.keep.normal) g.normal = from.normal;
            if (c.keep.groundTruth()) g.mask = from.mask;
        }
    }
    for (TruthCube& t : truthCubes_) {
        const float* data = t.quantity == SurfaceQuantity::Reflectance ? truth.reflectance : truth.illumination;
        if (!data) failRuntime("cannot write '{}': the render made no {} map", t.cube.target.path.string(),
                               surfaceQuantityName(t.quantity));
        t.cube.writer->writeRows(0, height_, data);
    }
    if (!ids_ && !depth_ && !normal_ && !mask_) return;
    if (!truth.geometry || truth.geometry->mask.size() != pixels)
        failRuntime("cannot write the ground truth's geometry maps: the render made none of {}×{} pixels", width_, height_);
    const GeometryMaps& g = *truth.geometry;
    if (ids_) {
        std::vector<float> ids(2 * pixels);
        for (size_t i = 0; i < pixels; ++i) {
            ids[2 * i] = float(g.object[i]);
            ids[2 * i + 1] = float(g.material[i]);
        }
        ids_->writeRows(0, height_, ids);
        legend_->naming([&] {
            std::ofstream f(legend_->tempPath(), std::ios::binary | std::ios::trunc);
            f << truth.legend;
            if (!f.flush()) failRuntime("cannot write '{}': {}", legend_->tempPath().string(), std::strerror(errno));
        });
    }
    if (depth_) depth_->writeRows(0, height_, g.depth_m);
    if (normal_) normal_->writeRows(0, height_, g.normal);
    if (mask_) {
        mask_->writeRows(0, height_, std::vector<uint16_t>(g.mask.begin(), g.mask.end()));
        const size_t clean = size_t(std::count(g.mask.begin(), g.mask.end(), uint8_t(0)));
        maskWhat_ = fmt::format("ground-truth mask: {} of {} pixels where radiance = reflectance × illumination (0); "
                                "bits 1 background, 2 fluorescent, 4 specular, 8 transparent in front, 16 "
                                "self-luminous, 32 edge", clean, pixels);
    }
}

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
    for (TruthCube& t : truthCubes_) {
        add(t.cube.writer->finish());
        const std::string what = t.quantity == SurfaceQuantity::Reflectance
                                     ? fmt::format("reflectance (ground truth), {}×{} px, {} bands {} nm, relative",
                                                   width_, height_, grid_.bands(), grid_.str())
                                     : fmt::format("illumination (ground truth: irradiance/π), {}", cubeWhat);
        written.push_back({t.cube.target.path, t.cube.target.format.format->describe
                                                   ? t.cube.target.format.format->describe(t.cube.target.path,
                                                                                           t.cube.settings, what)
                                                   : what});
    }
    if (ids_) {
        add(ids_->finish());
        written.push_back({targets_.ids, "object and material ids (ground truth), central sample"});
        add({legend_.get()});
        written.push_back({targets_.legend, "the ids' legend: object and material names"});
    }
    if (depth_) {
        add(depth_->finish());
        written.push_back({targets_.depth, "depth (ground truth), metres along the ray, central sample"});
    }
    if (normal_) {
        add(normal_->finish());
        written.push_back({targets_.normal, "shading normal (ground truth), camera frame, central sample"});
    }
    if (mask_) {
        add(mask_->finish());
        written.push_back({targets_.mask, maskWhat_});
    }
    std::vector<StagingFolder*> staged;
    if (beforeCommit) staged = beforeCommit(files);
    commitTogether(files, staged);
    return written;
}

}  // namespace metamer
