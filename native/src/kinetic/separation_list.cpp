#include "usdksl/kinetic/separation_list.hpp"

#include "usdksl/flightplan/crossing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace usdksl {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr int64_t kProgressEveryEvents = 1 << 14;
/// Progress (where a stop request is raised) also comes after so many entries
/// scheduled or narrow-phase runs: one event can cost many narrow-phase steps
/// or reschedule every entry of a box, and setting up the lists (one expansion
/// of a whole self-overlapping tree) has no events at all.
constexpr int64_t kProgressEveryWork = 1 << 8;
constexpr double kNothingTested = -1e300;

uint64_t pair_key(int32_t a, int32_t b) {
    return (static_cast<uint64_t>(static_cast<uint32_t>(a)) << 32) | static_cast<uint32_t>(b);
}

/// Events must move time forward, or a tie could fire forever.
double after(double event_time, double now) {
    return event_time > now ? event_time : std::nextafter(now, kInfinity);
}

} // namespace

KineticSeparationLists::KineticSeparationLists(const Scene& scene,
                                               const std::vector<std::pair<int32_t, int32_t>>& mesh_pairs,
                                               TrianglePairTester& tester, Counters& counters, double t_begin,
                                               double t_end, double thickness)
    : scene_(scene), tester_(tester), counters_(counters), t_begin_(t_begin), t_end_(t_end),
      thickness_(thickness) {
    const size_t mesh_count = scene.meshes.size();
    trees_.resize(mesh_count);
    tree_handle_base_.assign(mesh_count, 0);
    node_entries_.resize(mesh_count);
    std::vector<bool> used(mesh_count, false);
    for (const auto& [ma, mb] : mesh_pairs) used[ma] = used[mb] = true;
    // Handles follow mesh order, which process_tree_event relies on.
    int64_t handles = 0;
    for (size_t mesh = 0; mesh < mesh_count; ++mesh) {
        tree_handle_base_[mesh] = handles;
        if (!used[mesh] || scene.meshes[mesh].triangles.empty()) continue;
        trees_[mesh] = std::make_unique<KineticAabbTree>(scene.plans[mesh], scene.meshes[mesh].triangles,
                                                         t_begin);
        handles += static_cast<int64_t>(trees_[mesh]->topology().node_count()) * BOX_SLOTS;
        node_entries_[mesh].resize(static_cast<size_t>(trees_[mesh]->topology().node_count()));
    }
    entry_handle_base_ = handles;
    for (const auto& [ma, mb] : mesh_pairs) {
        if (!trees_[ma] || !trees_[mb]) continue;
        List list{std::min(ma, mb), std::max(ma, mb), ma == mb, {}};
        lists_.push_back(std::move(list));
        margin_.push_back(scene.contact_distance(ma, mb, thickness));
    }
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

// ---------------------------------------------------------- kinetic geometry

double KineticSeparationLists::margin_of(const List& list, int32_t a, int32_t b) const {
    return margin_[&list - lists_.data()] + trees_[list.mesh_a]->box_margin(a) + trees_[list.mesh_b]->box_margin(b);
}

bool KineticSeparationLists::overlaps(const List& list, int32_t a, int32_t b, double t) {
    if (list.self && a == b) return true;
    ++counters_.bv_tests;
    const KineticAabbTree& ta = *trees_[list.mesh_a];
    const KineticAabbTree& tb = *trees_[list.mesh_b];
    const double margin = margin_of(list, a, b);
    for (int axis = 0; axis < 3; ++axis) {
        if (ta.side(a, 2 * axis + 1, t) - tb.side(b, 2 * axis, t) + margin < 0.0) return false;
        if (tb.side(b, 2 * axis + 1, t) - ta.side(a, 2 * axis, t) + margin < 0.0) return false;
    }
    return true;
}

AxisGap KineticSeparationLists::box_gap(const List& list, int32_t a, int32_t b, int gap) const {
    // Gap 2 * axis is max(a) - min(b), gap 2 * axis + 1 is max(b) - min(a),
    // grown by the margin; the boxes overlap exactly while all six are >= 0.
    const KineticAabbTree& ta = *trees_[list.mesh_a];
    const KineticAabbTree& tb = *trees_[list.mesh_b];
    const double margin = margin_of(list, a, b);
    const int axis = gap / 2;
    if (gap % 2 == 0) return {&ta.plans(), ta.extreme(a, 2 * axis + 1), &tb.plans(), tb.extreme(b, 2 * axis), axis, margin};
    return {&tb.plans(), tb.extreme(b, 2 * axis + 1), &ta.plans(), ta.extreme(a, 2 * axis), axis, margin};
}

void KineticSeparationLists::box_gaps(const List& list, int32_t a, int32_t b, AxisGap gaps[6]) const {
    for (int gap = 0; gap < 6; ++gap) gaps[gap] = box_gap(list, a, b, gap);
}

int KineticSeparationLists::gap_of_side(int side, int slot) {
    // Side 0 is the entry's node a: its maximum enters gap 2 * axis, its minimum gap 2 * axis + 1.
    const int axis = slot_axis(slot);
    return 2 * axis + ((side == 0) == slot_is_max(slot) ? 0 : 1);
}

double KineticSeparationLists::gap_rise(const List& list, int32_t a, int32_t b, int gap, double t) const {
    return first_gap_change(box_gap(list, a, b, gap), GapChange::RisesToZero, t, t_end_, KINETIC_SEARCH_PIECES).time;
}

double KineticSeparationLists::separation_time(const List& list, int32_t a, int32_t b, double t) {
    if (list.self && a == b) return kInfinity;
    AxisGap gaps[6];
    box_gaps(list, a, b, gaps);
    double earliest = kInfinity;
    for (const AxisGap& gap : gaps) {
        const CrossingTime c =
            first_gap_change(gap, GapChange::DropsBelowZero, t, std::min(earliest, t_end_), KINETIC_SEARCH_PIECES);
        earliest = std::min(earliest, c.time);
    }
    return earliest;
}

double KineticSeparationLists::overlap_time(Entry& e, double t) {
    // Boxes overlap when all six gaps are >= 0; each gap's first rise is no
    // later than that moment, so their maximum is a bound that never fires
    // late. Each rise stays a valid bound until that gap's vertices change,
    // so the entry keeps all six and a box change recomputes only its own.
    const List& list = lists_[e.list];
    for (int gap = 0; gap < 6; ++gap) e.gap_rise[gap] = t;
    for (int gap = 0; gap < 6; ++gap) {
        e.gap_rise[gap] = gap_rise(list, e.a, e.b, gap, t);
        if (std::isinf(e.gap_rise[gap])) return kInfinity;
    }
    return *std::max_element(e.gap_rise, e.gap_rise + 6);
}

// --------------------------------------------------------- front maintenance

int32_t KineticSeparationLists::create_entry(int32_t list_id, int32_t a, int32_t b, const NodePair* father,
                                             bool overlapping_leaf, double t) {
    int32_t id;
    if (!free_entries_.empty()) {
        id = free_entries_.back();
        free_entries_.pop_back();
    } else {
        id = static_cast<int32_t>(entries_.size());
        entries_.emplace_back();
    }
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
    list.index.emplace(pair_key(a, b), id);
    auto& na = node_entries(list.mesh_a, a);
    e.slot_a = static_cast<int32_t>(na.size());
    na.push_back({id, 0});
    auto& nb = node_entries(list.mesh_b, b);
    e.slot_b = static_cast<int32_t>(nb.size());
    nb.push_back({id, 1});
    if (both_leaves(list, a, b)) {
        const int32_t tri_a = trees_[list.mesh_a]->topology().triangle[a];
        const int32_t tri_b = trees_[list.mesh_b]->topology().triangle[b];
        e.permanent = list.self && share_vertex(list.mesh_a, tri_a, tri_b);
        const auto saved = leaf_tested_until_.find(tester_key(list, a, b));
        if (saved != leaf_tested_until_.end()) {
            e.tested_until = saved->second;
            leaf_tested_until_.erase(saved);
        }
        if (overlapping_leaf) {
            if (tester_.settled(list.mesh_a, tri_a, list.mesh_b, tri_b)) {
                e.inert = true;
            } else if (initializing_ && tester_.test_static(list.mesh_a, tri_a, list.mesh_b, tri_b, t)) {
                e.inert = true;
            }
        }
    }
    schedule(id, t);
    return id;
}

void KineticSeparationLists::remove_entry(int32_t id) {
    Entry& e = entries_[id];
    List& list = lists_[e.list];
    queue_.cancel(entry_handle_base_ + id);
    list.index.erase(pair_key(e.a, e.b));
    const auto unlink = [&](int32_t mesh, int32_t node, int32_t slot) {
        auto& refs = node_entries(mesh, node);
        const NodeRef moved = refs.back();
        refs[slot] = moved;
        refs.pop_back();
        if (static_cast<size_t>(slot) < refs.size()) {
            Entry& m = entries_[moved.entry];
            (moved.side == 0 ? m.slot_a : m.slot_b) = slot;
        }
    };
    unlink(list.mesh_a, e.a, e.slot_a);
    unlink(list.mesh_b, e.b, e.slot_b);
    // A leaf pair keeps what its narrow phase covered, should it come back.
    if (!e.inert && e.tested_until > kNothingTested && both_leaves(list, e.a, e.b)) {
        leaf_tested_until_[tester_key(list, e.a, e.b)] = e.tested_until;
    }
    e.alive = false;
    free_entries_.push_back(id);
}

void KineticSeparationLists::expand(int32_t list_id, int32_t a, int32_t b, double t) {
    // Descend straight to the deepest non-overlapping pairs (section 6.1).
    const List& list = lists_[list_id];
    NodePair children[4];
    const int count = children_of(list, a, b, children);
    const NodePair father{a, b};
    for (int i = 0; i < count; ++i) {
        const NodePair c = children[i];
        if (list.self && c.a == c.b && trees_[list.mesh_a]->topology().is_leaf(c.a)) continue;
        if (!overlaps(list, c.a, c.b, t)) {
            create_entry(list_id, c.a, c.b, &father, false, t);
        } else if (both_leaves(list, c.a, c.b)) {
            create_entry(list_id, c.a, c.b, &father, true, t);
        } else {
            expand(list_id, c.a, c.b, t);
        }
    }
}

void KineticSeparationLists::remove_descendants(int32_t list_id, int32_t a, int32_t b) {
    const List& list = lists_[list_id];
    NodePair children[4];
    const int count = children_of(list, a, b, children);
    for (int i = 0; i < count; ++i) {
        const auto it = list.index.find(pair_key(children[i].a, children[i].b));
        if (it != list.index.end()) remove_entry(it->second);
        else remove_descendants(list_id, children[i].a, children[i].b);
    }
}

void KineticSeparationLists::cover(Entry& e, double t, double until) {
    if (e.inert || e.tested_until >= until) return;
    const List& list = lists_[e.list];
    const int32_t tri_a = trees_[list.mesh_a]->topology().triangle[e.a];
    const int32_t tri_b = trees_[list.mesh_b]->topology().triangle[e.b];
    if (tester_.settled(list.mesh_a, tri_a, list.mesh_b, tri_b)) {
        e.inert = true;
        return;
    }
    const StepRun run = tester_.test_steps(list.mesh_a, tri_a, list.mesh_b, tri_b, std::max(t, e.tested_until), until);
    e.tested_until = run.tested_until;
    if (run.hit) e.inert = true;
    worked(t);
}

void KineticSeparationLists::worked(double t) {
    if (progress_ && *progress_ && (++work_ % kProgressEveryWork) == 0) {
        (*progress_)(t, static_cast<int64_t>(tester_.contacts().size()));
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

uint64_t KineticSeparationLists::tester_key(const List& list, int32_t a, int32_t b) const {
    return tester_.key(list.mesh_a, trees_[list.mesh_a]->topology().triangle[a], list.mesh_b,
                       trees_[list.mesh_b]->topology().triangle[b]);
}

void KineticSeparationLists::schedule(int32_t id, double t) {
    worked(t);
    Entry& e = entries_[id];
    const List& list = lists_[e.list];
    double when = kInfinity;
    if (e.overlapping_leaf) {
        // The narrow phase covers every step until the leaves may separate, in
        // one loop; the event then asks whether they did. Leaves that share a
        // vertex never separate: their whole shot is covered at once.
        if (!e.inert) {
            when = e.permanent ? kInfinity : separation_time(list, e.a, e.b, t);
            cover(e, t, std::min(when, t_end_));
            if (e.inert) when = kInfinity;
        }
    } else {
        e.father_separation = e.fa >= 0 ? separation_time(list, e.fa, e.fb, t) : kInfinity;
        when = std::min(overlap_time(e, t), e.father_separation);
    }
    enqueue(id, when, t);
}

void KineticSeparationLists::enqueue(int32_t id, double when, double t) {
    if (when > t_end_) {
        queue_.cancel(entry_handle_base_ + id);
        return;
    }
    queue_.schedule(entry_handle_base_ + id, after(when, t));
}

void KineticSeparationLists::reschedule_stale_gaps(int32_t id, double t) {
    Entry& e = entries_[id];
    const List& list = lists_[e.list];
    for (int gap = 0; gap < 6; ++gap) {
        if (e.stale_gaps & (1u << gap)) e.gap_rise[gap] = gap_rise(list, e.a, e.b, gap, t);
    }
    e.stale_gaps = 0;
    // The father's separation bound holds whatever changed below it.
    enqueue(id, std::min(*std::max_element(e.gap_rise, e.gap_rise + 6), e.father_separation), t);
}

// -------------------------------------------------------------------- events

void KineticSeparationLists::process_entry_event(int32_t id, double t) {
    Entry& e = entries_[id];
    const List& list = lists_[e.list];
    if (e.overlapping_leaf) {
        if (!overlaps(list, e.a, e.b, t)) {
            ++counters_.leaves_do_not_overlap_events;
            e.overlapping_leaf = false;
        } else {
            ++counters_.polygons_collide_events;
        }
        schedule(id, t);
        return;
    }
    NodePair father{e.fa, e.fb};
    if (e.fa >= 0 && !overlaps(list, e.fa, e.fb, t)) {
        // Ascend to the highest pair that does not overlap (section 6.1).
        ++counters_.fathers_do_not_overlap_events;
        const int32_t list_id = e.list;
        NodePair top = father;
        NodePair up;
        bool has_up = father_of(list, top.a, top.b, up);
        while (has_up && !overlaps(list, up.a, up.b, t)) {
            top = up;
            has_up = father_of(list, top.a, top.b, up);
        }
        remove_descendants(list_id, top.a, top.b);
        create_entry(list_id, top.a, top.b, has_up ? &up : nullptr, false, t);
        return;
    }
    if (overlaps(list, e.a, e.b, t)) {
        ++counters_.bv_overlap_events;
        if (both_leaves(list, e.a, e.b)) {
            e.overlapping_leaf = true;
            schedule(id, t);
        } else {
            const int32_t list_id = e.list, a = e.a, b = e.b;
            remove_entry(id);
            expand(list_id, a, b, t);
        }
        return;
    }
    schedule(id, t);  // the overlap bound fired early: look again from here
}

void KineticSeparationLists::node_changed(int32_t mesh, int32_t node, int slot) {
    ++counters_.bv_change_events;
    // Only a pending overlap event can become late when a box grows, and only
    // through the one gap the changed side enters. Separation events (of
    // overlapping leaves, and of the father an entry hangs from) computed with
    // a vertex that is no longer extreme can only come early, since no single
    // vertex reaches beyond its box's true side; an early event looks again,
    // a late one would merely keep the front finer for longer.
    for (const NodeRef& ref : node_entries(mesh, node)) {
        Entry& e = entries_[ref.entry];
        if (e.overlapping_leaf) continue;
        if (e.stale_gaps == 0) pending_reschedule_.push_back(ref.entry);
        e.stale_gaps |= static_cast<uint8_t>(1u << gap_of_side(ref.side, slot));
    }
}

void KineticSeparationLists::process_tree_event(int64_t handle, double t) {
    ++counters_.kinetic_tree_events;
    // The last mesh whose handle range starts at or before `handle` and has a tree.
    int32_t mesh = static_cast<int32_t>(
        std::upper_bound(tree_handle_base_.begin(), tree_handle_base_.end(), handle) - tree_handle_base_.begin()) - 1;
    while (!trees_[mesh]) --mesh;
    KineticAabbTree& tree = *trees_[mesh];
    const int64_t local = handle - tree_handle_base_[mesh];
    int32_t node = static_cast<int32_t>(local / BOX_SLOTS);
    const int slot = static_cast<int>(local % BOX_SLOTS);
    pending_reschedule_.clear();
    bool changed = tree.repick(node, slot, t);
    queue_.schedule(handle, tree.certificate_failure(node, slot, t, t_end_));
    while (changed) {
        node_changed(mesh, node, slot);
        node = tree.topology().parent[node];
        if (node < 0) break;
        changed = tree.repick(node, slot, t);
        const int64_t parent_handle = tree_handle_base_[mesh] + static_cast<int64_t>(node) * BOX_SLOTS + slot;
        queue_.schedule(parent_handle, tree.certificate_failure(node, slot, t, t_end_));
    }
    for (int32_t id : pending_reschedule_) reschedule_stale_gaps(id, t);
}

void KineticSeparationLists::run(const ProgressCallback& progress) {
    progress_ = &progress;
    for (size_t m = 0; m < trees_.size(); ++m) {
        if (!trees_[m]) continue;
        const int32_t nodes = trees_[m]->topology().node_count();
        for (int32_t node = 0; node < nodes; ++node) {
            for (int slot = 0; slot < BOX_SLOTS; ++slot) {
                queue_.schedule(tree_handle_base_[m] + static_cast<int64_t>(node) * BOX_SLOTS + slot,
                                trees_[m]->certificate_failure(node, slot, t_begin_, t_end_));
            }
        }
    }
    initializing_ = true;
    for (int32_t id = 0; id < static_cast<int32_t>(lists_.size()); ++id) {
        const List& list = lists_[id];
        if (list.self) {
            expand(id, 0, 0, t_begin_);
        } else if (!overlaps(list, 0, 0, t_begin_)) {
            create_entry(id, 0, 0, nullptr, false, t_begin_);
        } else if (both_leaves(list, 0, 0)) {
            create_entry(id, 0, 0, nullptr, true, t_begin_);
        } else {
            expand(id, 0, 0, t_begin_);
        }
    }
    initializing_ = false;
    int64_t processed = 0;
    while (!queue_.empty() && queue_.top_time() <= t_end_) {
        const double t = queue_.top_time();
        const int64_t handle = queue_.pop();
        if (handle < entry_handle_base_) process_tree_event(handle, t);
        else process_entry_event(static_cast<int32_t>(handle - entry_handle_base_), t);
        if (progress && (++processed % kProgressEveryEvents) == 0) {
            progress(t, static_cast<int64_t>(tester_.contacts().size()));
        }
    }
    progress_ = nullptr;
}

} // namespace usdksl
