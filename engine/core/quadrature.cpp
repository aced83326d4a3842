#include "core/quadrature.h"

#include <numbers>

namespace metamer {

GaussRule gaussLegendre(int n) {
    GaussRule rule;
    rule.x.resize(n);
    rule.w.resize(n);
    for (int i = 0; i < n; ++i) {
        // Newton's method on L_n from the usual first guess; the nodes come out descending.
        double z = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5)), derivative = 1.0;
        for (int iteration = 0; iteration < 100; ++iteration) {
            double p1 = 1.0, p2 = 0.0;
            for (int j = 1; j <= n; ++j) {
                const double p3 = p2;
                p2 = p1;
                p1 = ((2.0 * j - 1.0) * z * p2 - (j - 1.0) * p3) / j;
            }
            derivative = n * (z * p1 - p2) / (z * z - 1.0);
            const double step = p1 / derivative;
            z -= step;
            if (std::fabs(step) < 1e-16) break;
        }
        rule.x[n - 1 - i] = z;
        rule.w[n - 1 - i] = 2.0 / ((1.0 - z * z) * derivative * derivative);
    }
    return rule;
}

void legendrePolynomials(double y, int m, double* l) {
    l[0] = 1.0;
    if (m > 0) l[1] = y;
    for (int k = 2; k <= m; ++k) l[k] = ((2.0 * k - 1.0) * y * l[k - 1] - (k - 1.0) * l[k - 2]) / k;
}

namespace quadrature_detail {

const std::array<std::array<double, 15>, 15>& kronrodToLegendre() {
    // The inverse of V(i, k) = L_k(x_i) at the Kronrod nodes, by Gauss–Jordan with partial
    // pivoting (15 × 15, once).
    static const std::array<std::array<double, 15>, 15> matrix = [] {
        double a[15][30];
        for (int i = 0; i < 15; ++i) {
            double l[15];
            legendrePolynomials(kKronrodX[i], 14, l);
            for (int k = 0; k < 15; ++k) {
                a[i][k] = l[k];
                a[i][15 + k] = i == k ? 1.0 : 0.0;
            }
        }
        for (int col = 0; col < 15; ++col) {
            int pivot = col;
            for (int row = col + 1; row < 15; ++row)
                if (std::fabs(a[row][col]) > std::fabs(a[pivot][col])) pivot = row;
            for (int k = 0; k < 30; ++k) std::swap(a[col][k], a[pivot][k]);
            const double d = a[col][col];
            for (int k = 0; k < 30; ++k) a[col][k] /= d;
            for (int row = 0; row < 15; ++row) {
                if (row == col) continue;
                const double factor = a[row][col];
                for (int k = 0; k < 30; ++k) a[row][k] -= factor * a[col][k];
            }
        }
        std::array<std::array<double, 15>, 15> m{};
        for (int k = 0; k < 15; ++k)
            for (int i = 0; i < 15; ++i) m[k][i] = a[k][15 + i];
        return m;
    }();
    return matrix;
}

}  // namespace quadrature_detail

double CumulativeIntegral::operator()(double x) const {
    if (starts_.empty() || x <= starts_.front()) return 0.0;
    if (x >= ends_.back()) return total_;
    const size_t i = static_cast<size_t>(std::upper_bound(starts_.begin(), starts_.end(), x) - starts_.begin()) - 1;
    const double half = 0.5 * (ends_[i] - starts_[i]), y = std::min(1.0, (x - (starts_[i] + half)) / half);
    // ∫_{−1}^{y} L_0 = y + 1; ∫_{−1}^{y} L_k = (L_{k+1}(y) − L_{k−1}(y))/(2k + 1) for k ≥ 1.
    double l[16];
    legendrePolynomials(y, 15, l);
    const auto& c = coefficients_[i];
    double sum = c[0] * (y + 1.0);
    for (int k = 1; k < 15; ++k) sum += c[k] * (l[k + 1] - l[k - 1]) / (2.0 * k + 1.0);
    return before_[i] + half * sum;
}

}  // namespace metamer
