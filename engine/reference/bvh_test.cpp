#include "reference/bvh.h"

#include "support/scene_builders.h"

#include <gtest/gtest.h>

#include <random>

using namespace metamer;
using namespace metamer::test;

namespace {

std::optional<RayHit> bruteForce(const std::vector<BvhTriangle>& tris, const Ray& ray, double tMin) {
    std::optional<RayHit> best;
    double tBest = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < tris.size(); ++i) {
        if (auto h = intersectTriangle(tris[i], ray, tMin, tBest)) {
            h->index = static_cast<uint32_t>(i);
            tBest = h->t;
            best = h;
        }
    }
    return best;
}

Ray rayTowards(glm::dvec3 origin, glm::dvec3 target) {
    return Ray{origin, glm::normalize(target - origin)};
}

}  // namespace

TEST(Bvh, NearestHitMatchesBruteForceOnRandomRays) {
    std::mt19937_64 rng(12345);
    std::uniform_real_distribution<double> unit(-1.0, 1.0), small(-0.15, 0.15), bary(0.0, 1.0);
    std::vector<BvhTriangle> tris;
    for (int i = 0; i < 2000; ++i) {
        glm::dvec3 c(unit(rng), unit(rng), unit(rng));
        BvhTriangle t;
        t.p0 = c + glm::dvec3(small(rng), small(rng), small(rng));
        t.p1 = c + glm::dvec3(small(rng), small(rng), small(rng));
        t.p2 = c + glm::dvec3(small(rng), small(rng), small(rng));
        t.triangle = i;
        tris.push_back(t);
    }
    Bvh bvh(tris);
    ASSERT_EQ(bvh.triangles().size(), tris.size());
    EXPECT_GT(bvh.depth(), 5);

    int hits = 0;
    const int kRays = 6000;
    for (int k = 0; k < kRays; ++k) {
        Ray ray;
        ray.origin = glm::dvec3(2.5 * unit(rng), 2.5 * unit(rng), 2.5 * unit(rng));
        if (k % 3 == 0) {
            // Random direction.
            ray.direction = glm::normalize(glm::dvec3(unit(rng), unit(rng), unit(rng)));
        } else if (k % 3 == 1) {
            // Aimed at a random point of a random triangle: mostly hits.
            const BvhTriangle& t = tris[rng() % tris.size()];
            double a = bary(rng), b = bary(rng);
            if (a + b > 1) a = 1 - a, b = 1 - b;
            ray = rayTowards(ray.origin, t.p0 + a * (t.p1 - t.p0) + b * (t.p2 - t.p0));
        } else {
            // Along an axis: the slab test's parallel case (1/0 = inf).
            glm::dvec3 d(0.0);
            d[(k / 3) % 3] = (k & 1) ? 1.0 : -1.0;
            ray.direction = d;
        }
        auto fast = bvh.intersect(ray, 1e-9);
        auto slow = bruteForce(bvh.triangles(), ray, 1e-9);
        ASSERT_EQ(fast.has_value(), slow.has_value()) << "ray " << k;
        if (!fast) continue;
        ++hits;
        EXPECT_EQ(fast->index, slow->index) << "ray " << k;
        EXPECT_EQ(fast->t, slow->t) << "ray " << k;
        EXPECT_EQ(fast->b1, slow->b1) << "ray " << k;
    }
    EXPECT_GT(hits, kRays / 3);
}

TEST(Bvh, RaysThroughTheDiagonalOfAQuadNeverSlipThrough) {
    // A quad's two triangles share the diagonal; rays exactly on it, and a hair either side of
    // it, must all hit. Several quad sizes and positions so rounding varies.
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    int misses = 0, rays = 0;
    for (double size : {1.0, 0.37, 3.3e-3, 12.5}) {
        for (glm::dvec3 centre : {glm::dvec3(0.0), glm::dvec3(0.1, -0.7, 2.3), glm::dvec3(113.7, 5.2, -41.9)}) {
            Scene s;
            s.meshes.push_back(quad(centre, {0.2, -0.3, 1.0}, size, 0.6 * size));
            Bvh bvh(Bvh::collectTriangles(s));
            const Mesh& m = s.meshes[0];
            const glm::dvec3 a = m.positions[0], c = m.positions[2];  // the shared diagonal
            const glm::dvec3 n = glm::normalize(glm::dvec3(0.2, -0.3, 1.0));
            for (int k = 0; k < 400; ++k) {
                const double t = 0.005 + 0.99 * u01(rng);
                const glm::dvec3 onEdge = a + t * (c - a);
                const glm::dvec3 side = glm::normalize(glm::cross(c - a, n));
                for (double off : {0.0, 1e-17, -1e-17, 1e-15, -1e-15}) {
                    const glm::dvec3 target = onEdge + off * size * side;
                    // Straight on, and from an oblique far-away eye.
                    for (glm::dvec3 eye : {target + 5.0 * n, centre + glm::dvec3(3.0, 2.0, 9.0) * size}) {
                        ++rays;
                        if (!bvh.intersect(rayTowards(eye, target))) ++misses;
                    }
                }
            }
        }
    }
    EXPECT_EQ(misses, 0) << "of " << rays;
}

TEST(Bvh, DenseRaysThroughABumpyMeshFindNoGaps) {
    // A 40×40-cell height field with jittered vertices: every ray aimed inside its footprint,
    // including exactly at vertices and edge midpoints, must hit.
    std::mt19937_64 rng(99);
    std::uniform_real_distribution<double> jitter(-0.3, 0.3), u01(0.0, 1.0);
    const int N = 40;
    Mesh m;
    for (int j = 0; j <= N; ++j)
        for (int i = 0; i <= N; ++i) {
            const bool border = i == 0 || j == 0 || i == N || j == N;
            const double x = -1.0 + 2.0 * (i + (border ? 0.0 : jitter(rng))) / N;
            const double y = -1.0 + 2.0 * (j + (border ? 0.0 : jitter(rng))) / N;
            m.positions.push_back({x, y, 0.02 * jitter(rng)});
        }
    for (int j = 0; j < N; ++j)
        for (int i = 0; i < N; ++i) {
            const uint32_t a = j * (N + 1) + i, b = a + 1, c = a + N + 2, d = a + N + 1;
            // Alternate the diagonal so both orientations of shared edges occur.
            if ((i + j) % 2) m.indices.insert(m.indices.end(), {a, b, c, a, c, d});
            else m.indices.insert(m.indices.end(), {a, b, d, b, c, d});
        }
    Scene s;
    s.meshes.push_back(m);
    Bvh bvh(Bvh::collectTriangles(s));
    ASSERT_EQ(bvh.triangles().size(), 2u * N * N);

    std::vector<glm::dvec3> targets;
    for (size_t t = 0; t < m.indices.size(); t += 3) {
        const glm::dvec3 p0 = m.positions[m.indices[t]], p1 = m.positions[m.indices[t + 1]],
                         p2 = m.positions[m.indices[t + 2]];
        for (const glm::dvec3& p : {p0, 0.5 * (p0 + p1), 0.5 * (p1 + p2), 0.5 * (p2 + p0)})
            if (std::abs(p.x) < 0.97 && std::abs(p.y) < 0.97) targets.push_back(p);
    }
    for (int k = 0; k < 20000; ++k) targets.push_back({1.9 * u01(rng) - 0.95, 1.9 * u01(rng) - 0.95, 0.0});

    int misses = 0;
    const glm::dvec3 eyes[] = {{0.0, 0.0, 6.0}, {0.3, -0.2, 3.0}, {-2.0, 1.0, 10.0}};
    for (const glm::dvec3& eye : eyes)
        for (const glm::dvec3& t : targets)
            if (!bvh.intersect(rayTowards(eye, t))) ++misses;
    EXPECT_EQ(misses, 0) << "of " << 3 * targets.size();
}

TEST(Bvh, RespectsTheRayInterval) {
    Scene s;
    s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 1.0, 1.0));
    Bvh bvh(Bvh::collectTriangles(s));
    const Ray ray{{0.1, 0.2, 1.0}, {0, 0, -1}};
    auto hit = bvh.intersect(ray);
    ASSERT_TRUE(hit);
    EXPECT_DOUBLE_EQ(hit->t, 1.0);
    EXPECT_FALSE(bvh.intersect(ray, 1e-9, 0.999));
    EXPECT_FALSE(bvh.intersect(ray, 1.001));
    EXPECT_FALSE(bvh.intersect(Ray{{0.1, 0.2, 1.0}, {0, 0, 1}}));  // pointing away
    EXPECT_FALSE(bvh.intersect(Ray{{0.1, 0.2, 0.0}, {1, 0, 0}}));  // in the plane
}

TEST(Bvh, NearestOfStackedQuadsWins) {
    Scene s;
    for (int i = 0; i < 10; ++i) s.meshes.push_back(quad({0, 0, 0.1 * i}, {0, 0, 1}, 1.0, 1.0));
    Bvh bvh(Bvh::collectTriangles(s));
    auto down = bvh.intersect(Ray{{0.1, 0.1, 5.0}, {0, 0, -1}});
    ASSERT_TRUE(down);
    EXPECT_EQ(bvh.triangles()[down->index].mesh, 9u);
    auto up = bvh.intersect(Ray{{0.1, 0.1, -5.0}, {0, 0, 1}});
    ASSERT_TRUE(up);
    EXPECT_EQ(bvh.triangles()[up->index].mesh, 0u);
}

TEST(Bvh, CollectTrianglesKeepsMeshAndTriangleIndices) {
    Scene s;
    s.meshes.push_back(quad({0, 0, 0}, {0, 0, 1}, 1.0, 1.0));
    s.meshes.push_back(sphere({0, 0, 0}, 1.0, 8, 4));
    auto tris = Bvh::collectTriangles(s);
    ASSERT_EQ(tris.size(), 2u + 2 * 8 * 3);
    EXPECT_EQ(tris[1].mesh, 0u);
    EXPECT_EQ(tris[1].triangle, 1u);
    EXPECT_EQ(tris[2].mesh, 1u);
    EXPECT_EQ(tris[2].triangle, 0u);
    EXPECT_EQ(tris[2].p0, s.meshes[1].positions[s.meshes[1].indices[0]]);
}

TEST(Bvh, EmptyNeverHits) {
    Bvh bvh(std::vector<BvhTriangle>{});
    EXPECT_FALSE(bvh.intersect(Ray{}));
    EXPECT_EQ(bvh.nodeCount(), 0u);
}

TEST(SceneBuilders, SphereTrianglesFaceOutwards) {
    Mesh m = sphere({1, 2, 3}, 0.5, 16, 8);
    EXPECT_EQ(m.indices.size() / 3, 2u * 16 * 7);
    for (size_t t = 0; t < m.indices.size(); t += 3) {
        const glm::dvec3 p0 = m.positions[m.indices[t]], p1 = m.positions[m.indices[t + 1]],
                         p2 = m.positions[m.indices[t + 2]];
        const glm::dvec3 ng = glm::cross(p1 - p0, p2 - p0);
        ASSERT_GT(glm::length(ng), 0.0) << "degenerate triangle " << t / 3;
        EXPECT_GT(glm::dot(ng, (p0 + p1 + p2) / 3.0 - glm::dvec3(1, 2, 3)), 0.0) << t / 3;
    }
}

TEST(SceneBuilders, QuadIsCounterClockwiseAroundItsNormal) {
    for (glm::dvec3 n : {glm::dvec3(0, 0, 1), glm::dvec3(0, 1, 0), glm::dvec3(0, -1, 0), glm::dvec3(1, 2, -3)}) {
        Mesh m = quad({0.5, 0, 0}, n, 2.0, 1.0);
        for (size_t t = 0; t < 6; t += 3) {
            const glm::dvec3 p0 = m.positions[m.indices[t]], p1 = m.positions[m.indices[t + 1]],
                             p2 = m.positions[m.indices[t + 2]];
            const glm::dvec3 ng = glm::normalize(glm::cross(p1 - p0, p2 - p0));
            EXPECT_NEAR(glm::dot(ng, glm::normalize(n)), 1.0, 1e-12);
        }
        EXPECT_NEAR(glm::length(m.positions[1] - m.positions[0]), 2.0, 1e-12);  // width
        EXPECT_NEAR(glm::length(m.positions[3] - m.positions[0]), 1.0, 1e-12);  // height
    }
}
