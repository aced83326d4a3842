#include "isp/demosaic.h"

#include "core/parallel_for.h"

#include <algorithm>

namespace metamer {

namespace {

// Index i mirrored beyond [0, n): half a sample out (Reflect: −1 → 0, −2 → 1, n → n − 1), or
// about the edge sample (Mirror: −1 → 1, −2 → 2, n → n − 2), which keeps every index's parity
// and so the CFA's colour.
int mirror(int i, int n, DemosaicBorder border) {
    if (border == DemosaicBorder::Reflect) {
        while (i < 0 || i >= n) i = i < 0 ? -i - 1 : 2 * n - i - 1;
    } else {
        while (i < 0 || i >= n) i = i < 0 ? -i : 2 * n - 2 - i;
    }
    return i;
}

struct Mosaic {
    const std::vector<double>& v;
    int w, h;
    std::array<int, 4> pattern;
    DemosaicBorder border;
    int mx(int x) const { return mirror(x, w, border); }
    int my(int y) const { return mirror(y, h, border); }
    double at(int x, int y) const { return v[size_t(my(y)) * size_t(w) + size_t(mx(x))]; }
    int colour(int x, int y) const { return pattern[size_t(my(y) % 2) * 2 + size_t(mx(x) % 2)]; }
};

// Σ k[j][i] · m(x + i − r, y + j − r) over a (2r+1)² kernel (symmetric: correlation = convolution).
template <int N>
double apply(const Mosaic& m, int x, int y, const double (&k)[N][N], double scale) {
    constexpr int r = N / 2;
    double s = 0.0;
    for (int j = 0; j < N; ++j)
        for (int i = 0; i < N; ++i)
            if (k[j][i] != 0.0) s += k[j][i] * m.at(x + i - r, y + j - r);
    return s * scale;
}

// Bilinear: each colour's samples, the others zero, convolved with a tent.
double bilinear(const Mosaic& m, int x, int y, int c) {
    static const double green[3][3] = {{0, 1, 0}, {1, 4, 1}, {0, 1, 0}};
    static const double redBlue[3][3] = {{1, 2, 1}, {2, 4, 2}, {1, 2, 1}};
    const auto& k = c == 1 ? green : redBlue;
    double s = 0.0;
    for (int j = -1; j <= 1; ++j)
        for (int i = -1; i <= 1; ++i)
            if (k[j + 1][i + 1] != 0.0 && m.colour(x + i, y + j) == c) s += k[j + 1][i + 1] * m.at(x + i, y + j);
    return s / 4.0;
}

// Malvar, He and Cutler's 5 × 5 filters (their Fig. 2), ×1/8: green at a red or blue pixel; red
// (blue) at a green pixel whose row holds red (blue), and its transpose for a column; red at blue
// and blue at red.
const double kGreenAtRB[5][5] = {{0, 0, -1, 0, 0}, {0, 0, 2, 0, 0}, {-1, 2, 4, 2, -1}, {0, 0, 2, 0, 0}, {0, 0, -1, 0, 0}};
const double kRowNeighbours[5][5] = {
    {0, 0, 0.5, 0, 0}, {0, -1, 0, -1, 0}, {-1, 4, 5, 4, -1}, {0, -1, 0, -1, 0}, {0, 0, 0.5, 0, 0}};
const double kColumnNeighbours[5][5] = {
    {0, 0, -1, 0, 0}, {0, -1, 4, -1, 0}, {0.5, 0, 5, 0, 0.5}, {0, -1, 4, -1, 0}, {0, 0, -1, 0, 0}};
const double kDiagonal[5][5] = {
    {0, 0, -1.5, 0, 0}, {0, 2, 0, 2, 0}, {-1.5, 0, 6, 0, -1.5}, {0, 2, 0, 2, 0}, {0, 0, -1.5, 0, 0}};

double malvar(const Mosaic& m, int x, int y, int c) {
    const int here = m.colour(x, y);
    if (here == c) return m.at(x, y);
    if (c == 1) return apply(m, x, y, kGreenAtRB, 1.0 / 8.0);
    if (here == 1) {
        // A green pixel: the wanted colour is in its row or in its column.
        const bool inRow = m.colour(x + 1, y) == c || m.colour(x - 1, y) == c;
        return apply(m, x, y, inRow ? kRowNeighbours : kColumnNeighbours, 1.0 / 8.0);
    }
    return apply(m, x, y, kDiagonal, 1.0 / 8.0);  // red at blue, blue at red
}

}  // namespace

DemosaicMethod parseDemosaicMethod(const std::string& name, const Where& where) {
    if (name == "bilinear") return DemosaicMethod::Bilinear;
    if (name == "malvar2004") return DemosaicMethod::Malvar2004;
    failInput(where, "'{}' is not a demosaicing method: bilinear or malvar2004", name);
}

std::array<int, 4> bayerPattern(const std::string& name, const Where& where) {
    std::array<int, 4> p{};
    if (name.size() != 4) failInput(where, "'{}' is not a Bayer pattern: RGGB, BGGR, GRBG or GBRG", name);
    int counts[3] = {0, 0, 0};
    for (size_t i = 0; i < 4; ++i) {
        const char ch = name[i];
        p[i] = ch == 'R' ? 0 : ch == 'G' ? 1 : ch == 'B' ? 2 : -1;
        if (p[i] < 0) failInput(where, "'{}' is not a Bayer pattern: RGGB, BGGR, GRBG or GBRG", name);
        ++counts[p[i]];
    }
    // Two greens on a diagonal, one red, one blue.
    if (counts[0] != 1 || counts[1] != 2 || counts[2] != 1 || !((p[0] == 1 && p[3] == 1) || (p[1] == 1 && p[2] == 1)))
        failInput(where, "'{}' is not a Bayer pattern: RGGB, BGGR, GRBG or GBRG", name);
    return p;
}

std::vector<double> demosaic(const std::vector<double>& mosaic, int width, int height, const std::array<int, 4>& pattern,
                             DemosaicMethod method, DemosaicBorder border) {
    if (width < 2 || height < 2 || mosaic.size() != size_t(width) * size_t(height))
        failInput(Where{"mosaic"}, "expected at least 2 × 2 values, width × height of them; got {} for {} × {}",
                  mosaic.size(), width, height);
    const Mosaic m{mosaic, width, height, pattern, border};
    std::vector<double> rgb(size_t(width) * size_t(height) * 3);
    // Rows on threads: every pixel is computed from the mosaic alone, so any split is the same.
    parallelFor(size_t(height), 0, 64, [&](size_t row) {
        const int y = int(row);
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < 3; ++c)
                rgb[(size_t(y) * width + size_t(x)) * 3 + size_t(c)] =
                    method == DemosaicMethod::Bilinear ? bilinear(m, x, y, c) : malvar(m, x, y, c);
    });
    return rgb;
}

}  // namespace metamer
