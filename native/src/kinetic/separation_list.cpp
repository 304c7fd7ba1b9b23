#include "usdksl/kinetic/separation_list.hpp"

#include "usdksl/kinetic/node_plane.hpp"
#include "usdksl/narrow_phase/triangle_pair.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace usdksl {
namespace {

/// Progress (where a stop request is raised) comes after so many entries
/// created or narrow-phase runs, and after every step: one step can expand a
/// whole self-overlapping tree or cover many leaf pairs.
constexpr int64_t kProgressEveryWork = 1 << 8;
constexpr double kNothingTested = -1e300;
/// Entry slots ahead of the one being brought up to date whose memory is asked for meanwhile.
constexpr int32_t kEntryPrefetchDistance = 16;
/// Wake step of a free entry slot.
constexpr int32_t kNeverWakes = std::numeric_limits<int32_t>::max();

/// Slack (fraction of a step) by which the times at which two moving boxes
/// overlap may miss each other and still count as meeting: covers rounding
/// of the crossing fractions, so rounding never hides a meeting.
constexpr double STEP_MEETING_SLACK = 1e-9;

/// A triangle's corners in a step tree's position array (x y z per vertex).
std::array<Vec3, 3> triangle_corners(const double* points, const Triangle& ids) {
    std::array<Vec3, 3> at;
    for (int i = 0; i < 3; ++i) at[i] = Eigen::Map<const Vec3>(points + 3 * static_cast<size_t>(ids[i]));
    return at;
}

uint64_t pair_key(int32_t a, int32_t b) {
    return (static_cast<uint64_t>(static_cast<uint32_t>(a)) << 32) | static_cast<uint32_t>(b);
}

/// Time codes at which some vertex of a used mesh has a flightplan
/// breakpoint, inside [t_begin, t_end], plus both ends, in order: every vertex
/// moves linearly between consecutive ones.
std::vector<double> breakpoint_times(const Scene& scene, const std::vector<bool>& used, double t_begin,
                                     double t_end) {
    std::vector<double> times{t_begin, t_end};
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        if (!used[m]) continue;
        // Breakpoints are sample times: mark which samples some vertex keeps.
        const std::vector<double>& samples = scene.meshes[m].times;
        std::vector<bool> kept(samples.size(), false);
        const Flightplans& plans = scene.plans[m];
        for (int32_t v = 0; v < plans.vertex_count(); ++v) {
            // A vertex's breakpoints ascend: each is found from the last one's
            // sample on, at once when it is the next sample (every sample kept).
            auto from = samples.begin();
            for (int64_t k = plans.key_begin(v); k < plans.key_end(v); ++k) {
                const double t = plans.key_time(v, k);
                const auto it = from != samples.end() && *from == t ? from : std::lower_bound(from, samples.end(), t);
                if (it != samples.end() && *it == t) {
                    kept[static_cast<size_t>(it - samples.begin())] = true;
                    from = it + 1;
                } else {
                    if (t > t_begin && t < t_end) times.push_back(t);
                    from = it;
                }
            }
        }
        for (size_t i = 0; i < samples.size(); ++i) {
            if (kept[i] && samples[i] > t_begin && samples[i] < t_end) times.push_back(samples[i]);
        }
    }
    std::sort(times.begin(), times.end());
    times.erase(std::unique(times.begin(), times.end()), times.end());
    return times;
}

/// Triangle pairs of the mesh that share a vertex, at most: pairs around
/// each vertex (a pair sharing an edge counts at both its vertices).
size_t vertex_sharing_pairs_at_most(const MeshAnimation& mesh) {
    std::vector<int32_t> triangles_at(static_cast<size_t>(mesh.vertex_count), 0);
    for (const Triangle& triangle : mesh.triangles) {
        for (int32_t v : triangle) ++triangles_at[static_cast<size_t>(v)];
    }
    size_t pairs = 0;
    for (int32_t count : triangles_at) pairs += static_cast<size_t>(count) * static_cast<size_t>(count - 1) / 2;
    return pairs;
}

} // namespace

KineticSeparationLists::KineticSeparationLists(const Scene& scene,
                                               const std::vector<std::pair<int32_t, int32_t>>& mesh_pairs,
                                               TrianglePairTester& tester, Counters& counters,
                                               const CheckOptions& options)
    : scene_(scene), tester_(tester), counters_(counters), t_begin_(options.t_begin), t_end_(options.t_end) {
    const size_t mesh_count = scene.meshes.size();
    trees_.resize(mesh_count);
    std::vector<bool> used(mesh_count, false);
    for (const auto& [ma, mb] : mesh_pairs) used[ma] = used[mb] = true;
    for (size_t mesh = 0; mesh < mesh_count; ++mesh) {
        if (!used[mesh] || scene.meshes[mesh].triangles.empty()) continue;
        trees_[mesh] = std::make_unique<StepBoxTree>(scene.plans[mesh], scene.meshes[mesh].triangles, t_begin_);
    }
    size_t sharing_pairs = 0;
    for (const auto& [ma, mb] : mesh_pairs) {
        if (!trees_[ma] || !trees_[mb]) continue;
        List list{std::min(ma, mb), std::max(ma, mb), ma == mb, {}};
        const int32_t nodes = trees_[list.mesh_a]->topology().node_count();
        list.index.resize(static_cast<size_t>((nodes + FRONT_INDEX_BLOCK_NODES - 1) / FRONT_INDEX_BLOCK_NODES));
        lists_.push_back(std::move(list));
        margin_.push_back(scene.contact_distance(ma, mb, options.ccd.thickness));
        if (ma != mb) {
            trees_[ma]->index_triangles_under();
            trees_[mb]->index_triangles_under();
        }
        if (ma == mb) sharing_pairs += vertex_sharing_pairs_at_most(scene.meshes[ma]);
    }
    // Every one of them may be handed over at the first step: reserved
    // once, the array is never copied while it grows (capacity that is
    // never written takes no memory).
    shared_vertex_pairs_.reserve(sharing_pairs);
}

// ---------------------------------------------------------------- BVTT shape

KineticSeparationLists::NodePair KineticSeparationLists::normalized(const List& list, int32_t a, int32_t b) const {
    if (list.self && a > b) std::swap(a, b);
    return {a, b};
}

bool KineticSeparationLists::both_leaves(const List& list, int32_t a, int32_t b) const {
    return trees_[list.mesh_a]->topology().is_leaf(a) && trees_[list.mesh_b]->topology().is_leaf(b);
}

bool KineticSeparationLists::father_of(const List& list, int32_t a, int32_t b, NodePair& father) const {
    const BvhTopology& ta = trees_[list.mesh_a]->topology();
    const BvhTopology& tb = trees_[list.mesh_b]->topology();
    if (a == 0 && b == 0) return false;
    if (list.self && a == b) {
        father = {ta.parent[a], ta.parent[a]};
        return true;
    }
    // Both trees descend in lock step; a leaf reached early waits for the other side.
    const int32_t da = ta.depth[a], db = tb.depth[b];
    if (da == db) father = {ta.parent[a], tb.parent[b]};
    else if (da < db) father = {a, tb.parent[b]};
    else father = {ta.parent[a], b};
    father = normalized(list, father.a, father.b);
    return true;
}

int KineticSeparationLists::children_of(const List& list, int32_t a, int32_t b, NodePair out[4]) const {
    const BvhTopology& ta = trees_[list.mesh_a]->topology();
    const BvhTopology& tb = trees_[list.mesh_b]->topology();
    if (list.self && a == b) {
        if (ta.is_leaf(a)) return 0;
        const int32_t l = ta.left[a], r = ta.right[a];
        out[0] = {l, l};
        out[1] = normalized(list, l, r);
        out[2] = {r, r};
        return 3;
    }
    const bool leaf_a = ta.is_leaf(a), leaf_b = tb.is_leaf(b);
    const int32_t da = ta.depth[a], db = tb.depth[b];
    const bool split_a = !leaf_a && da <= db;
    const bool split_b = !leaf_b && db <= da;
    // A leaf cannot split: the other side then descends alone.
    const bool descend_a = split_a || (!leaf_a && leaf_b);
    const bool descend_b = split_b || (!leaf_b && leaf_a);
    int count = 0;
    if (descend_a && descend_b) {
        for (int32_t ca : {ta.left[a], ta.right[a]})
            for (int32_t cb : {tb.left[b], tb.right[b]}) out[count++] = normalized(list, ca, cb);
    } else if (descend_a) {
        for (int32_t ca : {ta.left[a], ta.right[a]}) out[count++] = normalized(list, ca, b);
    } else if (descend_b) {
        for (int32_t cb : {tb.left[b], tb.right[b]}) out[count++] = normalized(list, a, cb);
    }
    return count;
}

// ------------------------------------------------------------------ geometry

double KineticSeparationLists::margin_of(const List& list) const { return margin_[&list - lists_.data()]; }

bool KineticSeparationLists::meet(const List& list, int32_t a, int32_t b, int64_t* quiet) {
    if (list.self && a == b) return true;
    ++counters_.bv_tests;
    const StepBox& ba = trees_[list.mesh_a]->box(a);
    const StepBox& bb = trees_[list.mesh_b]->box(b);
    const double margin = margin_of(list);
    const auto separated = [&]() {
        if (quiet) *quiet = quiet_until(list, a, b, ba, bb, margin);
        return false;
    };
    // Each of the six gaps (max(a) - min(b) and max(b) - min(a) per axis,
    // grown by the margin) is linear over the step; the boxes meet while all
    // are >= 0, on an interval of step fractions.
    double first = 0.0, last = 1.0;
    for (int axis = 0; axis < 3; ++axis) {
        for (int side = 0; side < 2; ++side) {
            const StepBox& upper = side == 0 ? ba : bb;
            const StepBox& lower = side == 0 ? bb : ba;
            const double g0 = upper.hi[0][axis] - lower.lo[0][axis] + margin;
            const double g1 = upper.hi[1][axis] - lower.lo[1][axis] + margin;
            if (g0 < 0.0) {
                if (g1 < 0.0) return separated();
                first = std::max(first, g0 / (g0 - g1));
            } else if (g1 < 0.0) {
                last = std::min(last, g0 / (g0 - g1));
            }
        }
    }
    return first <= last + STEP_MEETING_SLACK || separated();
}

bool KineticSeparationLists::apart(const List& list, int32_t a, int32_t b, double fraction) const {
    if (list.self && a == b) return false;
    const StepBoxTree& ta = *trees_[list.mesh_a];
    const StepBoxTree& tb = *trees_[list.mesh_b];
    const StepBox& ba = ta.box(a);
    const StepBox& bb = tb.box(b);
    // Apart means the boxes, grown by the contact distance, stay more than the hysteresis apart.
    const double slack = fraction * std::min(ta.extent(a), tb.extent(b)) + margin_of(list);
    for (int axis = 0; axis < 3; ++axis) {
        for (int side = 0; side < 2; ++side) {
            const StepBox& upper = side == 0 ? ba : bb;
            const StepBox& lower = side == 0 ? bb : ba;
            if (upper.hi[0][axis] - lower.lo[0][axis] + slack < 0.0 &&
                upper.hi[1][axis] - lower.lo[1][axis] + slack < 0.0) {
                return true;
            }
        }
    }
    return false;
}

void KineticSeparationLists::measure_travel() {
    const size_t steps = times_.size() - 1;
    travel_.assign(trees_.size(), {});
    for (size_t m = 0; m < trees_.size(); ++m) {
        if (!trees_[m]) continue;
        // Largest displacement along any axis of any vertex, per step: a
        // vertex moves linearly on each flightplan segment, so a step inside
        // a segment takes its share of the segment's displacement.
        std::vector<double> per_step(steps, 0.0);
        const Flightplans& plans = scene_.plans[m];
        for (int32_t v = 0; v < plans.vertex_count(); ++v) {
            // Segments ascend: each one's first step is searched from the last one's on, and found at
            // once when it begins at the next step time (every sample kept).
            size_t from = 0;
            for (int64_t k = plans.key_begin(v); k + 1 < plans.key_end(v); ++k) {
                const double t0 = plans.key_time(v, k), t1 = plans.key_time(v, k + 1);
                double moved = 0.0;
                for (int axis = 0; axis < 3; ++axis) {
                    moved = std::max(moved, std::abs(plans.key_coord(v, k + 1, axis) - plans.key_coord(v, k, axis)));
                }
                if (moved == 0.0) continue;
                const double speed = moved / (t1 - t0);
                // The last step time at or before t0 (the first step when none is).
                size_t i = from;
                if (!(from < times_.size() && times_[from] <= t0 && (from + 1 == times_.size() || times_[from + 1] > t0))) {
                    i = static_cast<size_t>(std::upper_bound(times_.begin(), times_.end(), t0) - times_.begin());
                    i = i == 0 ? 0 : i - 1;
                }
                for (; i < steps && times_[i] < t1; ++i) {
                    per_step[i] = std::max(per_step[i], speed * (times_[i + 1] - times_[i]));
                }
                from = i;
            }
        }
        std::vector<double>& travel = travel_[m];
        travel.assign(steps + 1, 0.0);
        for (size_t i = 0; i < steps; ++i) travel[i + 1] = travel[i] + per_step[i] * (1.0 + TRAVEL_ROUNDING);
    }
}

int64_t KineticSeparationLists::quiet_until(const List& list, int32_t a, int32_t b, const StepBox& ba,
                                            const StepBox& bb, double margin) const {
    // Lower bounds of the six separations (b above a, a above b per axis)
    // at the end of the last step judged; the boxes stay apart during a step
    // while one of them is positive at both its ends (each is linear across it).
    double gap[3][2];
    double widest = 0.0;
    for (int axis = 0; axis < 3; ++axis) {
        gap[axis][0] = bb.lo[1][axis] - ba.hi[1][axis] - margin;
        gap[axis][1] = ba.lo[1][axis] - bb.hi[1][axis] - margin;
        widest = std::max({widest, gap[axis][0], gap[axis][1]});
    }
    const int64_t steps = static_cast<int64_t>(times_.size()) - 1;
    int64_t next = step_index_ + 1;
    if (!(widest > 0.0) || next >= steps) return next;
    // Each box side moves as the vertices under its node: over the steps the
    // trees recorded, a separation shrinks by no more than how far the lower
    // node's shift may rise beyond the upper one's (both radii included)...
    const StepBoxTree& tree_a = *trees_[list.mesh_a];
    const StepBoxTree& tree_b = *trees_[list.mesh_b];
    const int64_t recorded_end = std::min(steps, next + NODE_TRAVEL_AHEAD_STEPS);
    for (; next < recorded_end; ++next) {
        const NodeShift& sa = tree_a.shift(a, next);
        const NodeShift& sb = tree_b.shift(b, next);
        const double spread = static_cast<double>(sa.radius) + sb.radius;
        bool apart_throughout = false;
        widest = -std::numeric_limits<double>::infinity();
        for (int axis = 0; axis < 3; ++axis) {
            const double rise = static_cast<double>(sa.center[axis]) - sb.center[axis];  // of a against b
            for (int side = 0; side < 2; ++side) {
                const double after = gap[axis][side] - ((side == 0 ? rise : -rise) + spread);
                apart_throughout = apart_throughout || (gap[axis][side] > 0.0 && after > 0.0);
                gap[axis][side] = after;
                widest = std::max(widest, after);
            }
        }
        if (!apart_throughout) return next;
    }
    if (next >= steps) return steps;
    if (!(widest > 0.0)) return next;
    // ... and beyond, their meshes' fastest vertex.
    const std::vector<double>& ta = travel_[list.mesh_a];
    const std::vector<double>& tb = travel_[list.mesh_b];
    const auto closes_by = [&](int64_t end) {  // travel over steps next..end-1
        return (ta[end] - ta[next]) + (tb[end] - tb[next]) >= widest;
    };
    int64_t low = next, high = steps;  // steps next..low-1 are safe; find the first end that closes
    if (!closes_by(high)) return steps;
    while (low + 1 < high) {
        const int64_t middle = low + (high - low) / 2;
        if (closes_by(middle)) high = middle;
        else low = middle;
    }
    return low;
}

// --------------------------------------------------------- front maintenance

int32_t KineticSeparationLists::create_entry(int32_t list_id, int32_t a, int32_t b, const NodePair* father,
                                             bool overlapping_leaf) {
    if (overlapping_leaf && hand_over_if_sharing_vertex(list_id, a, b)) return -1;
    int32_t id;
    if (!free_entries_.empty()) {
        id = free_entries_.back();
        free_entries_.pop_back();
    } else {
        id = static_cast<int32_t>(entries_.size());
        entries_.emplace_back();
        wake_step_.push_back(0);
    }
    wake_step_[id] = static_cast<int32_t>(step_index_) + 1;  // up to date for the step it is created in
    worked();
    List& list = lists_[list_id];
    Entry& e = entries_[id];
    e = Entry{};
    e.list = list_id;
    e.a = a;
    e.b = b;
    if (father) {
        e.fa = father->a;
        e.fb = father->b;
    }
    e.overlapping_leaf = overlapping_leaf;
    e.alive = true;
    index_of(list, a).emplace(pair_key(a, b), id);
    if (both_leaves(list, a, b)) {
        const int32_t tri_a = trees_[list.mesh_a]->topology().triangle[a];
        const int32_t tri_b = trees_[list.mesh_b]->topology().triangle[b];
        e.tested_until = take_saved_tested_until(list, a, b);
        if (tester_.settled(list.mesh_a, tri_a, list.mesh_b, tri_b)) {
            e.inert = true;
        } else if (overlapping_leaf) {
            if (initializing_ && !clear_at_begin(e) &&
                tester_.test_static(list.mesh_a, tri_a, list.mesh_b, tri_b, t_begin_)) {
                e.inert = true;
            }
            cover(e);
        }
    }
    if (done_with(e)) {
        remove_entry(id, false);
        return -1;
    }
    return id;
}

bool KineticSeparationLists::hand_over_if_sharing_vertex(int32_t list_id, int32_t a, int32_t b) {
    const List& list = lists_[list_id];
    if (!list.self || !both_leaves(list, a, b)) return false;
    const int32_t tri_a = trees_[list.mesh_a]->topology().triangle[a];
    const int32_t tri_b = trees_[list.mesh_b]->topology().triangle[b];
    if (!share_vertex(list.mesh_a, tri_a, tri_b)) return false;
    // Leaves that share a vertex never part: they follow every step from now
    // on here, outside the front, without an entry slot and two visits to
    // the front's index (the 1M tablecloth has 12M such pairs).
    worked();
    const double tested_until = take_saved_tested_until(list, a, b);
    if (tester_.settled(list.mesh_a, tri_a, list.mesh_b, tri_b) || !(tested_until < t_end_)) return true;
    SharedVertexPair pair{};
    pair.tested_until = tested_until;
    pair.list = list_id;
    pair.tri_a = tri_a;
    pair.tri_b = tri_b;
    pair.leaf_a = a;
    pair.leaf_b = b;
    pair.backoff = 1;
    pair.static_pending = initializing_;  // its static test comes with its first step
    shared_vertex_pairs_.push_back(pair);
    return true;
}

double KineticSeparationLists::take_saved_tested_until(const List& list, int32_t a, int32_t b) {
    const auto saved = leaf_tested_until_.find(tester_key(list, a, b));
    if (saved == leaf_tested_until_.end()) return kNothingTested;
    const double tested_until = saved->second;
    leaf_tested_until_.erase(saved);
    return tested_until;
}

bool KineticSeparationLists::done_with(const Entry& e) const { return e.inert; }

void KineticSeparationLists::remove_entry(int32_t id, bool keep_tested) {
    Entry& e = entries_[id];
    List& list = lists_[e.list];
    index_of(list, e.a).erase(pair_key(e.a, e.b));
    // A leaf pair keeps what its narrow phase covered, should it come back.
    if (keep_tested && !e.inert && e.tested_until > kNothingTested && both_leaves(list, e.a, e.b)) {
        leaf_tested_until_[tester_key(list, e.a, e.b)] = e.tested_until;
    }
    if (e.plane_kept) release_plane(e);
    else release_clearance_run(e);
    e.alive = false;
    wake_step_[id] = kNeverWakes;
    free_entries_.push_back(id);
}

void KineticSeparationLists::expand(int32_t list_id, int32_t a, int32_t b) {
    // Descend straight to the deepest pairs that do not meet (section 6.1).
    const List& list = lists_[list_id];
    NodePair children[4];
    const int count = children_of(list, a, b, children);
    const NodePair father{a, b};
    for (int i = 0; i < count; ++i) {
        const NodePair c = children[i];
        if (list.self && c.a == c.b && trees_[list.mesh_a]->topology().is_leaf(c.a)) continue;
        int64_t quiet;
        if (!meet(list, c.a, c.b, &quiet)) {
            const int32_t id = create_entry(list_id, c.a, c.b, &father, false);
            if (id >= 0) {
                entries_[id].quiet_until = static_cast<int32_t>(quiet);
                wake_step_[id] = std::max(wake_step_[id], static_cast<int32_t>(quiet));
            }
        } else if (both_leaves(list, c.a, c.b)) {
            create_entry(list_id, c.a, c.b, &father, true);
        } else if (NodePlane plane; plane_separates(list, c.a, c.b, nullptr, plane)) {
            create_plane_kept_entry(list_id, c.a, c.b, &father, plane);
        } else {
            expand(list_id, c.a, c.b);
        }
    }
}

void KineticSeparationLists::remove_descendants(int32_t list_id, int32_t a, int32_t b) {
    List& list = lists_[list_id];
    NodePair children[4];
    const int count = children_of(list, a, b, children);
    for (int i = 0; i < count; ++i) {
        const FlatHashMap<uint64_t, int32_t>& index = index_of(list, children[i].a);
        const auto it = index.find(pair_key(children[i].a, children[i].b));
        if (it != index.end()) remove_entry(it->second);
        else remove_descendants(list_id, children[i].a, children[i].b);
    }
}

void KineticSeparationLists::cover(Entry& e) {
    if (e.inert) return;
    const List& list = lists_[e.list];
    const int32_t tri_a = trees_[list.mesh_a]->topology().triangle[e.a];
    const int32_t tri_b = trees_[list.mesh_b]->topology().triangle[e.b];
    const double until = step_end_;
    if (e.tested_until >= until) return;
    // Only this entry tests its triangle pair, and a settled pair became
    // inert when the entry was created or when it hit.
    ++counters_.polygons_collide_events;
    // A pair the certificate clears is covered a few steps ahead in the same
    // call; update() skips it until then (it may turn apart meanwhile, which
    // only means those steps were covered in vain).
    const size_t ahead = std::min(static_cast<size_t>(step_index_) + 1 + LEAF_COVER_AHEAD_STEPS, times_.size() - 1);
    const StepRun run = tester_.test_steps(list.mesh_a, tri_a, list.mesh_b, tri_b,
                                           std::max(step_begin_, e.tested_until), until, true, &clearance_run(e),
                                           times_[ahead]);
    e.tested_until = run.tested_until;
    if (run.hit) {
        e.inert = true;
        release_clearance_run(e);
    }
    // Nothing to do for it before the first step that ends past what it covered.
    e.quiet_until = static_cast<int32_t>(
        std::upper_bound(times_.begin() + step_index_ + 1, times_.end(), e.tested_until) - times_.begin() - 1);
    worked();
}

bool KineticSeparationLists::clear_at_begin(Entry& e) {
    const List& list = lists_[e.list];
    int32_t mesh_a = list.mesh_a, mesh_b = list.mesh_b;
    int32_t tri_a = trees_[mesh_a]->topology().triangle[e.a], tri_b = trees_[mesh_b]->topology().triangle[e.b];
    // The order test_steps() carries the certificate in (TrianglePairTester's canonical order).
    if (mesh_a > mesh_b || (mesh_a == mesh_b && tri_a > tri_b)) {
        std::swap(mesh_a, mesh_b);
        std::swap(tri_a, tri_b);
    }
    const Triangle& ids_a = scene_.meshes[mesh_a].triangles[tri_a];
    const Triangle& ids_b = scene_.meshes[mesh_b].triangles[tri_b];
    const std::array<Vec3, 3> a = triangle_corners(trees_[mesh_a]->begin_points(), ids_a);
    const std::array<Vec3, 3> b = triangle_corners(trees_[mesh_b]->begin_points(), ids_b);
    ClearanceRun& run = clearance_run(e);
    run.clearance.start(ids_a, a, ids_b, b, mesh_a == mesh_b, margin_of(list), tester_.settings().tolerance,
                        std::max(scene_.triangle_magnitude(mesh_a, tri_a), scene_.triangle_magnitude(mesh_b, tri_b)));
    // The static test also reports triangles that pierce each other without
    // any primitive pair within reach: only the plane proof rules that out.
    if (!run.clearance.holds_at(a, b) || !run.clearance.separated_by_plane()) {
        run = ClearanceRun{};
        return false;
    }
    // Started at the window's begin: the narrow phase's first call goes on with it.
    run.certified = run.fresh = true;
    run.valid_at = t_begin_;
    return true;
}

bool KineticSeparationLists::clears_step(SharedVertexPair& pair) {
    const List& list = lists_[pair.list];
    const StepBoxTree& tree = *trees_[list.mesh_a];
    const std::vector<Triangle>& triangles = scene_.meshes[list.mesh_a].triangles;
    const Triangle& ids_a = triangles[pair.tri_a];
    const Triangle& ids_b = triangles[pair.tri_b];
    const double contact_distance = margin_of(list);
    const double tolerance = tester_.settings().tolerance;
    const auto record = [&](bool cleared) {
        if (cleared) {
            pair.fresh = false;
            pair.backoff = 1;
            ++counters_.cleared_steps;
        } else {
            pair.certified = false;
            pair.wait = pair.backoff;
            pair.backoff = static_cast<int8_t>(std::min(2 * pair.backoff, CLEARANCE_MAX_BACKOFF_STEPS));
        }
        return cleared;
    };
    // Most steps are cleared by the proof that held at the last one's end, asked at this one's end alone.
    const std::array<Vec3, 3> a1 = triangle_corners(tree.end_points(), ids_a);
    const std::array<Vec3, 3> b1 = triangle_corners(tree.end_points(), ids_b);
    if (pair.certified && !pair.static_pending && pair.clearance.holds_at_end(a1, b1)) return record(true);
    const std::array<Vec3, 3> a0 = triangle_corners(tree.begin_points(), ids_a);
    const std::array<Vec3, 3> b0 = triangle_corners(tree.begin_points(), ids_b);
    const auto start_certificate = [&]() {
        pair.clearance.start(ids_a, a0, ids_b, b0,
                             std::max(scene_.triangle_magnitude(list.mesh_a, pair.tri_a),
                                      scene_.triangle_magnitude(list.mesh_a, pair.tri_b)));
        pair.certified = pair.fresh = true;
    };
    // The schedule of TrianglePairTester::test_steps: a certificate that fails
    // at once backs off for a few steps; one that ran out after clearing
    // steps is restarted at this step's begin.
    if (!pair.certified && pair.wait == 0) start_certificate();
    if (pair.static_pending) {
        // The window's first step: a certificate that holds at its begin
        // proves what the static test would find (no contact there), once no
        // edge pierces the other triangle, which a plane rules out already.
        pair.static_pending = false;
        const bool clear = pair.certified &&
                           pair.clearance.holds_over(ids_a, a0, a0, ids_b, b0, b0, contact_distance, tolerance) &&
                           (pair.clearance.separated_by_plane() || (!edge_pierces_triangle(ids_a, a0, ids_b, b0) &&
                                                                    !edge_pierces_triangle(ids_b, b0, ids_a, a0)));
        if (!clear && tester_.test_static(list.mesh_a, pair.tri_a, list.mesh_b, pair.tri_b, t_begin_)) {
            pair.static_hit = true;
            return false;
        }
    }
    if (!pair.certified) {
        if (pair.wait > 0) --pair.wait;
        return false;
    }
    bool cleared = pair.clearance.holds_over(ids_a, a0, a1, ids_b, b0, b1, contact_distance, tolerance);
    if (!cleared && !pair.fresh) {
        start_certificate();
        cleared = pair.clearance.holds_over(ids_a, a0, a1, ids_b, b0, b1, contact_distance, tolerance);
    }
    return record(cleared);
}

void KineticSeparationLists::step_shared_vertex_pairs() {
    size_t kept = 0;
    for (size_t i = 0; i < shared_vertex_pairs_.size(); ++i) {
        SharedVertexPair& pair = shared_vertex_pairs_[i];
        bool hit = false;
        if (pair.tested_until < step_end_) {
            // The certificate follows whole steps; a narrow-phase run ends on
            // a breakpoint of the pair, which is a step's end too.
            if (pair.tested_until <= step_begin_ && clears_step(pair)) {
                const size_t through = cleared_ahead(pair);
                counters_.cleared_steps += static_cast<int64_t>(through) - (step_index_ + 1);
                pair.tested_until = times_[through];
            } else if (pair.static_hit) {
                hit = true;
            } else {
                const List& list = lists_[pair.list];
                ++counters_.polygons_collide_events;
                const StepRun run = tester_.test_steps(list.mesh_a, pair.tri_a, list.mesh_b, pair.tri_b,
                                                       std::max(step_begin_, pair.tested_until), step_end_, false);
                pair.tested_until = run.tested_until;
                hit = run.hit;
                worked();
            }
        }
        if (hit || pair.tested_until >= t_end_) continue;
        if (kept != i) shared_vertex_pairs_[kept] = pair;
        ++kept;
    }
    shared_vertex_pairs_.resize(kept);
}

size_t KineticSeparationLists::cleared_ahead(const SharedVertexPair& pair) const {
    const double allowance = pair.clearance.allowance();
    size_t step = static_cast<size_t>(step_index_) + 1;
    if (!(allowance > 0.0)) return step;
    const StepBoxTree& tree = *trees_[lists_[pair.list].mesh_a];
    // Recorded travel reaches NODE_TRAVEL_AHEAD_STEPS steps on; the last step ends the range.
    const size_t recorded = std::min(travel_recorded_, times_.size() - 1);
    double moved = 0.0;
    for (; step < recorded; ++step) {
        // Each corner and the shared vertex are under one leaf, whose vertices' displacements during the
        // step all lie in one cube: a corner moves relative to the shared vertex by at most its diagonal.
        moved += SHIFT_CUBE_DIAGONAL_PER_RADIUS *
                 std::max(static_cast<double>(tree.shift(pair.leaf_a, static_cast<int64_t>(step)).radius),
                          static_cast<double>(tree.shift(pair.leaf_b, static_cast<int64_t>(step)).radius));
        if (!(moved < allowance)) break;
    }
    return step;
}

bool KineticSeparationLists::plane_separates(const List& list, int32_t a, int32_t b, const NodePlane* previous,
                                             NodePlane& plane) const {
    if (list.self) return false;  // nodes of one mesh may share vertices, which no plane separates
    const StepBoxTree& tree_a = *trees_[list.mesh_a];
    const StepBoxTree& tree_b = *trees_[list.mesh_b];
    const auto [first_a, last_a] = tree_a.triangles_under(a);
    const auto [first_b, last_b] = tree_b.triangles_under(b);
    if (last_a - first_a > NODE_PLANE_MAX_TRIANGLES || last_b - first_b > NODE_PLANE_MAX_TRIANGLES) return false;
    const double reach = node_pair_reach(tree_a, a, tree_b, b, margin_of(list), tester_.settings().tolerance);
    plane.step = static_cast<int32_t>(step_index_);
    if (!previous) return find_node_plane(tree_a, a, tree_b, b, reach, Vec3::Zero(), plane.normal, &plane.gap);
    // The trees' positions at this step's begin are those at the last one's end.
    const bool begin_known = previous->step + 1 == step_index_;
    return find_node_plane(tree_a, a, tree_b, b, reach, previous->normal, plane.normal, &plane.gap,
                           begin_known ? &previous->gap : nullptr);
}

int64_t KineticSeparationLists::plane_quiet_until(const List& list, int32_t a, int32_t b,
                                                  const NodePlane& plane) const {
    return node_plane_quiet_until(*trees_[list.mesh_a], a, *trees_[list.mesh_b], b, plane.normal, plane.gap,
                                  margin_of(list), tester_.settings().tolerance, step_index_,
                                  static_cast<int64_t>(times_.size()) - 1, travel_[list.mesh_a].data(),
                                  travel_[list.mesh_b].data());
}

template <class Keeps>
bool KineticSeparationLists::climb(const List& list, NodePair& top, NodePair& up, Keeps&& keeps) const {
    bool has_up = father_of(list, top.a, top.b, up);
    while (has_up && keeps(up)) {
        top = up;
        has_up = father_of(list, top.a, top.b, up);
    }
    return has_up;
}

bool KineticSeparationLists::coarsen_to_plane(int32_t id) {
    const Entry& e = entries_[id];
    const List& list = lists_[e.list];
    if (list.self || e.fa < 0) return false;
    NodePlane plane;
    if (!plane_separates(list, e.fa, e.fb, nullptr, plane)) return false;
    // Ascend to the highest pair a plane keeps apart.
    NodePair top{e.fa, e.fb};
    NodePair up;
    const bool has_up = climb(list, top, up, [&](const NodePair& father) {
        NodePlane father_plane;
        if (!plane_separates(list, father.a, father.b, &plane, father_plane)) return false;
        plane = father_plane;
        return true;
    });
    const int32_t list_id = e.list;
    ++counters_.fathers_do_not_overlap_events;
    remove_descendants(list_id, top.a, top.b);
    create_plane_kept_entry(list_id, top.a, top.b, has_up ? &up : nullptr, plane);
    return true;
}

void KineticSeparationLists::create_plane_kept_entry(int32_t list_id, int32_t a, int32_t b, const NodePair* father,
                                                     const NodePlane& plane) {
    const int32_t id = create_entry(list_id, a, b, father, false);
    if (id < 0) return;
    keep_plane(id, plane);
    ++counters_.plane_kept_steps;
}

void KineticSeparationLists::keep_plane(int32_t id, const NodePlane& plane) {
    Entry& e = entries_[id];
    e.quiet_until = static_cast<int32_t>(plane_quiet_until(lists_[e.list], e.a, e.b, plane));
    // Created in this step (run() sets the wake step of the entry it updates).
    wake_step_[id] = std::max(wake_step_[id], e.quiet_until);
    if (!e.plane_kept) {
        if (free_kept_planes_.empty()) {
            e.certificate = static_cast<int32_t>(kept_planes_.size());
            kept_planes_.push_back(plane);
        } else {
            e.certificate = free_kept_planes_.back();
            free_kept_planes_.pop_back();
        }
        e.plane_kept = true;
    }
    kept_planes_[e.certificate] = plane;
}

void KineticSeparationLists::release_plane(Entry& e) {
    if (!e.plane_kept) return;
    free_kept_planes_.push_back(e.certificate);
    e.certificate = -1;
    e.plane_kept = false;
}

ClearanceRun& KineticSeparationLists::clearance_run(Entry& e) {
    if (e.certificate < 0) {
        if (free_clearance_runs_.empty()) {
            e.certificate = static_cast<int32_t>(clearance_runs_.size());
            clearance_runs_.emplace_back();
        } else {
            e.certificate = free_clearance_runs_.back();
            free_clearance_runs_.pop_back();
            clearance_runs_[e.certificate] = ClearanceRun{};
        }
    }
    return clearance_runs_[e.certificate];
}

void KineticSeparationLists::release_clearance_run(Entry& e) {
    if (e.certificate < 0) return;
    free_clearance_runs_.push_back(e.certificate);
    e.certificate = -1;
}

void KineticSeparationLists::worked() {
    if (progress_ && *progress_ && (++work_ % kProgressEveryWork) == 0) {
        (*progress_)(step_begin_, static_cast<int64_t>(tester_.contacts().size()));
    }
}

bool KineticSeparationLists::share_vertex(int32_t mesh, int32_t tri_a, int32_t tri_b) const {
    const Triangle& x = scene_.meshes[mesh].triangles[tri_a];
    const Triangle& y = scene_.meshes[mesh].triangles[tri_b];
    for (int32_t v : x) {
        if (v == y[0] || v == y[1] || v == y[2]) return true;
    }
    return false;
}
FlatHashMap<uint64_t, int32_t>& KineticSeparationLists::index_of(List& list, int32_t a) {
    return list.index[static_cast<size_t>(a / FRONT_INDEX_BLOCK_NODES)];
}

uint64_t KineticSeparationLists::tester_key(const List& list, int32_t a, int32_t b) const {
    return tester_.key(list.mesh_a, trees_[list.mesh_a]->topology().triangle[a], list.mesh_b,
                       trees_[list.mesh_b]->topology().triangle[b]);
}
// ---------------------------------------------------------------- the steps

void KineticSeparationLists::update(int32_t id) {
    Entry& e = entries_[id];
    if (e.inert) return;  // a settled triangle pair: nothing under it to find
    const List& list = lists_[e.list];
    const int32_t list_id = e.list;
    if (e.overlapping_leaf) {
        // Covered ahead already: whether the leaves parted is asked when
        // the covered steps run out (covering longer is never wrong).
        if (e.tested_until >= step_end_) return;
        if (coarsen_to_plane(id)) return;
        if (apart(list, e.a, e.b, LEAF_HYSTERESIS)) {
            ++counters_.leaves_do_not_overlap_events;
            e.overlapping_leaf = false;
            release_clearance_run(e);
        } else {
            cover(e);
            if (done_with(e)) remove_entry(id, false);
        }
        return;
    }
    if (e.fa >= 0 && (step_index_ + id) % FRONT_COARSEN_EVERY_STEPS == 0 &&
        apart(list, e.fa, e.fb, FRONT_HYSTERESIS)) {
        // Ascend to the highest pair that stays apart (section 6.1).
        ++counters_.fathers_do_not_overlap_events;
        NodePair top{e.fa, e.fb};
        NodePair up;
        const bool has_up = climb(list, top, up, [&](const NodePair& father) {
            return apart(list, father.a, father.b, FRONT_HYSTERESIS);
        });
        remove_descendants(list_id, top.a, top.b);
        create_entry(list_id, top.a, top.b, has_up ? &up : nullptr, false);
        return;
    }
    if ((step_index_ + id) % FRONT_COARSEN_EVERY_STEPS == 0 && coarsen_to_plane(id)) return;
    int64_t quiet;
    if (!meet(list, e.a, e.b, &quiet)) {
        if (e.plane_kept) release_plane(e);
        e.quiet_until = static_cast<int32_t>(quiet);
        return;
    }
    NodePlane plane;
    if (plane_separates(list, e.a, e.b, e.plane_kept ? &kept_planes_[e.certificate] : nullptr, plane)) {
        if (!e.plane_kept) ++counters_.bv_overlap_events;
        keep_plane(id, plane);
        ++counters_.plane_kept_steps;
        return;
    }
    if (e.plane_kept) release_plane(e);
    else ++counters_.bv_overlap_events;
    if (both_leaves(list, e.a, e.b)) {
        e.overlapping_leaf = true;
        cover(e);
        if (done_with(e)) remove_entry(id, false);
    } else {
        const int32_t a = e.a, b = e.b;
        remove_entry(id);
        expand(list_id, a, b);
    }
}

void KineticSeparationLists::run(const ProgressCallback& progress, WindowStop* stop) {
    progress_ = &progress;
    std::vector<bool> used(trees_.size(), false);
    for (size_t m = 0; m < trees_.size(); ++m) used[m] = trees_[m] != nullptr;
    times_ = breakpoint_times(scene_, used, t_begin_, t_end_);
    if (times_.size() == 1) times_.push_back(times_.front());  // an empty range: its one instant
    measure_travel();
    tester_.exchange_findings();  // a window cut from a running one starts knowing what earlier ones found
    for (size_t k = 0; k + 1 < times_.size(); ++k) {
        // Every step before k is done: all contacts before times_[k] are candidates.
        if (stop && k > 0 && stop->stops_before(times_[k])) break;
        step_index_ = static_cast<int64_t>(k);
        step_begin_ = times_[k];
        step_end_ = times_[k + 1];
        // The trees know their nodes' travel up to NODE_TRAVEL_AHEAD_STEPS steps after this one.
        const size_t recorded_end = std::min(times_.size() - 1, k + 1 + NODE_TRAVEL_AHEAD_STEPS);
        for (const auto& tree : trees_) {
            if (tree) {
                tree->fit(step_begin_, step_end_);
                for (size_t s = std::max(k + 1, travel_recorded_); s < recorded_end; ++s) {
                    tree->record_travel(static_cast<int64_t>(s), times_[s], times_[s + 1]);
                }
                ++counters_.kinetic_tree_events;
            }
        }
        travel_recorded_ = std::max(travel_recorded_, recorded_end);
        if (k == 0) {
            initializing_ = true;
            for (int32_t id = 0; id < static_cast<int32_t>(lists_.size()); ++id) {
                const List& list = lists_[id];
                if (list.self) {
                    expand(id, 0, 0);
                } else if (!meet(list, 0, 0)) {
                    create_entry(id, 0, 0, nullptr, false);
                } else if (both_leaves(list, 0, 0)) {
                    create_entry(id, 0, 0, nullptr, true);
                } else if (NodePlane plane; plane_separates(list, 0, 0, nullptr, plane)) {
                    create_plane_kept_entry(id, 0, 0, nullptr, plane);
                } else {
                    expand(id, 0, 0);
                }
            }
            initializing_ = false;
        } else {
            // Entries created during this step are up to date already.
            const int32_t slots = static_cast<int32_t>(entries_.size());
            for (int32_t id = 0; id < slots; ++id) {
                if (wake_step_[id] > step_index_) continue;
#if defined(__GNUC__)
                // Bringing an entry up to date mostly waits for its memory: ask for one further on meanwhile.
                if (id + kEntryPrefetchDistance < slots) __builtin_prefetch(&entries_[id + kEntryPrefetchDistance]);
#endif
                update(id);
                // It (or an entry that took its slot meanwhile) is up to date for this step.
                const Entry& e = entries_[id];
                if (e.alive) wake_step_[id] = std::max(static_cast<int32_t>(step_index_) + 1, e.quiet_until);
            }
        }
        step_shared_vertex_pairs();
        ++counters_.bv_change_events;
        if (stop) stop->reach(step_end_);
        tester_.exchange_findings();
        if (progress) progress(step_end_, static_cast<int64_t>(tester_.contacts().size()));
    }
    progress_ = nullptr;
}

} // namespace usdksl
