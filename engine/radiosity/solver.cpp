#include "radiosity/solver.h"

#include "core/error.h"
#include "radiosity/product.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace metamer::radiosity {

namespace {

using Eigen::ArrayXd;
using Eigen::MatrixXd;
using Eigen::RowVectorXd;

// The problem's per-element quantities, checked and laid out for the iteration.
struct Prepared {
    size_t elements = 0, bands = 0;
    MatrixXd rho;                 // [element][band]
    Eigen::VectorXd sqrtArea, invSqrtArea;
    MatrixXd sqrtRho;             // [element][band]
    bool reemits = false;
    double contraction = 0.0;     // q
};

Prepared prepare(const Problem& p) {
    Prepared s;
    s.elements = p.area.size();
    s.bands = size_t(p.emission.cols());
    const size_t n = s.elements;
    if (size_t(p.F().rows()) != n || size_t(p.F().cols()) != n || size_t(p.emission.rows()) != n ||
        p.surface.size() != n)
        failRuntime("radiosity: {} element areas, a {}×{} form-factor matrix, {} emission rows and {} surface "
                    "indices: they must agree",
                    n, p.F().rows(), p.F().cols(), p.emission.rows(), p.surface.size());
    std::vector<double> surfaceGain(p.surfaces.size(), 0.0);  // max_λ ρ(λ) + Σ_μ |M(λ, μ)|
    for (size_t k = 0; k < p.surfaces.size(); ++k) {
        const SurfaceResponse& r = p.surfaces[k];
        if (r.reflectance.size() != s.bands)
            failRuntime("radiosity: surface {} has {} reflectance bands, the emission {}", k, r.reflectance.size(), s.bands);
        const bool fluorescent = r.reemission.size() != 0;
        if (fluorescent && (size_t(r.reemission.rows()) != s.bands || size_t(r.reemission.cols()) != s.bands))
            failRuntime("radiosity: surface {}'s re-emission is {}×{}, not {}×{} bands", k, r.reemission.rows(),
                        r.reemission.cols(), s.bands, s.bands);
        s.reemits = s.reemits || fluorescent;
        for (size_t b = 0; b < s.bands; ++b) {
            const double rho = r.reflectance[b];
            if (!(rho >= 0.0 && rho <= 1.0))
                failRuntime("radiosity: surface {}'s reflectance in band {} is {}, outside [0, 1]", k, b, rho);
            const double gain = rho + (fluorescent ? r.reemission.row(Eigen::Index(b)).cwiseAbs().sum() : 0.0);
            surfaceGain[k] = std::max(surfaceGain[k], gain);
        }
    }
    // The rows' sums in one column-major pass (a row at a time strides the whole matrix).
    const Eigen::VectorXd rowSums = p.F().rowwise().sum();
    s.rho.resize(Eigen::Index(n), Eigen::Index(s.bands));
    s.sqrtArea.resize(Eigen::Index(n));
    s.invSqrtArea.resize(Eigen::Index(n));
    for (size_t i = 0; i < n; ++i) {
        if (p.surface[i] >= p.surfaces.size())
            failRuntime("radiosity: element {} names surface {}; there are {}", i, p.surface[i], p.surfaces.size());
        if (!(p.area[i] > 0.0)) failRuntime("radiosity: element {} has area {}", i, p.area[i]);
        const SurfaceResponse& r = p.surfaces[p.surface[i]];
        for (size_t b = 0; b < s.bands; ++b) s.rho(Eigen::Index(i), Eigen::Index(b)) = r.reflectance[b];
        s.sqrtArea[Eigen::Index(i)] = std::sqrt(p.area[i]);
        s.invSqrtArea[Eigen::Index(i)] = 1.0 / s.sqrtArea[Eigen::Index(i)];
        s.contraction = std::max(s.contraction, rowSums[Eigen::Index(i)] * surfaceGain[p.surface[i]]);
    }
    s.sqrtRho = s.rho.array().sqrt().matrix();
    return s;
}

// M(H): every element's re-emission of the irradiance it receives.
MatrixXd reemitted(const Problem& p, const MatrixXd& irradiance) {
    MatrixXd out = MatrixXd::Zero(irradiance.rows(), irradiance.cols());
    for (Eigen::Index i = 0; i < irradiance.rows(); ++i) {
        const SurfaceResponse& r = p.surfaces[p.surface[size_t(i)]];
        if (r.reemission.size() != 0) out.row(i) = (r.reemission * irradiance.row(i).transpose()).transpose();
    }
    return out;
}

// Solves δ = S + ρ·(F·δ) for every band at once by conjugate gradients on the symmetric form
// (I − T)w = A^½ρ^½F·S, T = A^½ρ^½Fρ^½A^-½, δ = S + ρ^½A^-½w, each band's residual reduced by
// `reduction`; the steps taken are added to `iterations`.
MatrixXd solveReflection(const Problem& p, const Prepared& s, const MatrixXd& S, double reduction, int maxIterations,
                         int& iterations) {
    const MatrixXd& F = p.F();
    auto scaleIn = [&](const MatrixXd& w) {  // ρ^½A^-½ w
        return (s.sqrtRho.array() * (w.array().colwise() * s.invSqrtArea.array())).matrix();
    };
    auto scaleOut = [&](const MatrixXd& y) {  // A^½ρ^½ y
        return (s.sqrtRho.array() * (y.array().colwise() * s.sqrtArea.array())).matrix();
    };
    const MatrixXd c = scaleOut(timesOnEveryCore(F, S));
    MatrixXd w = MatrixXd::Zero(c.rows(), c.cols());
    MatrixXd r = c, d = c;
    RowVectorXd rr = r.colwise().squaredNorm();
    const RowVectorXd goal = rr * (reduction * reduction);
    for (int k = 0; k < maxIterations; ++k) {
        bool done = true;
        for (Eigen::Index b = 0; b < rr.size(); ++b) done = done && rr[b] <= goal[b];
        if (done) break;
        const MatrixXd q = d - scaleOut(timesOnEveryCore(F, scaleIn(d)));
        const RowVectorXd dq = (d.array() * q.array()).colwise().sum();
        ++iterations;
        for (Eigen::Index b = 0; b < rr.size(); ++b) {
            if (rr[b] <= goal[b] || !(dq[b] > 0.0)) continue;  // this band is there (or has nothing left)
            const double alpha = rr[b] / dq[b];
            w.col(b) += alpha * d.col(b);
            r.col(b) -= alpha * q.col(b);
            const double next = r.col(b).squaredNorm();
            d.col(b) = r.col(b) + (next / rr[b]) * d.col(b);
            rr[b] = next;
        }
    }
    return S + scaleIn(w);
}

// The solution's error bound from its residual r (per band, out.residual): ‖B − B*‖∞ ≤ ‖r‖∞ /
// (1 − contraction), absolute and relative to `largest` (the largest of B and E); none (∞) when the
// contraction reaches 1, and 0 for a zero residual whatever the contraction.
void setBound(Solution& out, double largest) {
    const double inf = std::numeric_limits<double>::infinity();
    const double gain = out.contraction < 1.0 ? 1.0 / (1.0 - out.contraction) : inf;
    const double r = out.residual.size() ? out.residual.maxCoeff() : 0.0;
    out.bound = r > 0.0 ? r * gain : 0.0;
    out.relativeBound = largest > 0.0 ? out.bound / largest : (r == 0.0 ? 0.0 : inf);
}

}  // namespace

std::string Solution::describe() const {
    const std::string boundText =
        std::isfinite(relativeBound) ? fmt::format("to {:.1e} of its largest value (bound)", relativeBound)
                                     : std::string("without a bound (the re-emission can exceed what a band absorbs)");
    if (rescaled) return fmt::format("B {}, the last solve's scaled band by band as the emission was", boundText);
    return fmt::format("B {}, {} iteration{}, {} sweep{}", boundText, iterations, iterations == 1 ? "" : "s", sweeps,
                       sweeps == 1 ? "" : "s");
}

Solution solve(const Problem& p, double tolerance, int maxIterations, const Eigen::MatrixXd* start) {
    const Prepared s = prepare(p);
    Solution out;
    out.contraction = s.contraction;
    out.radiosity = MatrixXd::Zero(Eigen::Index(s.elements), Eigen::Index(s.bands));
    if (start) {
        if (start->rows() != out.radiosity.rows() || start->cols() != out.radiosity.cols())
            failRuntime("radiosity solve: a first guess of {}×{} for {} elements and {} bands", start->rows(), start->cols(),
                        s.elements, s.bands);
        out.radiosity = *start;
    }
    const double inf = std::numeric_limits<double>::infinity();
    const double gain = s.contraction < 1.0 ? 1.0 / (1.0 - s.contraction) : inf;
    // Each refinement asks the conjugate gradients for a tenth of the tolerance, at most 10⁻³: the
    // true residual, which includes what the symmetric form leaves out, decides when to stop.
    const double reduction = std::min(1e-3, 0.5 * tolerance);
    bool current = false;  // out.irradiance is F·out.radiosity
    for (int sweep = 0; sweep < 100; ++sweep) {
        out.irradiance = timesOnEveryCore(p.F(), out.radiosity);
        current = true;
        MatrixXd residual = p.emission + (s.rho.array() * out.irradiance.array()).matrix() - out.radiosity;
        if (s.reemits) residual += reemitted(p, out.irradiance);
        const double largest = std::max(out.radiosity.cwiseAbs().maxCoeff(), p.emission.cwiseAbs().maxCoeff());
        out.residual = residual.cwiseAbs().colwise().maxCoeff();
        const double r = out.residual.maxCoeff();
        setBound(out, largest);
        if (std::isfinite(gain) ? out.bound <= tolerance * largest : r <= tolerance * largest * 1e-3) break;
        if (out.iterations >= maxIterations) break;
        // From a first guess the residual may already be small: ask for what the bound needs
        // (a tenth of it), not for a fixed reduction of what is left.
        const double asked = start && std::isfinite(gain) && r > 0.0
                                 ? std::min(1e-3, std::max(reduction, 0.1 * tolerance * largest / (gain * r)))
                                 : reduction;
        out.radiosity += solveReflection(p, s, residual, asked, maxIterations - out.iterations, out.iterations);
        current = false;
        ++out.sweeps;
    }
    if (!current) out.irradiance = timesOnEveryCore(p.F(), out.radiosity);
    return out;
}

std::optional<Solution> rescaledSolution(const Problem& earlier, const Solution& solved, const Problem& now) {
    const MatrixXd &E0 = earlier.emission, &E1 = now.emission;
    if (E0.rows() != E1.rows() || E0.cols() != E1.cols() || solved.radiosity.rows() != E1.rows() ||
        solved.radiosity.cols() != E1.cols() || solved.residual.size() != E1.cols() || earlier.area != now.area ||
        earlier.surface != now.surface || earlier.surfaces.size() != now.surfaces.size())
        return std::nullopt;
    for (size_t k = 0; k < now.surfaces.size(); ++k) {
        const SurfaceResponse &a = earlier.surfaces[k], &b = now.surfaces[k];
        if (a.reflectance != b.reflectance || a.reemission.rows() != b.reemission.rows() ||
            a.reemission.cols() != b.reemission.cols() || a.reemission != b.reemission)
            return std::nullopt;
    }
    // Each band's factor by least squares, then checked: every element's emission must follow it.
    RowVectorXd scale(E1.cols());
    for (Eigen::Index b = 0; b < E1.cols(); ++b) {
        const double norm = E0.col(b).squaredNorm();
        scale[b] = norm > 0.0 ? E1.col(b).dot(E0.col(b)) / norm : 0.0;
        const double largest = E1.col(b).cwiseAbs().maxCoeff();
        if ((E1.col(b) - scale[b] * E0.col(b)).cwiseAbs().maxCoeff() > 1e-12 * largest ||
            (norm == 0.0 && largest > 0.0))
            return std::nullopt;
    }
    Solution out = solved;
    out.radiosity = solved.radiosity * scale.asDiagonal();
    out.irradiance = solved.irradiance * scale.asDiagonal();
    out.residual = solved.residual.cwiseProduct(scale.cwiseAbs());
    setBound(out, std::max(out.radiosity.cwiseAbs().maxCoeff(), E1.cwiseAbs().maxCoeff()));
    out.iterations = 0;
    out.sweeps = 0;
    out.rescaled = true;
    return out;
}

}  // namespace metamer::radiosity
