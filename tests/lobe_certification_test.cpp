// The certification of the hemisphere lights' lobe tables (docs/physics.md, "Hemisphere lights"):
// for every gloss of a bundled scene's specular materials (glTF ones included) and for gloss 1, 4,
// 10, 60, 200, 1000 and 10⁴, the table's I(n, v, u) against the ring oracle (tests/support/
// lobe_oracles.h: exact on each ring of half vectors, adaptive in the radial variable, to 10⁻⁹),
// relative to the unoccluded lobe, over 10⁴ random configurations (half of them with the
// hemisphere's boundary within four lobe widths of the mirror direction, where the lobe is cut)
// and 10³ grazing ones (n·v < 0.02): the largest error must be at most 10⁻⁴. The ring oracle is
// checked against the independent lune oracle on 50 configurations per gloss. Prints the table
// docs/physics.md quotes. Runs in the plain suite only (ci/sanitize.sh leaves it out).
#include "core/cpu_count.h"
#include "reference/lobe_table.h"
#include "scene/scene_json.h"
#include "spectral/library.h"

#include "support/lobe_oracles.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <set>
#include <thread>
#include <vector>

using namespace metamer;
using glm::dvec3;

namespace {

// The gloss values of the bundled scenes' specular materials.
std::set<double> bundledGlosses() {
    std::set<double> glosses;
    const SpectrumLibrary library;
    for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(METAMER_SOURCE_DIR) / "scenes"))
        if (entry.path().extension() == ".json" && entry.path().filename().string()[0] != '.')
            for (const Material& m : loadScene(entry.path(), library).materials)
                if (m.hasSpecular() && m.gloss > 0.0) glosses.insert(m.gloss);
    return glosses;
}

struct Configuration : test::LobeConfiguration {
    bool grazing;
};

// 10⁴ random views (n·v uniform in [0, 1]) and 10³ grazing ones (n·v < 0.02); every second
// hemisphere's boundary near the lobe.
std::vector<Configuration> configurations(double gloss) {
    test::LobeConfigurations random(2026);
    std::vector<Configuration> out;
    for (int i = 0; i < 11000; ++i) {
        const bool grazing = i >= 10000;
        out.push_back({random.next(gloss, grazing ? 0.02 : 1.0, i % 2 == 0), grazing});
    }
    return out;
}

}  // namespace

TEST(LobeCertification, EveryBundledGlossAndTheListedOnesWithin1e4OfTheUnoccludedLobe) {
    std::set<double> glosses = bundledGlosses();
    EXPECT_GE(glosses.size(), 7u) << "the bundled scenes' glosses were not found";
    for (double N : {1.0, 4.0, 10.0, 60.0, 200.0, 1000.0, 10000.0}) glosses.insert(N);
    std::printf("| gloss | median | 99th percentile | max (random) | max (grazing) | unoccluded lobe, max | exactly 0 or all | ring vs lune |\n"
                "|--:|--:|--:|--:|--:|--:|--:|--:|\n");
    const int threads = usableCpuCount();  // what the scheduler gave (core/cpu_count.h)
    for (double N : glosses) {
        const auto table = lobeTableFor(N);
        const std::vector<Configuration> cs = configurations(N);
        std::vector<double> error(cs.size()), unoccludedError(cs.size());
        std::vector<char> decided(cs.size());
        std::atomic<size_t> next{0};
        auto work = [&] {
            for (size_t i; (i = next++) < cs.size();) {
                const Configuration& c = cs[i];
                const double whole = test::ringOracle(c.n, c.v, c.u, N, false, 1e-10);
                const double exact = test::ringOracle(c.n, c.v, c.u, N, true, 1e-9);
                const glm::dvec2 lobe = lobeIntegrals(*table, c.n, c.v, c.u);
                error[i] = std::fabs(lobe.x - exact) / whole;
                unoccludedError[i] = std::fabs(lobe.y / whole - 1.0);
                decided[i] = lobe.x == 0.0 || lobe.x == lobe.y;
            }
        };
        std::vector<std::thread> pool;
        for (int t = 0; t < threads; ++t) pool.emplace_back(work);
        for (auto& t : pool) t.join();
        // The oracle itself, against the other one.
        double oracles = 0.0;
        for (size_t i = 0; i < 50; ++i) {
            const Configuration& c = cs[i * 211];
            const double whole = test::ringOracle(c.n, c.v, c.u, N, false, 1e-10);
            oracles = std::max(oracles, std::fabs(test::ringOracle(c.n, c.v, c.u, N, true, 1e-10) -
                                                  test::luneOracle(c.n, c.v, c.u, N)) / whole);
        }
        std::vector<double> random(error.begin(), error.begin() + 10000), grazing(error.begin() + 10000, error.end());
        std::vector<double> sorted = error;
        std::sort(sorted.begin(), sorted.end());
        const double maxRandom = *std::max_element(random.begin(), random.end());
        const double maxGrazing = *std::max_element(grazing.begin(), grazing.end());
        std::printf("| %g | %.1e | %.1e | %.1e | %.1e | %.1e | %.0f %% | %.0e |\n", N, sorted[sorted.size() / 2],
                    sorted[sorted.size() * 99 / 100], maxRandom, maxGrazing,
                    *std::max_element(unoccludedError.begin(), unoccludedError.end()),
                    100.0 * std::count(decided.begin(), decided.end(), 1) / double(cs.size()), oracles);
        EXPECT_LE(std::max(maxRandom, maxGrazing), 1e-4) << "gloss " << N;
        EXPECT_LE(oracles, 1e-9) << "gloss " << N;
    }
}
