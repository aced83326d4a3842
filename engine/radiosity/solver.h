// The radiosity equation on elements, every band at once:
//   B_i(λ) = E_i(λ) + ρ_i(λ)·H_i(λ) + Σ_μ M_i(λ, μ)·H_i(μ),   H_i(λ) = Σ_j F_ij·B_j(λ)
// B: radiosity leaving element i (W·m⁻²·nm⁻¹), E: what the direct light makes it send (its own
// reflection and fluorescence of the direct irradiance), H: the irradiance the other elements send
// it, F_ij: the form factor from i to j (radiosity/form_factor.h), ρ: diffuse reflectance, M: the
// re-emission of a fluorescent surface (radiosity in band λ per irradiance in band μ, its Donaldson
// matrix or rank-one pair on the grid with the band widths folded in; zero without).
//
// Solved by conjugate gradients, which do not stall on bright scenes as Jacobi does (ρ_max^k: 1800
// steps for 10⁻⁶ at ρ = 0.99): with reciprocity (A_i F_ij = A_j F_ji) the equation for
// w = A^½ρ^½H, (I − A^½ρ^½Fρ^½A^-½)w = A^½ρ^½F·E, is symmetric positive definite, its eigenvalues
// within [1 − ρ_max, 1 + ρ_max]; every band's iteration shares one product F·[bands]. The form
// factors are reciprocal only to their quadrature, so each solve corrects the residual of the
// equation itself (iterative refinement) until the bound on the remaining error meets the
// tolerance. Re-emission couples the bands: they are swept in order of wavelength (fluorescence
// emits at longer wavelengths than it absorbs, so one sweep nearly solves it) until the whole
// residual's bound meets the tolerance.
//
// The bound: the error e = B − B* satisfies e = (ρF + MF)e − r, r the residual; with
// q = max_i Σ_j F_ij · max_λ (ρ_i(λ) + Σ_μ |M_i(λ, μ)|) < 1, |e_i(λ)| ≤ ‖r‖_∞/(1 − q) everywhere.
// Tests: engine/radiosity/solver_test.cpp (furnaces, a fluorescent furnace, the bound against a
// direct solve, iterations against Jacobi's).
#pragma once

#include <Eigen/Dense>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace metamer::radiosity {

// What one kind of surface does with the irradiance it receives, per band.
struct SurfaceResponse {
    std::vector<double> reflectance;  // [band], diffuse ρ in [0, 1]
    Eigen::MatrixXd reemission;       // [emission band][excitation band]; empty: not fluorescent
};

struct Problem {
    std::vector<double> area;       // [element], m²
    Eigen::MatrixXd formFactors;    // [receiver i][emitter j]: F_ij
    // Or, when set, F held elsewhere (the geometry cache's), read in place of formFactors: a
    // sweep's solve does not copy elements² × 8 bytes.
    std::shared_ptr<const Eigen::MatrixXd> sharedFormFactors;
    const Eigen::MatrixXd& F() const { return sharedFormFactors ? *sharedFormFactors : formFactors; }
    std::vector<uint32_t> surface;  // [element]: index into surfaces
    std::vector<SurfaceResponse> surfaces;
    Eigen::MatrixXd emission;       // [element][band]: E, W·m⁻²·nm⁻¹
};

struct Solution {
    Eigen::MatrixXd radiosity;   // [element][band]: B, W·m⁻²·nm⁻¹
    Eigen::MatrixXd irradiance;  // [element][band]: H = F·B, W·m⁻²·nm⁻¹
    // The bound on |B_i(λ) − B*_i(λ)| over every element and band, W·m⁻²·nm⁻¹, and that over the
    // largest radiosity; infinite where q ≥ 1 (a re-emission that can exceed what a band absorbs).
    double bound = 0.0, relativeBound = 0.0;
    double contraction = 0.0;  // q above
    int iterations = 0;        // conjugate-gradient steps, every band's counted once per shared product
    int sweeps = 0;            // over the bands (1 without re-emission)
    Eigen::RowVectorXd residual;  // [band]: max_i |r_i(λ)| where it stopped, W·m⁻²·nm⁻¹ (the bound's ‖r‖∞ is their max)
    bool rescaled = false;        // from an earlier solution (rescaledSolution), no iteration
    std::string describe() const;  // "B to 3.1e-07 of its largest value (bound), 41 iterations, 1 sweep"
};

// Solves to `tolerance`: the bound on the remaining error at most tolerance × the largest B. A
// problem whose sizes disagree, or a reflectance outside [0, 1] or not finite, is a runtime error
// naming what (the scene reader has refused such input before); one that cannot reach the
// tolerance in `maxIterations` returns what it has, its bound saying so.
// `start`: a first guess at B ([element][band]; a sweep's last solution): the iteration begins from
// it and stops at the same bound, in fewer steps the nearer it is (none when it already meets it).
Solution solve(const Problem& problem, double tolerance, int maxIterations = 2000, const Eigen::MatrixXd* start = nullptr);

// `now` on the same form factors as `earlier`, with the same areas and surfaces, and an emission
// that is earlier's scaled band by band (E' = E·diag(s), to 10⁻¹² of each band's largest: one light's
// spectrum or scale changed, or an emitter's): `solved` (earlier's solution) scaled the same way —
// exactly, the equation being linear in E — its residual and bound with it, no product with F.
// nullopt for anything else (then solve, `start` from it).
std::optional<Solution> rescaledSolution(const Problem& earlier, const Solution& solved, const Problem& now);

}  // namespace metamer::radiosity
