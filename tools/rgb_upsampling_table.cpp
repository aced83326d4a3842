// Build-time tool: fits the RGB → spectrum up-sampling table (engine/color/rgb_upsampling.h)
// and writes it as a binary file that the engine loads. Run by CMake; prints what it did.
//
//   metamer_rgb_upsampling_table --spectra DIR --resolution N --threads N --out FILE
#include "color/rgb_upsampling.h"

#include <fmt/format.h>

#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>

using namespace metamer;

int main(int argc, char** argv) {
    std::string spectra, out;
    int resolution = RgbUpsampler::kDefaultResolution;
    int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    for (int i = 1; i < argc; ++i) {
        auto value = [&](const char* name) -> const char* {
            if (i + 1 >= argc) {
                fmt::print(stderr, "{}: {} needs a value\n", argv[0], name);
                std::exit(2);
            }
            return argv[++i];
        };
        if (!std::strcmp(argv[i], "--spectra")) spectra = value("--spectra");
        else if (!std::strcmp(argv[i], "--out")) out = value("--out");
        else if (!std::strcmp(argv[i], "--resolution")) resolution = std::atoi(value("--resolution"));
        else if (!std::strcmp(argv[i], "--threads")) threads = std::atoi(value("--threads"));
        else {
            fmt::print(stderr, "usage: {} --spectra DIR --out FILE [--resolution N] [--threads N]\n", argv[0]);
            return 2;
        }
    }
    if (spectra.empty() || out.empty() || resolution < 3 || threads < 1) {
        fmt::print(stderr, "usage: {} --spectra DIR --out FILE [--resolution N ≥ 3] [--threads N ≥ 1]\n", argv[0]);
        return 2;
    }
    try {
        SpectrumLibrary library(spectra);
        RgbUpsampler::BuildStats stats;
        RgbUpsampler table = RgbUpsampler::build(library, resolution, threads, &stats);
        table.write(out);
        const long nodes = 3L * resolution * resolution * resolution;
        fmt::print("RGB up-sampling table: {} nodes (3 × {}³) in {:.2f} s on {} thread(s), {:.1f} µs/node, "
                   "{:.2f} iterations/node; largest node ΔE*ab {:.2e}, {} above {:.0e}; wrote {}\n",
                   nodes, resolution, stats.seconds, threads, 1e6 * stats.seconds / nodes,
                   double(stats.iterations) / nodes, stats.maxResidual, stats.unconverged,
                   RgbUpsampler::kResidualTolerance, out);
    } catch (const std::exception& e) {
        fmt::print(stderr, "{}: {}\n", argv[0], e.what());
        return 1;
    }
    return 0;
}
