// The form-factor matrix of refined elements: a closed box's rows, reciprocity, and occlusion by a
// plate between two squares against the unoccluded closed form.
#include "radiosity/element_coupling.h"

#include "radiosity/element_mesh.h"
#include "radiosity/form_factor.h"

#include <gtest/gtest.h>

#include <cstdio>

using namespace metamer;
using namespace metamer::radiosity;
using glm::dvec3;

namespace {

// The unit cube as one closed mesh (8 corners shared), facing inwards, refined to `edge`.
ElementMesh insideOfACube(double edge) {
    std::vector<dvec3> p;
    for (int k = 0; k < 8; ++k) p.push_back(dvec3(k & 1, (k >> 1) & 1, (k >> 2) & 1));
    // Each face's corners counter-clockwise seen from outside.
    const std::vector<uint32_t> quads{0, 2, 3, 1,  4, 5, 7, 6,  0, 1, 5, 4,  2, 6, 7, 3,  0, 4, 6, 2,  1, 3, 7, 5};
    std::vector<uint32_t> indices;
    for (size_t q = 0; q < quads.size(); q += 4)
        for (uint32_t k : {0u, 2u, 1u, 0u, 3u, 2u}) indices.push_back(quads[q + k]);  // reversed: inwards
    return refineMesh(p, indices, edge, 100000);
}

std::vector<std::array<dvec3, 3>> cornersOf(const ElementMesh& m) {
    std::vector<std::array<dvec3, 3>> out;
    for (size_t t = 0; t < m.triangles.size(); ++t) out.push_back(m.corners(t));
    return out;
}

}  // namespace

// Inside a closed box every row sums to 1 and A_i F_ij = A_j F_ji; the worst deviations are
// printed (the quadrature's) and bounded.
TEST(ElementCoupling, AClosedBoxsRowsSumToOneAndAreReciprocal) {
    const ElementMesh m = insideOfACube(0.3);
    for (size_t t = 0; t < m.triangles.size(); ++t) ASSERT_GT(glm::dot(m.normal(t), dvec3(0.5) - m.centroid(t)), 0.0);
    const auto elements = cornersOf(m);
    const Coupling c = formFactorMatrix(elements, nullptr, {});
    const Eigen::MatrixXd& F = c.formFactors;
    double worstRow = 0.0, worstReciprocity = 0.0;
    for (Eigen::Index i = 0; i < F.rows(); ++i) {
        worstRow = std::max(worstRow, std::fabs(F.row(i).sum() - 1.0));
        for (Eigen::Index j = 0; j < F.cols(); ++j) {
            const double ai = m.area(size_t(i)) * F(i, j), aj = m.area(size_t(j)) * F(j, i);
            worstReciprocity = std::max(worstReciprocity, std::fabs(ai - aj) / std::max(1e-300, std::max(ai, aj)));
        }
    }
    std::printf("%zu elements, %zu near pairs, %.2f s: worst |row sum − 1| %.2e, worst relative reciprocity %.2e\n",
                elements.size(), c.nearPairs, c.seconds, worstRow, worstReciprocity);
    EXPECT_LT(worstRow, 2e-6);
    EXPECT_LT(worstReciprocity, 2e-4);
}

// A square plate halfway between two parallel squares hides part of each from the other: the
// matrix's factor between their elements drops by what the plate covers — against the closed forms
// without occluder (0.1998) and with the plate's share removed.
TEST(ElementCoupling, APlateBetweenTwoSquaresOccludesWhatItCovers) {
    // Bottom square facing up, top square facing down, a unit apart; the plate at z = 0.5.
    std::vector<dvec3> p{dvec3(0, 0, 0), dvec3(1, 0, 0), dvec3(1, 1, 0), dvec3(0, 1, 0),
                         dvec3(0, 0, 1), dvec3(0, 1, 1), dvec3(1, 1, 1), dvec3(1, 0, 1)};
    std::vector<uint32_t> indices{0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
    const ElementMesh m = refineMesh(p, indices, 0.15, 100000);
    const auto elements = cornersOf(m);
    std::vector<uint32_t> source(m.triangles.size());
    std::vector<BvhTriangle> scene;
    for (size_t t = 0; t < m.triangles.size(); ++t) {
        source[t] = uint32_t(t);
        scene.push_back({elements[t][0], elements[t][1], elements[t][2], 0, uint32_t(t)});
    }
    const Coupling open = formFactorMatrix(elements, nullptr, {});
    // A plate covering the middle quarter (0.25–0.75 in x and y).
    scene.push_back({dvec3(0.25, 0.25, 0.5), dvec3(0.75, 0.25, 0.5), dvec3(0.75, 0.75, 0.5), 1, 0});
    scene.push_back({dvec3(0.25, 0.25, 0.5), dvec3(0.75, 0.75, 0.5), dvec3(0.25, 0.75, 0.5), 1, 1});
    const Bvh bvh(scene);
    const Coupling shaded = formFactorMatrix(elements, &bvh, source);
    // Square to square: the sum over the top's elements, area-weighted over the bottom's.
    auto squareToSquare = [&](const Eigen::MatrixXd& F) {
        double sum = 0.0, area = 0.0;
        for (size_t i = 0; i < m.triangles.size(); ++i) {
            if (m.inputTriangle[i] >= 2) continue;
            double row = 0.0;
            for (size_t j = 0; j < m.triangles.size(); ++j)
                if (m.inputTriangle[j] >= 2) row += F(Eigen::Index(i), Eigen::Index(j));
            sum += m.area(i) * row;
            area += m.area(i);
        }
        return sum / area;
    };
    EXPECT_NEAR(squareToSquare(open.formFactors), 0.199824895698387, 2e-4);
    const double shadedFactor = squareToSquare(shaded.formFactors);
    std::printf("unoccluded %.6f, behind the plate %.6f, %zu of %zu rays blocked\n", squareToSquare(open.formFactors),
                shadedFactor, shaded.blockedRays, shaded.rays);
    EXPECT_LT(shadedFactor, 0.199824895698387 - 0.02);
    EXPECT_GT(shaded.blockedRays, 0u);
}
