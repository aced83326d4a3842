// Numerical integration in double, for what is computed once per scene (the hemisphere lights'
// lobe tables, reference/lobe_table) and for the tests' independent oracles:
//
// - gaussLegendre(n): the n-point Gauss–Legendre rule on [−1, 1].
// - integrateAdaptively(f, breaks, relTol): adaptive Gauss–Kronrod (G7K15) over the pieces between
//   consecutive `breaks`, the piece with the largest error estimate halved until the estimates sum
//   to at most relTol·|integral| (or maxPieces). The breaks are where the integrand is not smooth
//   and where it has features the first estimates must not miss; the adaptivity does the rest.
// - CumulativeIntegral: the same, keeping each final piece's 15 values, so that ∫ from the first
//   break to any x comes from the piece's interpolating polynomial (degree 14, integrated exactly
//   through its Legendre expansion): one adaptive pass answers many upper limits.
//
// Tests: core/quadrature_test.cpp.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <vector>

namespace metamer {

struct GaussRule {
    std::vector<double> x, w;  // nodes on [−1, 1], ascending, and their weights
};
GaussRule gaussLegendre(int n);

// L_0(y) … L_m(y), the Legendre polynomials, into l[0..m].
void legendrePolynomials(double y, int m, double* l);

namespace quadrature_detail {

// G7K15: the Kronrod nodes ascending on [−1, 1] (node 7 is 0), their weights, and the embedded
// 7-point Gauss weights (at the odd-numbered Kronrod nodes).
inline constexpr std::array<double, 15> kKronrodX = {
    -0.991455371120812639206854697526329, -0.949107912342758524526189684047851, -0.864864423359769072789712788640926,
    -0.741531185599394439863864773280788, -0.586087235467691130294144845693013, -0.405845151377397166906606412076961,
    -0.207784955007898467600689403773245, 0.0,
    0.207784955007898467600689403773245, 0.405845151377397166906606412076961, 0.586087235467691130294144845693013,
    0.741531185599394439863864773280788, 0.864864423359769072789712788640926, 0.949107912342758524526189684047851,
    0.991455371120812639206854697526329};
inline constexpr std::array<double, 15> kKronrodW = {
    0.022935322010529224963732008058970, 0.063092092629978553290700663189204, 0.104790010322250183839876322541518,
    0.140653259715525918745189590510238, 0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
    0.204432940075298892414161999234649, 0.209482141084727828012999174891714,
    0.204432940075298892414161999234649, 0.190350578064785409913256402421014, 0.169004726639267902826583426598550,
    0.140653259715525918745189590510238, 0.104790010322250183839876322541518, 0.063092092629978553290700663189204,
    0.022935322010529224963732008058970};
inline constexpr std::array<double, 15> kGauss7W = {
    0, 0.129484966168869693270611432679082, 0, 0.279705391489276667901467771423780, 0,
    0.381830050505118944950369775488975, 0, 0.417959183673469387755102040816327, 0,
    0.381830050505118944950369775488975, 0, 0.279705391489276667901467771423780, 0,
    0.129484966168869693270611432679082, 0};

struct Piece {
    double a, b, integral, error;
    std::array<double, 15> values;
};

template <class F>
void evaluate(const F& f, Piece& p) {
    const double mid = 0.5 * (p.a + p.b), half = 0.5 * (p.b - p.a);
    double kronrod = 0.0, gauss = 0.0;
    for (int i = 0; i < 15; ++i) {
        p.values[i] = f(mid + half * kKronrodX[i]);
        kronrod += kKronrodW[i] * p.values[i];
        gauss += kGauss7W[i] * p.values[i];
    }
    p.integral = kronrod * half;
    p.error = std::fabs((kronrod - gauss) * half);
}

// The pieces after refinement, in no particular order.
template <class F>
std::vector<Piece> refine(const F& f, std::span<const double> breaks, double relTol, int maxPieces) {
    std::vector<Piece> pieces;
    double total = 0.0, error = 0.0;
    for (size_t i = 0; i + 1 < breaks.size(); ++i) {
        if (!(breaks[i + 1] > breaks[i])) continue;
        Piece p{breaks[i], breaks[i + 1], 0.0, 0.0, {}};
        evaluate(f, p);
        total += p.integral;
        error += p.error;
        pieces.push_back(p);
    }
    auto smallerError = [](const Piece& x, const Piece& y) { return x.error < y.error; };
    std::make_heap(pieces.begin(), pieces.end(), smallerError);
    while (error > relTol * std::fabs(total) && static_cast<int>(pieces.size()) < maxPieces) {
        std::pop_heap(pieces.begin(), pieces.end(), smallerError);
        const Piece worst = pieces.back();
        pieces.pop_back();
        const double mid = 0.5 * (worst.a + worst.b);
        if (!(mid > worst.a && mid < worst.b)) {  // cannot halve further: keep it as it is
            pieces.push_back(worst);
            std::push_heap(pieces.begin(), pieces.end(), smallerError);
            break;
        }
        Piece left{worst.a, mid, 0.0, 0.0, {}}, right{mid, worst.b, 0.0, 0.0, {}};
        evaluate(f, left);
        evaluate(f, right);
        total += left.integral + right.integral - worst.integral;
        error += left.error + right.error - worst.error;
        pieces.push_back(left);
        std::push_heap(pieces.begin(), pieces.end(), smallerError);
        pieces.push_back(right);
        std::push_heap(pieces.begin(), pieces.end(), smallerError);
    }
    return pieces;
}

// The matrix taking a piece's 15 values to the Legendre coefficients of their interpolant.
const std::array<std::array<double, 15>, 15>& kronrodToLegendre();

}  // namespace quadrature_detail

// ∫ f over [breaks.front(), breaks.back()].
template <class F>
double integrateAdaptively(const F& f, std::span<const double> breaks, double relTol, int maxPieces = 20000) {
    double sum = 0.0;
    for (const auto& p : quadrature_detail::refine(f, breaks, relTol, maxPieces)) sum += p.integral;
    return sum;
}

class CumulativeIntegral {
public:
    template <class F>
    CumulativeIntegral(const F& f, std::span<const double> breaks, double relTol, int maxPieces = 20000) {
        auto pieces = quadrature_detail::refine(f, breaks, relTol, maxPieces);
        std::sort(pieces.begin(), pieces.end(), [](const auto& x, const auto& y) { return x.a < y.a; });
        const auto& m = quadrature_detail::kronrodToLegendre();
        double run = 0.0;
        for (const auto& p : pieces) {
            starts_.push_back(p.a);
            ends_.push_back(p.b);
            before_.push_back(run);
            std::array<double, 15> c{};
            for (int k = 0; k < 15; ++k)
                for (int i = 0; i < 15; ++i) c[k] += m[k][i] * p.values[i];
            coefficients_.push_back(c);
            run += p.integral;
        }
        total_ = run;
    }

    double total() const { return total_; }
    // ∫ f from the first break to x (0 before it, the total after the last).
    double operator()(double x) const;
    // The final pieces, ascending: [starts()[i], ends()[i]] (other integrands with the same
    // features can be integrated on them with one G7K15 each).
    const std::vector<double>& starts() const { return starts_; }
    const std::vector<double>& ends() const { return ends_; }

private:
    std::vector<double> starts_, ends_, before_;
    std::vector<std::array<double, 15>> coefficients_;
    double total_ = 0.0;
};

}  // namespace metamer
