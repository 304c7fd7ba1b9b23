/// @file geometry_kernels_test.cpp
/// @brief The kernels of the region measurement against closed forms: the
///        segment two triangles share, the closest feature of a triangle,
///        signed distance and inside test of closed meshes (either winding),
///        and the branch-and-bound depth of triangles inside a box and a sphere.

#include "region_shapes.hpp"

#include "usdksl/geometry/triangle_triangle_static.hpp"
#include "usdksl/regions/closed_surface.hpp"
#include "usdksl/regions/closest_feature.hpp"
#include "usdksl/regions/inside_depth.hpp"
#include "usdksl/regions/intersection_segment.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>

using namespace usdksl;
using namespace usdksl::region_shapes;

namespace {

using Tri = std::array<Vec3, 3>;

/// Signed distance to the box [-h, h]^3 (positive inside), closed form.
double box_depth(const Vec3& p, const Vec3& h) {
    const Vec3 q = p.cwiseAbs() - h;
    if ((q.array() <= 0.0).all()) return -q.maxCoeff();
    return -q.cwiseMax(0.0).norm();
}

/// A closed surface and the storage it points into.
struct Surface {
    StoredMesh mesh;
    MeshView view;
    std::vector<Vec3> points;
    ClosedMeshTopology topology;
    ClosedSurface surface;

    explicit Surface(StoredMesh m) : mesh(std::move(m)) {
        view = mesh.view();
        points = mesh.sample(0);
        topology = build_closed_mesh_topology(view, points.data());
        surface.update(view, topology, points.data());
    }
};

/// Distance from `centre` to the nearest point of the mesh: the faceted
/// surface of a sphere lies between it and the radius.
double inscribed_radius(const StoredMesh& mesh, const Vec3& centre) {
    const std::vector<Vec3> p = mesh.sample(0);
    double least = std::numeric_limits<double>::infinity();
    for (size_t t = 0; t < mesh.triangles.size(); t += 3) {
        const ClosestOnTriangle on =
            closest_on_triangle(centre, p[mesh.triangles[t]], p[mesh.triangles[t + 1]], p[mesh.triangles[t + 2]]);
        least = std::min(least, std::sqrt(on.distance_squared));
    }
    return least;
}

double longest_edge(const Tri& t) {
    return std::max({(t[1] - t[0]).norm(), (t[2] - t[1]).norm(), (t[0] - t[2]).norm()});
}

} // namespace

TEST(IntersectionSegment, PerpendicularTrianglesShareTheExpectedSegment) {
    const Tri a = {Vec3(-2, -2, 0), Vec3(4, -2, 0), Vec3(-2, 4, 0)};
    const Tri b = {Vec3(-1, 0, -1), Vec3(1, 0, -1), Vec3(0, 0, 1)};
    const IntersectionSegment s = triangle_intersection_segment(a, b);
    ASSERT_TRUE(s.meets);
    EXPECT_NEAR(s.length(), 1.0, 1e-15);
    EXPECT_NEAR(std::min(s.p.x(), s.q.x()), -0.5, 1e-15);
    EXPECT_NEAR(std::max(s.p.x(), s.q.x()), 0.5, 1e-15);
    EXPECT_EQ(s.p.z(), 0.0);
    // swapping the triangles gives the same segment
    EXPECT_NEAR(triangle_intersection_segment(b, a).length(), 1.0, 1e-15);
}

TEST(IntersectionSegment, ClippedByTheSmallerTriangle) {
    // a meets the line y = 0, z = 0 over x in [0, 1]; b's cut is x in [-0.5, 0.5]
    const Tri a = {Vec3(0, -1, 0), Vec3(2, -1, 0), Vec3(0, 1, 0)};
    const Tri b = {Vec3(-1, 0, -1), Vec3(1, 0, -1), Vec3(0, 0, 1)};
    const IntersectionSegment s = triangle_intersection_segment(a, b);
    ASSERT_TRUE(s.meets);
    EXPECT_NEAR(s.length(), 0.5, 1e-15);
    EXPECT_NEAR(std::min(s.p.x(), s.q.x()), 0.0, 1e-15);
}

TEST(IntersectionSegment, AnEdgeInTheOtherPlaneIsFlagged) {
    const Tri a = {Vec3(-2, -2, 0), Vec3(4, -2, 0), Vec3(-2, 4, 0)};
    // b's edge from (-1, 0, 0) to (1, 0, 0) lies in a's plane; its third corner is above
    const Tri b = {Vec3(-1, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, 1)};
    const IntersectionSegment s = triangle_intersection_segment(a, b);
    ASSERT_TRUE(s.meets);
    EXPECT_NEAR(s.length(), 2.0, 1e-15);
    EXPECT_TRUE(s.along_edge_of_b);
    EXPECT_FALSE(s.along_edge_of_a);
    const IntersectionSegment crossing = triangle_intersection_segment(a, {Vec3(-1, 0, -1), Vec3(1, 0, -1), Vec3(0, 0, 1)});
    EXPECT_FALSE(crossing.along_edge_of_a || crossing.along_edge_of_b);
}

TEST(IntersectionSegment, TouchingApartAndCoplanar) {
    const Tri a = {Vec3(-2, -2, 0), Vec3(4, -2, 0), Vec3(-2, 4, 0)};
    const Tri apex_down = {Vec3(-1, 0, 1), Vec3(1, 0, 1), Vec3(0, 0, 0)};
    const IntersectionSegment touch = triangle_intersection_segment(a, apex_down);
    ASSERT_TRUE(touch.meets) << "a corner resting on the other triangle is one shared point";
    EXPECT_EQ(touch.length(), 0.0);
    EXPECT_EQ(touch.p, Vec3(0, 0, 0));
    const Tri above = {Vec3(-1, 0, 0.5), Vec3(1, 0, 0.5), Vec3(0, 0, 1)};
    EXPECT_FALSE(triangle_intersection_segment(a, above).meets);
    const Tri coplanar = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    EXPECT_FALSE(triangle_intersection_segment(a, coplanar).meets) << "a coplanar overlap is an area, not a curve";
    // straddling each other's planes without meeting: b's cut lies beside a
    const Tri beside = {Vec3(5, 5, -1), Vec3(6, 5, -1), Vec3(5.5, 5, 1)};
    EXPECT_FALSE(triangle_intersection_segment(a, beside).meets);
}

TEST(IntersectionSegment, RandomPairsAgreeWithTheExactTestAndLieOnBoth) {
    std::mt19937_64 random(5);
    std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
    const auto random_triangle = [&]() {
        Tri t;
        for (Vec3& v : t) v = Vec3(coordinate(random), coordinate(random), coordinate(random));
        return t;
    };
    int crossing = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        const Tri a = random_triangle(), b = random_triangle();
        const IntersectionSegment s = triangle_intersection_segment(a, b);
        ASSERT_EQ(s.meets, triangles_intersect_static(a, b, 0.0)) << "trial " << trial;
        if (!s.meets) continue;
        ++crossing;
        for (const Vec3& p : {s.p, s.q, Vec3(0.5 * (s.p + s.q))}) {
            EXPECT_LT(closest_on_triangle(p, a[0], a[1], a[2]).distance_squared, 1e-22);
            EXPECT_LT(closest_on_triangle(p, b[0], b[1], b[2]).distance_squared, 1e-22);
        }
        // the segment is the whole shared part: points just beyond its ends leave one triangle
        const Vec3 d = s.q - s.p;
        if (d.norm() > 1e-6) {
            const Vec3 beyond_q = s.q + 1e-4 * d.normalized(), beyond_p = s.p - 1e-4 * d.normalized();
            for (const Vec3& p : {beyond_p, beyond_q}) {
                const double off = std::max(closest_on_triangle(p, a[0], a[1], a[2]).distance_squared,
                                            closest_on_triangle(p, b[0], b[1], b[2]).distance_squared);
                EXPECT_GT(off, 1e-16) << "trial " << trial;
            }
        }
    }
    EXPECT_GT(crossing, 2000);
}

TEST(ClosestFeature, InteriorEdgesAndCorners) {
    const Vec3 a(0, 0, 0), b(2, 0, 0), c(0, 2, 0);
    ClosestOnTriangle on = closest_on_triangle(Vec3(0.5, 0.5, 3), a, b, c);
    EXPECT_EQ(on.feature, TriangleFeature::Interior);
    EXPECT_DOUBLE_EQ(on.distance_squared, 9.0);
    on = closest_on_triangle(Vec3(1, -1, 1), a, b, c);
    EXPECT_EQ(on.feature, TriangleFeature::Edge01);
    EXPECT_DOUBLE_EQ(on.distance_squared, 2.0);
    on = closest_on_triangle(Vec3(2, 2, 0), a, b, c);
    EXPECT_EQ(on.feature, TriangleFeature::Edge12);
    EXPECT_DOUBLE_EQ(on.distance_squared, 2.0);
    on = closest_on_triangle(Vec3(-1, 1, 0), a, b, c);
    EXPECT_EQ(on.feature, TriangleFeature::Edge20);
    on = closest_on_triangle(Vec3(-1, -1, -1), a, b, c);
    EXPECT_EQ(on.feature, TriangleFeature::Corner0);
    EXPECT_DOUBLE_EQ(on.distance_squared, 3.0);
    EXPECT_EQ(closest_on_triangle(Vec3(3, -1, 0), a, b, c).feature, TriangleFeature::Corner1);
    EXPECT_EQ(closest_on_triangle(Vec3(-1, 3, 0), a, b, c).feature, TriangleFeature::Corner2);
}

TEST(ClosedSurface, SignedDistanceToABoxIsTheClosedFormEitherWinding) {
    const Vec3 h(1.0, 0.5, 2.0);
    Surface outward(box(Vec3::Zero(), h));
    Surface inward(reversed(box(Vec3::Zero(), h)));
    EXPECT_EQ(outward.surface.orientation(), 1.0);
    EXPECT_EQ(inward.surface.orientation(), -1.0);
    std::mt19937_64 random(3);
    std::uniform_real_distribution<double> coordinate(-3.0, 3.0);
    int inside = 0;
    for (int trial = 0; trial < 5000; ++trial) {
        const Vec3 p(coordinate(random), coordinate(random), coordinate(random));
        const double expected = box_depth(p, h);
        ASSERT_NEAR(outward.surface.signed_distance(p), expected, 1e-12) << p.transpose();
        ASSERT_NEAR(inward.surface.signed_distance(p), expected, 1e-12) << p.transpose();
        inside += expected > 0.0;
    }
    EXPECT_GT(inside, 100);
    // exactly along the directions where the closest feature is a corner or an edge
    EXPECT_NEAR(outward.surface.signed_distance(Vec3(2, 1.5, 3)), -std::sqrt(3.0), 1e-12);
    EXPECT_NEAR(outward.surface.signed_distance(Vec3(0.99, 0.49, 0)), 0.01, 1e-12);
    EXPECT_NEAR(outward.surface.signed_distance(Vec3(0.9, 0.45, 1.9)), 0.05, 1e-12);
}

TEST(ClosedSurface, SignedDistanceToASphereWithinItsFaceting) {
    const double r = 2.0;
    Surface sphere(icosphere(Vec3(1, -1, 0.5), r, 4));
    // the faceted surface lies between the inscribed radius and r
    const double sagitta = r - inscribed_radius(sphere.mesh, Vec3(1, -1, 0.5));
    ASSERT_LT(sagitta, 0.01 * r);
    std::mt19937_64 random(8);
    std::uniform_real_distribution<double> coordinate(-3.5, 3.5);
    for (int trial = 0; trial < 2000; ++trial) {
        const Vec3 p = Vec3(1, -1, 0.5) + Vec3(coordinate(random), coordinate(random), coordinate(random));
        const double expected = r - (p - Vec3(1, -1, 0.5)).norm();
        ASSERT_NEAR(sphere.surface.signed_distance(p), expected, sagitta) << p.transpose();
    }
}

namespace {

/// A cube [-1, 1]^3 whose top is a fan of four triangles around a vertex
/// pushed down and aside to `apex`: a concave vertex with very unequal angles.
StoredMesh dented_cube(const Vec3& apex) {
    StoredMesh mesh = box(Vec3::Zero(), Vec3(1, 1, 1));
    // drop the top quad (face 1: triangles 2 and 3) and fan its corners 4, 5, 7, 6 around the apex
    mesh.triangles.erase(mesh.triangles.begin() + 6, mesh.triangles.begin() + 12);
    mesh.triangle_face.erase(mesh.triangle_face.begin() + 2, mesh.triangle_face.begin() + 4);
    mesh.points.insert(mesh.points.end(), {apex[0], apex[1], apex[2]});
    mesh.vertex_count = 9;
    const int ring[4] = {4, 5, 7, 6};
    for (int i = 0; i < 4; ++i) {
        mesh.triangles.insert(mesh.triangles.end(), {ring[i], ring[(i + 1) % 4], 8});
        mesh.triangle_face.push_back(6 + i);
    }
    return mesh;
}

/// Generalized winding number of a closed triangle soup around p (about 1
/// inside for outward winding, 0 outside), an inside test of its own.
double winding_number(const std::vector<Vec3>& points, const std::vector<int32_t>& triangles, const Vec3& p) {
    double sum = 0.0;
    for (size_t t = 0; t < triangles.size(); t += 3) {
        const Vec3 a = points[triangles[t]] - p, b = points[triangles[t + 1]] - p, c = points[triangles[t + 2]] - p;
        const double la = a.norm(), lb = b.norm(), lc = c.norm();
        sum += 2.0 * std::atan2(a.dot(b.cross(c)), la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb);
    }
    return sum / (4.0 * M_PI);
}

} // namespace

TEST(ClosedSurface, TheInsideTestHoldsOnADentedCube) {
    // Points nearest to the apex are decided by its pseudonormal; the answer
    // is held to a winding number, on a mesh that is not convex.
    const Vec3 apex(0.7, 0.55, -0.2);
    Surface dented(dented_cube(apex));
    std::mt19937_64 random(21);
    std::normal_distribution<double> near(0.0, 0.3);
    std::uniform_real_distribution<double> anywhere(-1.5, 1.5);
    int decided_by_the_apex = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        const Vec3 p = trial % 2 ? Vec3(apex + Vec3(near(random), near(random), near(random)))
                                 : Vec3(anywhere(random), anywhere(random), anywhere(random));
        const ClosedSurface::Closest c = dented.surface.closest(p);
        if (c.on.distance_squared < 1e-12) continue;
        const bool inside = winding_number(dented.points, dented.mesh.triangles, p) > 0.5;
        ASSERT_EQ(dented.surface.signed_distance(p) > 0.0, inside) << p.transpose();
        decided_by_the_apex += c.on.point == apex;
    }
    EXPECT_GT(decided_by_the_apex, 100);
}

TEST(ClosedSurface, MeetsIsTheExactTestAgainstEveryTriangle) {
    Surface cube(box(Vec3::Zero(), Vec3(1, 1, 1)));
    EXPECT_TRUE(cube.surface.meets({Vec3(0, 0, 0.5), Vec3(3, 0, 0.5), Vec3(0, 3, 0.5)}));
    EXPECT_FALSE(cube.surface.meets({Vec3(-0.5, -0.5, 0), Vec3(0.5, -0.5, 0), Vec3(0, 0.5, 0)})) << "wholly inside";
    EXPECT_FALSE(cube.surface.meets({Vec3(2, 2, 2), Vec3(3, 2, 2), Vec3(2, 3, 2)})) << "wholly outside";
    EXPECT_TRUE(cube.surface.meets({Vec3(1, 1, 1), Vec3(3, 2, 2), Vec3(2, 3, 2)})) << "touching a corner";
}

TEST(InsideDepth, SheetThroughABoxReachesTheCentre) {
    Surface cube(box(Vec3::Zero(), Vec3(1, 1, 1)));
    for (double z : {-0.7, -0.2, 0.0, 0.35, 0.9}) {
        // one large triangle whose plane z cuts the box; its deepest point is (0, 0, z), not a corner
        const std::vector<Tri> tris = {{Vec3(-3, -2.2, z), Vec3(3.3, -2, z), Vec3(0.1, 3.1, z)}};
        const InsideDepth d = deepest_inside(cube.surface, tris);
        const double expected = 1.0 - std::abs(z);
        const double accuracy = DEPTH_RELATIVE_ACCURACY * longest_edge(tris[0]);
        EXPECT_LE(d.depth, expected + 1e-12) << z;
        EXPECT_GE(d.depth + accuracy, expected) << z;
        EXPECT_TRUE(d.any_inside);
        EXPECT_NEAR(box_depth(d.deepest, Vec3(1, 1, 1)), d.depth, 1e-12) << "the depth is that of a real point";
    }
}

TEST(InsideDepth, TriangleOverAnEdgeWithEveryCornerOutside) {
    Surface cube(box(Vec3::Zero(), Vec3(1, 1, 1)));
    for (double h : {0.05, 0.2, 0.6}) {
        // plane x + z = 2 - h cuts off the edge x = z = 1; deepest point depth h / 2
        const Tri t = {Vec3(2, -3, -h), Vec3(2, 3, -h), Vec3(-h, 0, 2)};
        for (const Vec3& v : t) ASSERT_LT(box_depth(v, Vec3(1, 1, 1)), 0.0);
        const InsideDepth d = deepest_inside(cube.surface, {t});
        const double accuracy = DEPTH_RELATIVE_ACCURACY * longest_edge(t);
        EXPECT_LE(d.depth, h / 2 + 1e-12) << h;
        EXPECT_GE(d.depth + accuracy, h / 2) << h;
        EXPECT_GT(d.depth, 0.0);
    }
}

TEST(InsideDepth, OutsideTrianglesCostOneQueryAndReportNothing) {
    Surface cube(box(Vec3::Zero(), Vec3(1, 1, 1)));
    // resting 0.001 above the top face: no crossing, so no splitting
    const Tri t = {Vec3(-3, -3, 1.001), Vec3(3, -3, 1.001), Vec3(0, 3, 1.001)};
    const InsideDepth d = deepest_inside(cube.surface, {t});
    EXPECT_EQ(d.depth, 0.0);
    EXPECT_FALSE(d.any_inside);
    EXPECT_EQ(d.evaluations, 1);
}

TEST(InsideDepth, PlaneThroughASphere) {
    const double r = 1.0;
    Surface sphere(icosphere(Vec3::Zero(), r, 4));
    const double faceting = r - inscribed_radius(sphere.mesh, Vec3::Zero());
    for (double z : {0.0, 0.3, -0.6}) {
        const Tri t = {Vec3(-2, -2, z), Vec3(2.5, -2, z), Vec3(0, 2.5, z)};
        const InsideDepth d = deepest_inside(sphere.surface, {t});
        const double expected = r - std::abs(z);  // at (0, 0, z), straight to the closest pole
        const double accuracy = DEPTH_RELATIVE_ACCURACY * longest_edge(t);
        EXPECT_LE(d.depth, expected + faceting) << z;
        EXPECT_GE(d.depth + accuracy + faceting, expected) << z;
    }
}
