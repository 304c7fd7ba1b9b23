/// @file kinetic_aabb_tree_test.cpp
/// @brief Between its events, every box of the kinetic AABB tree encloses the
///        vertices under it (up to its stated margin): certificates never fail late.

#include "animations.hpp"
#include "usdksl/kinetic/event_queue.hpp"
#include "usdksl/kinetic/kinetic_aabb_tree.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

using namespace usdksl;

namespace {

/// Vertices under each node (brute force, from the topology).
std::vector<std::vector<int32_t>> vertices_under(const KineticAabbTree& tree, const std::vector<Triangle>& tris) {
    const BvhTopology& topo = tree.topology();
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

/// Largest amount (scene units) by which a stored box side falls short of the
/// true extreme of the vertices under its node, minus that node's margin.
double worst_shortfall(const KineticAabbTree& tree, const std::vector<std::vector<int32_t>>& under, double t) {
    double worst = -std::numeric_limits<double>::infinity();
    for (int32_t node = 0; node < tree.topology().node_count(); ++node) {
        for (int slot = 0; slot < BOX_SLOTS; ++slot) {
            const int axis = slot_axis(slot);
            const double sign = slot_is_max(slot) ? 1.0 : -1.0;
            double extreme = -std::numeric_limits<double>::infinity();
            for (int32_t v : under[node]) extreme = std::max(extreme, sign * tree.plans().coord(v, axis, t));
            worst = std::max(worst, extreme - sign * tree.side(node, slot, t) - tree.box_margin(node));
        }
    }
    return worst;
}

void run_and_check(const MeshAnimation& mesh, bool merge, int* events_out) {
    const Flightplans plans(mesh, merge);
    const double t_begin = mesh.times.front(), t_end = mesh.times.back();
    KineticAabbTree tree(plans, mesh.triangles, t_begin);
    const auto under = vertices_under(tree, mesh.triangles);
    EventQueue queue;
    const int32_t nodes = tree.topology().node_count();
    for (int32_t node = 0; node < nodes; ++node) {
        for (int slot = 0; slot < BOX_SLOTS; ++slot) {
            queue.schedule(int64_t{node} * BOX_SLOTS + slot, tree.certificate_failure(node, slot, t_begin, t_end));
        }
    }
    double now = t_begin;
    int events = 0;
    const double probe_step = 0.0137;  // not commensurate with the samples
    while (true) {
        const double next = std::min(queue.top_time(), t_end);
        for (double t = now; t < next; t += probe_step) {
            ASSERT_LE(worst_shortfall(tree, under, t), 1e-12) << "a box is too small at t = " << t;
        }
        if (queue.empty() || queue.top_time() > t_end) break;
        now = queue.top_time();
        const int64_t handle = queue.pop();
        ++events;
        int32_t node = static_cast<int32_t>(handle / BOX_SLOTS);
        const int slot = static_cast<int>(handle % BOX_SLOTS);
        bool changed = tree.repick(node, slot, now);
        queue.schedule(handle, tree.certificate_failure(node, slot, now, t_end));
        while (changed) {
            node = tree.topology().parent[node];
            if (node < 0) break;
            changed = tree.repick(node, slot, now);
            queue.schedule(int64_t{node} * BOX_SLOTS + slot, tree.certificate_failure(node, slot, now, t_end));
        }
    }
    *events_out = events;
}

} // namespace

TEST(KineticAabbTree, BoxesEncloseTheirVerticesBetweenEventsOnACurvedCloth) {
    int events = 0;
    run_and_check(animations::folding_cloth(5, 16), true, &events);
    EXPECT_GT(events, 10) << "the fold must reorder extreme vertices";
}

TEST(KineticAabbTree, BoxesEncloseTheirVerticesBetweenEventsOnRandomMergedTrajectories) {
    int events = 0;
    run_and_check(animations::random_walk(45, 20, 99, 0.0), true, &events);
    EXPECT_GT(events, 10);
}

TEST(KineticAabbTree, MarginIsLocalToTheVerticesUnderANode) {
    MeshAnimation mesh = animations::random_walk(45, 10, 4, 0.0);
    mesh.points[(static_cast<size_t>(5) * 45 + 0) * 3 + 1] = 1e9;  // vertex 0 (triangle 0) blown at sample 5
    const Flightplans plans(mesh, true);
    const KineticAabbTree tree(plans, mesh.triangles, 0.0);
    const BvhTopology& topo = tree.topology();
    for (int32_t node = 0; node < topo.node_count(); ++node) {
        if (topo.is_leaf(node) && topo.triangle[node] != 0) {
            EXPECT_LT(tree.box_margin(node), 1e-8) << "leaf of triangle " << topo.triangle[node];
        }
    }
}
