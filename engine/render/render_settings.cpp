#include "render/render_settings.h"

#include "core/error.h"

#include <algorithm>
#include <map>

namespace metamer {

const char* renderSettingHelp(const std::string& name) {
    static const std::map<std::string, const char*> help = {
        {"set", "override a scene value: KEY=VALUE, e.g. lights.0.spectrum=illuminants/A"},
        {"grid", "spectral grid START:END:STEP in nm, e.g. 300:740:5 (overrides the scene)"},
        {"resample", "how spectra go onto the grid: interpolate (default: tabulated values at data points, linear "
                     "between, band means where the grid is coarser), sprague or band-mean"},
        {"mode", "representation: full (default), rgb, ac1c2[:N], linear:K (docs/representations.md)"},
        {"detector", "cie1931, cie1964, camera:<name>, film:<name> or csv:<path> (default: the scene's output block, "
                     "else cie1931)"},
        {"adapt", "chromatic adaptation: none, vonkries-xyz, vonkries, bradford, cat02, cat16"},
        {"display", "display model: srgb or crt"},
        {"bits", "display counts: 8 or 16 bits (the preview's window shows 8; its saved PNGs take this)"},
        {"integration", "riemann (default), trapezoid or astm-e308 (ASTM E308 weighting factors)"},
        {"xyz", "XYZ output scale: relative (white Y = 100) or absolute (cd/m²)"},
        {"ssaa", "supersampling: N×N samples per pixel (1-4)"},
        {"backend", "gpu (Vulkan) or cpu (double-precision reference)"},
        {"readback", "auto, map (linear host-visible image) or copy"},
        {"half", "write float16 instead of float32"},
        {"compression", "the cube's OpenEXR compression: piz (default), zip[:1-9], zips, rle, none, ... (docs/io.md)"},
        {"strict-coverage", "error when a spectrum's data do not cover the grid"},
        {"memory-budget", "MiB the render may hold at once (default: a quarter of the machine's memory); a larger image "
                          "is rendered in strips and streamed to the files"},
        {"write", "outputs, comma-separated: cube, png, xyz, responses, edges, and the ground truth: reflectance, "
                  "illumination, ids, depth, normal (docs/io.md; default cube,png)"},
        {"format", "the cube's containers, comma-separated: exr (default), hdf5, hdf5:gzip[:1-9], arad (MATLAB v7.3, "
                   "400-700 nm / 10 nm), envi[:bsq|bil|bip] (docs/io.md)"},
        {"no-png", "skip the display PNG"},
        {"frames", "render N frames (timing: first frame and median of the rest)"},
        {"validation", "enable Vulkan validation layers; any error fails the run"},
        {"device", "Vulkan device index, UUID or name substring (default: METAMER_DEVICE, else CUDA_VISIBLE_DEVICES, "
                   "else SLURM_LOCALID, else the best; docs/cli.md)"},
        {"verbose", "print the chosen device (and, rendering, the render plan)"},
        {"allow-outside-paths", "let the scene read files outside its own folder tree and the spectra library "
                                "(docs/scene-format.md)"},
    };
    auto it = help.find(name);
    if (it == help.end()) failRuntime("no render setting '{}'", name);
    return it->second;
}

void applyRenderSettings(const RenderSettings& s, RenderJob& job,
                         const std::function<std::string(const std::string&)>& spell) {
    auto at = [&](const char* name) { return Where{"", spell(name)}; };
    job.overrides = s.overrides;
    if (!s.grid.empty()) job.grid = Grid::parse(s.grid, at("grid"));
    if (!s.resample.empty()) job.resampling = parseResampling(s.resample, at("resample"));
    job.mode = s.mode;
    if (!s.detector.empty()) job.detector = s.detector;
    if (!s.adapt.empty()) job.adaptation = s.adapt;
    if (!s.display.empty()) job.display = s.display;
    if (!s.integration.empty()) job.integration = s.integration;
    if (!s.xyz.empty()) job.xyz = s.xyz;
    if (s.bits && s.bits != 8 && s.bits != 16) failInput(at("bits"), "{} bits; expected 8 or 16", s.bits);
    if (s.bits) job.bits = s.bits;
    if (s.ssaa < 1 || s.ssaa > 4) failInput(at("ssaa"), "{} samples per side; expected 1 to 4", s.ssaa);
    job.ssaa = s.ssaa;
    if (s.backend != "gpu" && s.backend != "cpu")
        failInput(at("backend"), "'{}' is not a backend; expected \"gpu\" or \"cpu\"", s.backend);
    job.backend = s.backend == "cpu" ? Backend::Cpu : Backend::Gpu;
    if (s.readback != "auto" && s.readback != "map" && s.readback != "copy")
        failInput(at("readback"), "'{}' is not a readback; expected \"auto\", \"map\" or \"copy\"", s.readback);
    job.readback = s.readback == "map" ? Readback::Map : s.readback == "copy" ? Readback::Copy : Readback::Auto;
    job.half = s.half;
    job.compression = s.compression;
    job.coverage = s.strictCoverage ? CoveragePolicy::Error : CoveragePolicy::ZeroWithWarning;
    // Capped at 2⁴⁰ MiB (an exabyte): a larger number means "no limit" and would overflow the bytes.
    if (s.memoryBudgetMiB > 0) job.memoryBudget = size_t(std::min(s.memoryBudgetMiB, 1099511627776.0) * (1 << 20));
    if (!s.write.empty()) job.write = s.write;
    if (!s.format.empty()) job.format = s.format;
    if (s.noPng) {
        // No PNG: whatever would be written, but not the PNG.
        std::vector<std::string> w = job.write ? *job.write : std::vector<std::string>{"cube"};
        w.erase(std::remove(w.begin(), w.end(), "png"), w.end());
        job.write = w;
    }
    job.frames = s.frames;
    job.validation = s.validation;
    job.device = s.device;
    job.verbose = s.verbose;
    job.allowOutsidePaths = s.allowOutsidePaths;
}

}  // namespace metamer
