#include "reference/lobe_table.h"

#include "core/cpu_count.h"

#include "core/cache_folder.h"
#include "io/atomic_file.h"
#include "reference/lobe_integrals.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <mutex>
#include <numbers>
#include <system_error>
#include <thread>

// The shared lookup, compiled as C++ in double on the float data.
namespace metamer::lobe_lookup {
using namespace glm;
inline dvec4 floatsOf(const uvec4& u) {
    return dvec4(std::bit_cast<float>(u.x), std::bit_cast<float>(u.y), std::bit_cast<float>(u.z), std::bit_cast<float>(u.w));
}
inline dvec2 unormPair(uint32_t x) { return dvec2(double(x & 0xffffu) / 65535.0, double(x >> 16) / 65535.0); }
#define LT_FLOAT double
#define LT_VEC2 glm::dvec2
#define LT_VEC3 glm::dvec3
#define LT_VEC4 glm::dvec4
#define LOBE_DATA_PARAM const glm::uvec4 *lobeData,
#define LOBE_FETCH(i) lobeData[(i)]
#define LOBE_FLOATS(u) floatsOf(u)
#define LOBE_UNORM(x) unormPair(x)
#include "lobe_lookup.h"
}  // namespace metamer::lobe_lookup

namespace metamer {

namespace {

constexpr double kPi = std::numbers::pi;
// The share of the lobe the early-out may leave on the wrong side (shaders/lobe_lookup.h).
constexpr double kConeTail = 1e-7;
// The quadrature's tolerance for each row of the table, relative to the lobe.
constexpr double kRowTolerance = 1e-8;
// Bumped whenever what a table holds changes (its layout, the builder's method): old files are
// then ignored.
constexpr uint32_t kTableVersion = 5;
constexpr char kMagic[8] = {'M', 'T', 'M', 'R', 'L', 'O', 'B', 'E'};

// The view elevation θe at x1 (the inverse of lobeX1).
double thetaEAt(double x1, double gloss) {
    const double k = LOBE_X1_WARP * std::sqrt(gloss + 1.0);
    return std::expm1(x1 * std::log1p(k * 0.5 * kPi)) / k;
}

// Runs task(0 … count − 1) on `threads` threads.
template <class Task>
void parallelFor(int count, int threads, const Task& task) {
    std::atomic<int> next{0};
    auto work = [&] {
        for (int i; (i = next++) < count;) task(i);
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(work);
    work();
    for (auto& thread : pool) thread.join();
}

}  // namespace

LobeTable buildLobeTable(double gloss, int threads) {
    if (threads <= 0) threads = usableCpuCount();
    LobeTable table;
    table.gloss = gloss;
    table.data.assign(LOBE_TABLE_UVEC4, glm::uvec4(0u));
    auto floatBits = [](double x) { return std::bit_cast<uint32_t>(static_cast<float>(x)); };

    // The moments at the nodes; the cone of each interval: the wider of its ends', widened by 5 %
    // (the cone varies slowly and smoothly with θe, and an interval spans 1/512 of x1).
    std::vector<LobeMoments> moments(LOBE_MOMENT_NODES);
    parallelFor(LOBE_MOMENT_NODES, threads, [&](int i) {
        moments[i] = lobeMoments(thetaEAt(double(i) / (LOBE_MOMENT_NODES - 1), gloss), gloss, kConeTail);
    });
    std::vector<glm::dvec4> stored(LOBE_MOMENT_NODES);  // the moments as the lookup reads them
    for (int i = 0; i < LOBE_MOMENT_NODES; ++i) {
        const LobeMoments& m = moments[i];
        const glm::vec4 rounded(m.gamma, m.sigma1, m.sigma2, std::log(m.unoccluded));
        table.data[i] = glm::uvec4(floatBits(rounded.x), floatBits(rounded.y), floatBits(rounded.z), floatBits(rounded.w));
        stored[i] = glm::dvec4(rounded);
    }
    // The slope of ln I_unoccluded at each node, in units of an interval: fourth-order differences
    // (one-sided at the ends), for the lookup's cubic Hermite.
    auto lnU = [&](int i) { return std::log(moments[std::clamp(i, 0, LOBE_MOMENT_NODES - 1)].unoccluded); };
    auto slope = [&](int i) {
        if (i < 2 || i > LOBE_MOMENT_NODES - 3) {
            const int d = i < 2 ? 1 : -1;  // −25/12 f0 + 4 f1 − 3 f2 + 4/3 f3 − 1/4 f4, towards the inside
            return d * (-25.0 / 12.0 * lnU(i) + 4.0 * lnU(i + d) - 3.0 * lnU(i + 2 * d) + 4.0 / 3.0 * lnU(i + 3 * d) -
                        0.25 * lnU(i + 4 * d));
        }
        return (-lnU(i + 2) + 8.0 * lnU(i + 1) - 8.0 * lnU(i - 1) + lnU(i - 2)) / 12.0;
    };
    for (int i = 0; i + 1 < LOBE_MOMENT_NODES; ++i) {
        const double widest = 1.05 * std::max(moments[i].coneHalfAngle, moments[i + 1].coneHalfAngle);
        table.data[LOBE_CONES_OFFSET + i] = glm::uvec4(floatBits(widest < 0.5 * kPi ? std::sin(widest) : LOBE_NO_CONE),
                                                       floatBits(slope(i)), floatBits(slope(i + 1)), 0u);
    }

    // The rows (x1, β_w) for β_w ≤ π/2, as 16-bit fixed point; each gives its mirror too: the
    // hemisphere −u is (π − β_w, −x2), and I(−u) = I_unoccluded − I(u), kept exact in fixed point.
    constexpr int half = (LOBE_BETA_NODES - 1) / 2;
    std::vector<uint16_t> q(size_t(LOBE_X1_NODES) * LOBE_BETA_NODES * LOBE_X2_NODES);
    auto at = [&](int i1, int ib, int k) -> uint16_t& { return q[(size_t(i1) * LOBE_BETA_NODES + ib) * LOBE_X2_NODES + k]; };
    parallelFor(LOBE_X1_NODES * (half + 1), threads, [&](int task) {
        const int i1 = task / (half + 1), ib = task % (half + 1);
        const double x1 = double(i1) / (LOBE_X1_NODES - 1), thetaE = thetaEAt(x1, gloss);
        // The moments as the lookup interpolates them, so that the rows' coordinates are the lookup's.
        const double xm = x1 * (LOBE_MOMENT_NODES - 1);
        const int m0 = std::clamp(int(std::floor(xm)), 0, LOBE_MOMENT_NODES - 2);
        const glm::dvec4 m = (1.0 - (xm - m0)) * stored[m0] + (xm - m0) * stored[m0 + 1];
        const double gamma = m.x, sigma1 = m.y, sigma2 = m.z;
        const double betaW = kPi * ib / (LOBE_BETA_NODES - 1);
        const double beta = std::atan2(std::sin(betaW) / sigma2, std::cos(betaW) / sigma1);
        const double spread = std::hypot(sigma1 * std::cos(beta), sigma2 * std::sin(beta));
        std::vector<double> epsilons(LOBE_X2_NODES);
        for (int k = 0; k < LOBE_X2_NODES; ++k) {
            const double x2 = -1.0 + 2.0 * k / (LOBE_X2_NODES - 1);
            epsilons[k] = std::fabs(x2) == 1.0 ? x2 * 0.5 * kPi : std::atan(LOBE_X2_SCALE * std::tan(0.5 * kPi * x2) * spread);
        }
        const HemisphereFractions row = hemisphereFractions(thetaE, gloss, gamma, sigma1, sigma2, beta, epsilons, kRowTolerance);
        for (int k = 0; k < LOBE_X2_NODES; ++k) {
            const auto fixed = static_cast<uint16_t>(std::lround(std::clamp(row.fractions[k], 0.0, 1.0) * 65535.0));
            at(i1, ib, k) = fixed;
            if (ib < half) at(i1, LOBE_BETA_NODES - 1 - ib, LOBE_X2_NODES - 1 - k) = uint16_t(65535 - fixed);
        }
    });
    // Entry (x1 node, β_w pair b, x2 interval j): nodes b − 1 and b (mirrored past the ends), the
    // four values each of interval j's cubic.
    auto mirrored = [](int ib) { return ib < 0 ? -ib : ib > LOBE_BETA_NODES - 1 ? 2 * (LOBE_BETA_NODES - 1) - ib : ib; };
    auto pair = [](uint16_t low, uint16_t high) { return uint32_t(low) | uint32_t(high) << 16; };
    for (int i1 = 0; i1 < LOBE_X1_NODES; ++i1)
        for (int b = 0; b < LOBE_BETA_PAIRS; ++b)
            for (int j = 0; j + 1 < LOBE_X2_NODES; ++j) {
                const int j0 = std::clamp(j - 1, 0, LOBE_X2_NODES - 4), n0 = mirrored(b - 1), n1 = mirrored(b);
                table.data[LOBE_VALUES_OFFSET + (size_t(i1) * LOBE_BETA_PAIRS + b) * (LOBE_X2_NODES - 1) + j] =
                    glm::uvec4(pair(at(i1, n0, j0), at(i1, n0, j0 + 1)), pair(at(i1, n0, j0 + 2), at(i1, n0, j0 + 3)),
                               pair(at(i1, n1, j0), at(i1, n1, j0 + 1)), pair(at(i1, n1, j0 + 2), at(i1, n1, j0 + 3)));
            }
    return table;
}

glm::dvec2 lobeWarp(double gloss) { return lobe_lookup::lobeWarp(gloss); }

glm::dvec2 lobeIntegrals(const LobeTable& table, const glm::dvec3& n, const glm::dvec3& v, const glm::dvec3& u) {
    return lobe_lookup::lobeIntegrals(table.data.data(), 0, lobe_lookup::lobeWarp(table.gloss), n, v, u);
}

std::filesystem::path lobeCacheFolder() { return cacheFolder("METAMER_LOBE_CACHE"); }

std::string lobeCacheFileName(double gloss) {
    char name[64];
    std::snprintf(name, sizeof name, "lobe-v%u-%016llx.bin", kTableVersion,
                  static_cast<unsigned long long>(std::bit_cast<uint64_t>(gloss)));
    return name;
}

namespace {

struct FileHeader {
    char magic[8];
    uint32_t version, layout[5];
    double gloss;
    uint64_t checksum;  // FNV-1a of the data: a file damaged in place is rebuilt, not read
};

uint64_t checksumOf(const std::vector<glm::uvec4>& data) {
    uint64_t h = 0xcbf29ce484222325ull;
    const auto* bytes = reinterpret_cast<const unsigned char*>(data.data());
    for (size_t i = 0; i < data.size() * sizeof(glm::uvec4); ++i) h = (h ^ bytes[i]) * 0x100000001b3ull;
    return h;
}

FileHeader headerFor(double gloss) {
    FileHeader h{};
    std::memcpy(h.magic, kMagic, sizeof kMagic);
    h.version = kTableVersion;
    const uint32_t layout[5] = {LOBE_MOMENT_NODES, LOBE_X1_NODES, LOBE_BETA_NODES, LOBE_X2_NODES, LOBE_TABLE_UVEC4};
    std::memcpy(h.layout, layout, sizeof layout);
    h.gloss = gloss;
    return h;
}

}  // namespace

std::shared_ptr<LobeTable> readLobeTable(const std::filesystem::path& file, double gloss) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) return nullptr;
    const FileHeader expected = headerFor(gloss);
    const size_t bytes = LOBE_TABLE_UVEC4 * sizeof(glm::uvec4);
    if (std::filesystem::file_size(file, ec) != sizeof expected + bytes || ec) return nullptr;
    std::ifstream in(file, std::ios::binary);
    FileHeader header{};
    in.read(reinterpret_cast<char*>(&header), sizeof header);
    if (!in || std::memcmp(&header, &expected, offsetof(FileHeader, checksum)) != 0) return nullptr;
    auto table = std::make_shared<LobeTable>();
    table->gloss = gloss;
    table->data.resize(LOBE_TABLE_UVEC4);
    in.read(reinterpret_cast<char*>(table->data.data()), static_cast<std::streamsize>(bytes));
    if (!in || checksumOf(table->data) != header.checksum) return nullptr;
    // The moments and cones are floats and must be finite (the values are fixed point: any bits),
    // and within what a built table holds (issue 51, class 7: a file that passes its checksum may
    // still not be ours): the centroid's angle γ within ±π (built: 0 … 1.5683, π/2 in the limit of
    // gloss 0 at grazing), the spreads σ1, σ2 within [0, π],
    // ln I_unoccluded within [−200, 10] (built: −15 … 1.1), an interval's cone sine within [0, 1]
    // or LOBE_NO_CONE, its slopes of ln I_unoccluded within ±10³ (built: under 0.03).
    auto within = [](float v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; };
    constexpr double kPi = std::numbers::pi;
    for (size_t i = 0; i < LOBE_VALUES_OFFSET; ++i) {
        const glm::uvec4& e = table->data[i];
        const float a = std::bit_cast<float>(e.x), b = std::bit_cast<float>(e.y), c = std::bit_cast<float>(e.z),
                    d = std::bit_cast<float>(e.w);
        const bool sane = i < LOBE_CONES_OFFSET ? within(a, -kPi, kPi) && within(b, 0.0, kPi) && within(c, 0.0, kPi) &&
                                                      within(d, -200.0, 10.0)
                                                : (within(a, 0.0, 1.0) || a == float(LOBE_NO_CONE)) &&
                                                      within(b, -1e3, 1e3) && within(c, -1e3, 1e3) && std::isfinite(d);
        if (!sane) return nullptr;
    }
    return table;
}

void writeLobeTable(const std::filesystem::path& file, const LobeTable& table) {
    FileHeader header = headerFor(table.gloss);
    header.checksum = checksumOf(table.data);
    std::string bytes(reinterpret_cast<const char*>(&header), sizeof header);
    bytes.append(reinterpret_cast<const char*>(table.data.data()), table.data.size() * sizeof(glm::uvec4));
    writeFileAtomically(file, bytes);
}

std::shared_ptr<const LobeTable> lobeTableFor(double gloss) {
    static std::mutex mutex;
    static std::map<uint64_t, std::shared_ptr<const LobeTable>> tables;
    const std::lock_guard lock(mutex);
    auto& slot = tables[std::bit_cast<uint64_t>(gloss)];
    if (slot) return slot;
    const std::filesystem::path folder = lobeCacheFolder();
    const std::filesystem::path file = folder.empty() ? std::filesystem::path() : folder / lobeCacheFileName(gloss);
    if (!file.empty())
        if (auto cached = readLobeTable(file, gloss)) return slot = std::move(cached);
    auto built = std::make_shared<LobeTable>(buildLobeTable(gloss));
    if (!file.empty()) {
        // The cache saves time; failing to write it is not an error of the render.
        std::error_code ec;
        std::filesystem::create_directories(folder, ec);
        try {
            writeLobeTable(file, *built);
        } catch (const std::exception&) {
        }
    }
    return slot = std::move(built);
}

}  // namespace metamer
