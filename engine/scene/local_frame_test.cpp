#include "scene/local_frame.h"

#include "core/error.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace metamer;

namespace {

// Two triangles spanning the box [lo, hi] (its diagonal as one edge).
Scene boxScene(glm::dvec3 lo, glm::dvec3 hi) {
    Scene s;
    s.file = "frame.json";
    Mesh m;
    m.positions = {lo, hi, {hi.x, lo.y, lo.z}};
    m.indices = {0, 1, 2};
    s.meshes.push_back(m);
    return s;
}

Camera at(glm::dvec3 position) {
    Camera c;
    c.position = position;
    c.target = {0, 0, 0};
    return c;
}

void expectInputError(const std::function<void()>& f, const std::string& key, const std::string& fragment) {
    try {
        f();
        ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        EXPECT_EQ(e.where().file, "frame.json");
        EXPECT_EQ(e.where().key, key) << e.text();
        EXPECT_NE(e.message().find(fragment), std::string::npos) << e.text();
    }
}

}  // namespace

TEST(LocalFrame, OriginIsTheBoxPointNearestTheCameraOrTheCameraInsideIt) {
    const Scene s = boxScene({-1, -2, -3}, {1, 2, 3});
    EXPECT_EQ(localFrameFor(s, at({0.5, 0.25, 0.125})).origin, glm::dvec3(0.5, 0.25, 0.125));  // inside
    EXPECT_EQ(localFrameFor(s, at({10, 1, -20})).origin, glm::dvec3(1, 1, -3));              // outside
    // No vertices: the camera's own position.
    Scene empty;
    EXPECT_EQ(localFrameFor(empty, at({7, 8, 9})).origin, glm::dvec3(7, 8, 9));
    EXPECT_EQ(localFrameFor(empty, at({7, 8, 9})).unitExponent, 0);
}

TEST(LocalFrame, UnitIsThePowerOfTwoNearestTheDiagonal) {
    struct Case {
        double side;  // a cube's side: diagonal side·√3
        int exponent;
    };
    // √3 = 1.73 → 2 (2¹); 2.9·√3 = 5.0 → 4 (2²); 3.7·√3 = 6.4 → 8; 1e-6·√3 → 2⁻¹⁹ (1.9e-6); 1e6·√3 → 2²¹.
    for (const Case& c : {Case{1.0, 1}, Case{2.9, 2}, Case{3.7, 3}, Case{1e-6, -19}, Case{1e6, 21}}) {
        const Scene s = boxScene({0, 0, 0}, glm::dvec3(c.side));
        const LocalFrame f = localFrameFor(s, at({0, 0, 5 * c.side}));
        EXPECT_EQ(f.unitExponent, c.exponent) << c.side;
        EXPECT_EQ(f.unit_m(), std::ldexp(1.0, c.exponent));
        EXPECT_EQ(f.inverseSquareUnit(), std::ldexp(1.0, -2 * c.exponent));
    }
}

TEST(LocalFrame, MovingToTheFrameIsExactWhereTheCoordinatesAllowIt) {
    // A scene 10⁷ m from the world origin with dyadic offsets: the frame's positions are exactly
    // those of the same scene at the origin, and a length is a power-of-two scaling.
    const glm::dvec3 t(1e7, -7.5e6, 5e6);
    const Scene near = boxScene({-1, -1, 0}, {1, 1, 0}), far = boxScene(t + glm::dvec3(-1, -1, 0), t + glm::dvec3(1, 1, 0));
    const glm::dvec3 camera(0.25, -0.5, 2.5), point(0.375, 0.25, 0.625);
    const LocalFrame a = localFrameFor(near, at(camera)), b = localFrameFor(far, at(t + camera));
    EXPECT_EQ(b.unitExponent, a.unitExponent);
    EXPECT_EQ(b.position(t + point), a.position(point));
    EXPECT_EQ(b.position(t + camera), a.position(camera));
    Camera ortho = at(t + camera);
    ortho.height_m = 3.0;
    const Camera local = b.camera(ortho);
    EXPECT_EQ(local.position, a.position(camera));
    EXPECT_EQ(local.height_m, 3.0 / b.unit_m());
    EXPECT_EQ(b.length(1.5), 1.5 / b.unit_m());
}

TEST(LocalFrame, RefusesLengthsBeyondTheSupportedRangeNamingTheKey) {
    expectInputError([] { localFrameFor(boxScene({0, 0, 0}, {1e-16, 0, 0}), at({0, 0, 1e-15})); }, "objects",
                     "the objects span 1e-16 m");
    expectInputError([] { localFrameFor(boxScene({0, 0, 0}, {2e15, 0, 0}), at({0, 0, 1e15})); }, "objects",
                     "Metamer renders scenes from 1e-15 m to 1e+15 m");
    expectInputError([] { localFrameFor(boxScene({0, 0, 0}, {1, 0, 0}), at({0, 0, 1e19})); }, "camera.position",
                     "the camera is 1e+19 m from objects that span 1 m");
    Scene s = boxScene({0, 0, 0}, {1, 0, 0});
    Light l;
    l.type = Light::Type::Point;
    l.position = {0, -2e18, 0};
    l.name = "lights.3";
    s.lights.push_back(l);
    expectInputError([&] { localFrameFor(s, at({0, 0, 2})); }, "lights.3.position", "the light is 2e+18 m");
    // Directional and hemisphere lights have no position; the limits themselves are accepted.
    s.lights[0].type = Light::Type::Directional;
    EXPECT_NO_THROW(localFrameFor(s, at({0, 0, 2})));
    EXPECT_NO_THROW(localFrameFor(boxScene({0, 0, 0}, {1e-15, 0, 0}), at({0, 0, 1e-15})));
    EXPECT_NO_THROW(localFrameFor(boxScene({0, 0, 0}, {1e15, 0, 0}), at({0, 0, 1e15})));
}
