// Form factors against closed forms from Howell's catalogue (A Catalog of Radiation Heat Transfer
// Configuration Factors: B-11 parallel rectangles, C-14 perpendicular rectangles with a common edge,
// B-3 a differential area under a rectangle's corner, B-13 a coaxial disk), reciprocity, and a
// closed cube whose rows sum to 1.
#include "radiosity/form_factor.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

using namespace metamer::radiosity;
using glm::dvec3;

namespace {

constexpr double kPi = std::numbers::pi;

// A square's two triangles, counter-clockwise seen from the side `normal` points to.
using Tri = std::array<dvec3, 3>;
std::vector<Tri> squareTriangles(const std::array<dvec3, 4>& q) { return {{q[0], q[1], q[2]}, {q[0], q[2], q[3]}}; }

// F from a polygon (triangulated) to a polygon: the area-weighted mean of its triangles' factors.
double polygonToPolygon(const std::vector<Tri>& receiver, std::span<const dvec3> emitter, double tolerance = 1e-11) {
    double weighted = 0.0, area = 0.0;
    for (const Tri& t : receiver) {
        const double a = polygonArea(t);
        weighted += a * triangleToPolygon(t[0], t[1], t[2], emitter, tolerance);
        area += a;
    }
    return weighted / area;
}

}  // namespace

// Howell B-3: from a differential area a unit distance below the corner of an X × Y rectangle,
// F = (1/2π)[X/√(1+X²)·atan(Y/√(1+X²)) + Y/√(1+Y²)·atan(X/√(1+Y²))]; X = 2, Y = 3: 0.2175752061.
TEST(FormFactor, PointUnderARectanglesCornerMatchesTheClosedForm) {
    const std::array<dvec3, 4> rectangle{dvec3(0, 0, 1), dvec3(0, 3, 1), dvec3(2, 3, 1), dvec3(2, 0, 1)};  // faces −z
    EXPECT_NEAR(pointToPolygon(dvec3(0), dvec3(0, 0, 1), rectangle), 0.217575206107758, 1e-14);
    // Seen from behind, or with the receiver turned away, nothing.
    EXPECT_EQ(pointToPolygon(dvec3(0, 0, 2), dvec3(0, 0, -1), rectangle), 0.0);
    EXPECT_EQ(pointToPolygon(dvec3(0), dvec3(0, 0, -1), rectangle), 0.0);
    // In its own plane: edge-on, nothing.
    EXPECT_EQ(pointToPolygon(dvec3(5, 5, 1), dvec3(0, 0, 1), rectangle), 0.0);
}

// Howell B-13: a differential area on the axis of a parallel disk of radius R at height h sees
// F = R²/(R² + h²); the disk as a regular polygon of 4096 sides (its factor differs from the
// disk's by the area missing between them, (2π/N)²/6 relatively).
TEST(FormFactor, PointOnTheAxisOfADiskMatchesTheClosedForm) {
    const int sides = 4096;
    const double R = 1.5, h = 0.8;
    std::vector<dvec3> disk;
    for (int k = 0; k < sides; ++k) {
        const double phi = -2.0 * kPi * k / sides;  // clockwise seen from above: faces down
        disk.push_back(dvec3(R * std::cos(phi), R * std::sin(phi), h));
    }
    const double polygonArea_ = polygonArea(disk), diskArea = kPi * R * R;
    // The inscribed polygon's factor, from the disk's with its radius scaled to the same area.
    const double Re2 = R * R * polygonArea_ / diskArea;
    EXPECT_NEAR(pointToPolygon(dvec3(0), dvec3(0, 0, 1), disk), R * R / (R * R + h * h), 2e-6);
    EXPECT_NEAR(pointToPolygon(dvec3(0), dvec3(0, 0, 1), disk), Re2 / (Re2 + h * h), 2e-7);
}

// A polygon partly below the receiver's horizon counts only its part above: the same as the
// polygon cut there by hand.
TEST(FormFactor, APolygonCrossingTheHorizonCountsItsVisiblePartOnly) {
    // A wall in the plane x = 1 facing −x, from z = −1 to 1: the receiver at the origin facing +z
    // sees its upper half.
    const std::array<dvec3, 4> wall{dvec3(1, -1, -1), dvec3(1, -1, 1), dvec3(1, 1, 1), dvec3(1, 1, -1)};
    const std::array<dvec3, 4> upper{dvec3(1, -1, 0), dvec3(1, -1, 1), dvec3(1, 1, 1), dvec3(1, 1, 0)};
    const double whole = pointToPolygon(dvec3(0), dvec3(0, 0, 1), wall);
    EXPECT_GT(whole, 0.05);
    EXPECT_NEAR(whole, pointToPolygon(dvec3(0), dvec3(0, 0, 1), upper), 1e-15);
}

// Howell B-11: two directly opposed unit squares a unit apart: 0.1998248957.
TEST(FormFactor, ParallelUnitSquaresAUnitApart) {
    const std::array<dvec3, 4> bottom{dvec3(0, 0, 0), dvec3(1, 0, 0), dvec3(1, 1, 0), dvec3(0, 1, 0)};  // faces +z
    const std::array<dvec3, 4> top{dvec3(0, 0, 1), dvec3(0, 1, 1), dvec3(1, 1, 1), dvec3(1, 0, 1)};     // faces −z
    EXPECT_NEAR(polygonToPolygon(squareTriangles(bottom), top), 0.199824895698387, 1e-9);
    EXPECT_NEAR(polygonToPolygon(squareTriangles(top), bottom), 0.199824895698387, 1e-9);
}

// Howell C-14: two unit squares at a right angle sharing an edge: 0.2000437761 — the integrand's
// slope is unbounded at the shared edge, which the adaptive quadrature follows.
TEST(FormFactor, PerpendicularUnitSquaresSharingAnEdge) {
    const std::array<dvec3, 4> floor{dvec3(0, 0, 0), dvec3(1, 0, 0), dvec3(1, 1, 0), dvec3(0, 1, 0)};  // faces +z
    const std::array<dvec3, 4> wall{dvec3(0, 0, 0), dvec3(0, 0, 1), dvec3(1, 0, 1), dvec3(1, 0, 0)};   // faces +y
    EXPECT_NEAR(polygonToPolygon(squareTriangles(floor), wall), 0.200043776075403, 1e-8);
    EXPECT_NEAR(polygonToPolygon(squareTriangles(wall), floor), 0.200043776075403, 1e-8);
}

// Reciprocity, A_i F_ij = A_j F_ji, for triangles of different sizes and orientations.
TEST(FormFactor, ReciprocityHoldsBetweenUnequalTriangles) {
    const Tri small{dvec3(0, 0, 0), dvec3(0.3, 0, 0), dvec3(0, 0.4, 0)};            // faces +z
    const Tri large{dvec3(-1, 2, 1.5), dvec3(2, 1, 0.5), dvec3(1, -1, 2.5)};        // faces down-ish
    ASSERT_LT(polygonNormal(large).z, 0.0);
    const double fsl = triangleToPolygon(small[0], small[1], small[2], large, 1e-12);
    const double fls = triangleToPolygon(large[0], large[1], large[2], small, 1e-12);
    ASSERT_GT(fsl, 0.01);
    EXPECT_NEAR(polygonArea(small) * fsl, polygonArea(large) * fls, 1e-10);
}

// In a closed cube every point sees all of the inside: each face's factors to the other faces sum to
// 1 (Lambert's contour integrals over a closed surface), and opposite faces see 0.1998, adjacent
// 0.2000 (the two tests above), 0.1998 + 4 × 0.2000 = 1.
TEST(FormFactor, TheRowsOfAClosedCubeSumToOne) {
    // The six faces of the unit cube, facing inwards.
    const std::array<std::array<dvec3, 4>, 6> faces{{
        {dvec3(0, 0, 0), dvec3(1, 0, 0), dvec3(1, 1, 0), dvec3(0, 1, 0)},  // z = 0, faces +z
        {dvec3(0, 0, 1), dvec3(0, 1, 1), dvec3(1, 1, 1), dvec3(1, 0, 1)},  // z = 1, faces −z
        {dvec3(0, 0, 0), dvec3(0, 0, 1), dvec3(1, 0, 1), dvec3(1, 0, 0)},  // y = 0, faces +y
        {dvec3(0, 1, 0), dvec3(1, 1, 0), dvec3(1, 1, 1), dvec3(0, 1, 1)},  // y = 1, faces −y
        {dvec3(0, 0, 0), dvec3(0, 1, 0), dvec3(0, 1, 1), dvec3(0, 0, 1)},  // x = 0, faces +x
        {dvec3(1, 0, 0), dvec3(1, 0, 1), dvec3(1, 1, 1), dvec3(1, 1, 0)},  // x = 1, faces −x
    }};
    for (const auto& f : faces) ASSERT_GT(glm::dot(polygonNormal(f), dvec3(0.5) - f[0]), 0.0);
    for (size_t i = 0; i < faces.size(); ++i) {
        double row = 0.0;
        for (size_t j = 0; j < faces.size(); ++j)
            if (j != i) row += polygonToPolygon(squareTriangles(faces[i]), faces[j]);
        EXPECT_NEAR(row, 1.0, 1e-9) << "face " << i;
    }
}

// Far away the rule on the triangle (no arc tangent) is the closed form's value: a tilted triangle
// seen from a tilted point at 4, 8 and 16 of its edges; the rule's error falls as the sixth power
// of the distance's inverse (a degree-5 rule).
TEST(FormFactor, TheRuleOnAFarTriangleMatchesTheClosedForm) {
    const Tri t{dvec3(0.0, 0.0, 0.0), dvec3(1.0, 0.1, 0.2), dvec3(0.2, 0.9, -0.1)};
    const dvec3 front = polygonNormal(t);
    std::array<dvec3, 7> rule;
    for (size_t k = 0; k < kTriangleRule.size(); ++k) rule[k] = kTriangleRule[k].on(t);
    const dvec3 centroid = (t[0] + t[1] + t[2]) / 3.0;
    double previous = 1.0;
    for (double distance : {4.0, 8.0, 16.0}) {
        const dvec3 x = centroid + distance * glm::normalize(front + dvec3(0.3, -0.2, 0.0));
        const dvec3 n = glm::normalize(centroid - x + dvec3(0.1, 0.2, -0.3) * distance);
        const double exact = pointToTriangle(x, n, t, front);
        const double error = std::fabs(pointToTriangleByRule(x, n, rule, front, polygonArea(t)) / exact - 1.0);
        std::printf("%g edges away: F %.6e, the rule's relative error %.1e\n", distance, exact, error);
        EXPECT_LT(error, 1e-5);
        EXPECT_LT(error, previous / 16.0);  // at least the fourth power; the sixth expected
        previous = error;
    }
}
