/// @file step_box_tree_test.cpp
/// @brief Throughout every step between consecutive breakpoints, each moving
///        box of the step box tree encloses the vertices under it, probed at
///        many times inside each step; each node's recorded shift holds the
///        displacement of every vertex under it, and is narrow for a mesh
///        that moves rigidly however far it travels; the tree lists exactly
///        the distinct vertices under each node small enough to be asked for
///        a separating plane.

#include "animations.hpp"
#include "usdksl/kinetic/step_box_tree.hpp"

#include <Eigen/Geometry>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <vector>

using namespace usdksl;

namespace {

/// Vertices under each node (brute force, from the topology).
std::vector<std::vector<int32_t>> vertices_under(const BvhTopology& topo, const std::vector<Triangle>& tris) {
    std::vector<std::vector<int32_t>> under(static_cast<size_t>(topo.node_count()));
    for (int32_t node = topo.node_count() - 1; node >= 0; --node) {
        if (topo.is_leaf(node)) {
            const Triangle& t = tris[topo.triangle[node]];
            under[node] = {t[0], t[1], t[2]};
        } else {
            under[node] = under[topo.left[node]];
            under[node].insert(under[node].end(), under[topo.right[node]].begin(), under[topo.right[node]].end());
        }
    }
    return under;
}

/// Largest amount (scene units) by which a vertex sticks out of its node's
/// box (grown by its rounding margin) at time code t, step fraction s: > 0
/// means a box too small.
double worst_overhang(const StepBoxTree& tree, const Flightplans& plans,
                      const std::vector<std::vector<int32_t>>& under, double t, double s) {
    double worst = -std::numeric_limits<double>::infinity();
    for (int32_t node = 0; node < tree.topology().node_count(); ++node) {
        const StepBox& box = tree.box(node);
        for (int axis = 0; axis < 3; ++axis) {
            const double lo = box.lo[0][axis] + s * (box.lo[1][axis] - box.lo[0][axis]);
            const double hi = box.hi[0][axis] + s * (box.hi[1][axis] - box.hi[0][axis]);
            for (int32_t v : under[node]) {
                const double x = plans.coord(v, axis, t);
                worst = std::max({worst, lo - x, x - hi});
            }
        }
    }
    return worst;
}

/// Every breakpoint time of any vertex, in order: the steps' ends.
std::vector<double> breakpoint_times(const Flightplans& plans) {
    std::set<double> breakpoints;
    for (int32_t v = 0; v < plans.vertex_count(); ++v) {
        for (int64_t k = plans.key_begin(v); k < plans.key_end(v); ++k) breakpoints.insert(plans.key_time(v, k));
    }
    return {breakpoints.begin(), breakpoints.end()};
}

/// Fits the tree to every step between the mesh's breakpoints, probes it at
/// many times inside each, and returns the number of steps.
int check_every_step(const MeshAnimation& mesh, bool merge) {
    const Flightplans plans(mesh, merge);
    StepBoxTree tree(plans, mesh.triangles, mesh.times.front());
    const auto under = vertices_under(tree.topology(), mesh.triangles);
    const std::vector<double> times = breakpoint_times(plans);
    constexpr int probes = 13;  // not commensurate with anything in the motion
    int steps = 0;
    for (size_t k = 0; k + 1 < times.size(); ++k) {
        tree.fit(times[k], times[k + 1]);
        ++steps;
        for (int p = 0; p <= probes; ++p) {
            const double s = static_cast<double>(p) / probes;
            const double t = times[k] + s * (times[k + 1] - times[k]);
            EXPECT_LE(worst_overhang(tree, plans, under, t, s), 0.0) << "a box is too small at t = " << t;
        }
    }
    return steps;
}

/// Records every step of the mesh and checks, for each node and each of the
/// last NODE_TRAVEL_AHEAD_STEPS recorded steps, that every vertex under it
/// moved within its shift along each axis. Returns the widest radius
/// relative to the largest displacement (how tight the shifts are).
double check_shifts(const MeshAnimation& mesh, bool merge) {
    const Flightplans plans(mesh, merge);
    StepBoxTree tree(plans, mesh.triangles, mesh.times.front());
    const auto under = vertices_under(tree.topology(), mesh.triangles);
    const std::vector<double> times = breakpoint_times(plans);
    const int64_t steps = static_cast<int64_t>(times.size()) - 1;
    double widest_radius = 0.0, largest_move = 0.0;
    for (int64_t k = 0; k < steps; ++k) {
        tree.record_travel(k, times[k], times[k + 1]);
        for (int64_t back = 0; back < NODE_TRAVEL_AHEAD_STEPS && back <= k; ++back) {
            const int64_t step = k - back;  // still remembered
            for (int32_t node = 0; node < tree.topology().node_count(); ++node) {
                const NodeShift& shift = tree.shift(node, step);
                widest_radius = std::max(widest_radius, static_cast<double>(shift.radius));
                for (int32_t v : under[node]) {
                    for (int axis = 0; axis < 3; ++axis) {
                        const double moved = plans.coord(v, axis, times[step + 1]) - plans.coord(v, axis, times[step]);
                        largest_move = std::max(largest_move, std::abs(moved));
                        EXPECT_LE(std::abs(moved - shift.center[axis]), shift.radius)
                            << "vertex " << v << " leaves the shift of node " << node << " in step " << step;
                    }
                }
            }
        }
    }
    return largest_move > 0.0 ? widest_radius / largest_move : widest_radius;
}

} // namespace

TEST(StepBoxTree, ShiftsHoldEveryVertexDisplacementOfACurvedCloth) {
    EXPECT_GT(check_shifts(animations::folding_cloth(5, 16), false), 0.01);
}

TEST(StepBoxTree, ShiftsHoldEveryVertexDisplacementOnStaggeredMergedBreakpoints) {
    check_shifts(animations::random_walk(45, 20, 99, 0.0), true);
    check_shifts(animations::random_walk(45, 20, 7, 1e-3), false);
}

TEST(StepBoxTree, ShiftsOfARigidlyFallingSheetAreNarrow) {
    // Falling and drifting far per step (a card in free fall): the shift's
    // radius stays at the rounding allowance, so two such sheets falling
    // together are seen to keep their gap.
    const MeshAnimation falling = animations::sheet(6, 12, [](double x, double z, int k) {
        const double t = static_cast<double>(k);
        return Vec3(x + 3.0 * t, 100.0 - 4.9 * t * t, z - 0.5 * t);
    });
    EXPECT_LT(check_shifts(falling, false), 1e-4);
}

TEST(StepBoxTree, BoxesEncloseTheirVerticesThroughoutEveryStepOfACurvedCloth) {
    EXPECT_EQ(check_every_step(animations::folding_cloth(5, 16), false), 15);
}

TEST(StepBoxTree, BoxesEncloseTheirVerticesOnStaggeredMergedBreakpoints) {
    // Merged random walks keep different breakpoints per vertex: a step ends
    // at every breakpoint of any vertex, and vertices that merged their
    // samples move linearly across several steps.
    const int steps = check_every_step(animations::random_walk(45, 20, 99, 0.0), true);
    EXPECT_GT(steps, 5);
    EXPECT_LE(steps, 19);
}

TEST(StepBoxTree, BoxesOfAMeshThatNeverMovesHoldForEveryStep) {
    const MeshAnimation mesh = animations::folding_cloth(3, 1);
    const Flightplans plans(mesh, true);
    StepBoxTree tree(plans, mesh.triangles, 0.0);
    const auto under = vertices_under(tree.topology(), mesh.triangles);
    for (double t0 : {0.0, 3.0, 7.5}) {
        tree.fit(t0, t0 + 1.0);
        EXPECT_LE(worst_overhang(tree, plans, under, t0 + 0.5, 0.5), 0.0);
    }
}

namespace {

/// Checks vertices_under() of every node against the distinct vertices
/// under it (brute force); returns how many nodes have a list.
int check_vertices_under(const MeshAnimation& mesh) {
    const Flightplans plans(mesh, false);
    StepBoxTree tree(plans, mesh.triangles, mesh.times.front());
    tree.index_triangles_under();
    const BvhTopology& topology = tree.topology();
    const auto under = vertices_under(topology, mesh.triangles);
    int listed = 0;
    for (int32_t node = 0; node < topology.node_count(); ++node) {
        const auto [first_triangle, last_triangle] = tree.triangles_under(node);
        const auto [first, last] = tree.vertices_under(node);
        const std::vector<int32_t> distinct = [&] {
            std::set<int32_t> seen(under[node].begin(), under[node].end());
            return std::vector<int32_t>(seen.begin(), seen.end());
        }();
        if (last_triangle - first_triangle > NODE_PLANE_MAX_TRIANGLES) {
            EXPECT_EQ(first, last) << "node " << node << " is too large to be listed";
            continue;
        }
        ++listed;
        std::vector<int32_t> listed_vertices(first, last);
        if (!topology.is_leaf(node)) {
            EXPECT_TRUE(std::is_sorted(listed_vertices.begin(), listed_vertices.end())) << "node " << node;
        }
        std::sort(listed_vertices.begin(), listed_vertices.end());
        EXPECT_EQ(listed_vertices, distinct) << "node " << node;
    }
    return listed;
}

} // namespace

TEST(StepBoxTree, ListsTheDistinctVerticesUnderEveryNodeSmallEnoughForAPlane) {
    // 12 x 12 quads: 288 triangles, so the nodes near the root are too
    // large, and neighbouring subtrees share the vertices on their border.
    const MeshAnimation cloth = animations::folding_cloth(12, 5);
    const int listed = check_vertices_under(cloth);
    EXPECT_GT(listed, 500);
    EXPECT_LT(listed, 2 * static_cast<int>(cloth.triangles.size()) - 1) << "the root must be too large";
    // Triangles that share no vertex, and a triangle that repeats one.
    check_vertices_under(animations::random_walk(45, 4, 3, 0.0));
    MeshAnimation repeated = animations::folding_cloth(2, 5);
    repeated.triangles.push_back({4, 4, 7});
    repeated.triangle_face.push_back(static_cast<int32_t>(repeated.triangle_face.size()));
    EXPECT_EQ(check_vertices_under(repeated), 2 * static_cast<int>(repeated.triangles.size()) - 1);
}

TEST(StepBoxTree, TwoVerticesUnderALeafMoveApartByAtMostTheShiftsDiagonal) {
    // A triangle whose corners move along the axes' diagonal by different
    // amounts each step (the direction in which a per-axis half-width
    // understates a displacement the most): the difference of any two of its
    // vertices' displacements over a step stays within
    // SHIFT_CUBE_DIAGONAL_PER_RADIUS times the leaf's shift radius, and
    // comes within 0.01 scene units of it (the bound is probed where it is
    // tight: twice the radius would not hold).
    MeshAnimation mesh;
    mesh.vertex_count = 3;
    mesh.triangles = {{0, 1, 2}};
    const int samples = 12;
    for (int k = 0; k < samples; ++k) {
        mesh.times.push_back(static_cast<double>(k));
        const double wobble = (k % 2 == 0) ? 1.0 : -1.0;  // a breakpoint at every sample
        const Vec3 corners[3] = {Vec3(0, 0, 0), Vec3(1, 0, 0) + 0.1 * wobble * Vec3(1, 1, 1),
                                 Vec3(0, 1, 0) + 0.05 * k * Vec3(1, 1, 1)};
        for (const Vec3& p : corners)
            for (int axis = 0; axis < 3; ++axis) mesh.points.push_back(p[axis]);
    }
    const Flightplans plans(mesh, false);
    StepBoxTree tree(plans, mesh.triangles, mesh.times.front());
    int32_t leaf = 0;
    while (!tree.topology().is_leaf(leaf)) ++leaf;
    double closest = std::numeric_limits<double>::infinity();
    for (int64_t k = 0; k + 1 < samples; ++k) {
        tree.record_travel(k, mesh.times[k], mesh.times[k + 1]);
        const double bound = SHIFT_CUBE_DIAGONAL_PER_RADIUS * tree.shift(leaf, k).radius;
        for (int32_t i = 0; i < 3; ++i) {
            for (int32_t j = i + 1; j < 3; ++j) {
                const Vec3 moved_i = plans.position(i, mesh.times[k + 1]) - plans.position(i, mesh.times[k]);
                const Vec3 moved_j = plans.position(j, mesh.times[k + 1]) - plans.position(j, mesh.times[k]);
                const double apart = (moved_i - moved_j).norm();
                EXPECT_LE(apart, bound) << "vertices " << i << " and " << j << " in step " << k;
                if (apart > 0.0) closest = std::min(closest, bound - apart);
            }
        }
    }
    EXPECT_LT(closest, 0.01);
}

TEST(StepBoxTree, MeanNormalsFollowEveryFitAndStayForAMeshThatNeverMoves) {
    // A cloth folding over five samples: every node's normal turns from step
    // to step, and each is asked twice a step (the second answer is kept).
    const MeshAnimation cloth = animations::folding_cloth(6, 5);
    const Flightplans plans(cloth, false);
    StepBoxTree tree(plans, cloth.triangles, cloth.times.front());
    tree.index_triangles_under();
    int turned = 0;
    std::vector<Vec3> before(static_cast<size_t>(tree.topology().node_count()), Vec3::Zero());
    for (size_t k = 0; k + 1 < cloth.times.size(); ++k) {
        tree.fit(cloth.times[k], cloth.times[k + 1]);
        for (int32_t node = 0; node < tree.topology().node_count(); ++node) {
            Vec3 sum = Vec3::Zero();
            const auto [first, last] = tree.triangles_under(node);
            for (const int32_t* t = first; t != last; ++t) {
                const Triangle& ids = cloth.triangles[static_cast<size_t>(*t)];
                const auto at = [&](int32_t v) { return plans.position(v, cloth.times[k + 1]); };
                sum += (at(ids[1]) - at(ids[0])).cross(at(ids[2]) - at(ids[0]));
            }
            const Vec3 expected = sum.norm() > 0.0 ? Vec3(sum / sum.norm()) : Vec3::Zero();
            for (int ask = 0; ask < 2; ++ask) {
                EXPECT_LT((tree.end_mean_normal(node) - expected).norm(), 1e-12) << "node " << node << ", step " << k;
            }
            turned += (tree.end_mean_normal(node) - before[static_cast<size_t>(node)]).norm() > 1e-3;
            before[static_cast<size_t>(node)] = tree.end_mean_normal(node);
        }
    }
    EXPECT_GT(turned, 3 * tree.topology().node_count()) << "the normals do turn from step to step";
    const MeshAnimation still = animations::folding_cloth(3, 1);
    const Flightplans still_plans(still, true);
    StepBoxTree still_tree(still_plans, still.triangles, 0.0);
    still_tree.index_triangles_under();
    still_tree.fit(0.0, 1.0);
    const Vec3 first = still_tree.end_mean_normal(0);
    still_tree.fit(3.0, 4.0);
    EXPECT_EQ(still_tree.end_mean_normal(0), first);
    EXPECT_NEAR(first.norm(), 1.0, 1e-12);
}
