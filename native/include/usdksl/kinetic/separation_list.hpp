#pragma once
/// @file separation_list.hpp
/// @brief Kinetic separation lists (paper section 5): the BVTT front of every
///        checked mesh pair (or mesh against itself), kept valid by events.

#include "usdksl/collision/check.hpp"
#include "usdksl/collision/scene.hpp"
#include "usdksl/collision/triangle_pair_tester.hpp"
#include "usdksl/flightplan/crossing.hpp"
#include "usdksl/kinetic/event_queue.hpp"
#include "usdksl/kinetic/kinetic_aabb_tree.hpp"

#include <cstdint>
#include <memory>
#include <unordered_map>
#include <utility>
#include <vector>

namespace usdksl {

/// @brief All separation lists of one check, sharing one kinetic AABB tree per
///        mesh and one event queue. Each list entry is a BVTT node: a pair of
///        tree nodes that does not overlap (with the father it hangs from), or
///        an overlapping pair of leaves whose triangles the narrow phase tests
///        on every flightplan step while they keep overlapping.
class KineticSeparationLists {
public:
    KineticSeparationLists(const Scene& scene, const std::vector<std::pair<int32_t, int32_t>>& mesh_pairs,
                           TrianglePairTester& tester, Counters& counters, double t_begin, double t_end,
                           double thickness);

    /// @brief Processes every event up to t_end (time codes).
    void run(const ProgressCallback& progress);

private:
    struct List {
        int32_t mesh_a;
        int32_t mesh_b;
        bool self;
        std::unordered_map<uint64_t, int32_t> index;  // (a << 32 | b) -> entry
    };
    struct Entry {
        int32_t list = -1;
        int32_t a = -1, b = -1;      // tree nodes (mesh_a's tree, mesh_b's tree)
        int32_t fa = -1, fb = -1;    // BVTT father, -1 for the root pair
        bool overlapping_leaf = false;
        bool inert = false;          // leaf pair whose triangle pair is settled
        bool permanent = false;      // self leaf pair sharing a vertex: its boxes always overlap
        double tested_until = -1e300;  // end of the last flightplan step the narrow phase covered
        int32_t slot_a = -1, slot_b = -1;  // positions in the node entry lists
        uint8_t stale_gaps = 0;      // bit g: gap g's vertices changed since gap_rise[g] was computed
        double gap_rise[6] = {};     // non-overlapping entry: no gap g rises to 0 before gap_rise[g]
        double father_separation = 0.0;  // non-overlapping entry: its father does not separate before this
        bool alive = false;
    };
    struct NodeRef { int32_t entry; int32_t side; };  // side 0: node is entry.a, 1: entry.b
    struct NodePair { int32_t a, b; };

    // BVTT structure
    NodePair normalized(const List& list, int32_t a, int32_t b) const;
    bool father_of(const List& list, int32_t a, int32_t b, NodePair& father) const;
    int children_of(const List& list, int32_t a, int32_t b, NodePair out[4]) const;
    bool both_leaves(const List& list, int32_t a, int32_t b) const;

    // Kinetic geometry
    /// Scene units two boxes grow by before they count as overlapping: the
    /// pair's contact distance plus each box's own slack and padding.
    double margin_of(const List& list, int32_t a, int32_t b) const;
    AxisGap box_gap(const List& list, int32_t a, int32_t b, int gap) const;
    void box_gaps(const List& list, int32_t a, int32_t b, AxisGap gaps[6]) const;
    /// Which of an entry's six gaps the box side `slot` of its node on `side` (0: a, 1: b) enters.
    static int gap_of_side(int side, int slot);
    /// Time code before which gap `gap` of (a, b) does not rise to 0 (never late).
    double gap_rise(const List& list, int32_t a, int32_t b, int gap, double t) const;
    bool overlaps(const List& list, int32_t a, int32_t b, double t);
    double separation_time(const List& list, int32_t a, int32_t b, double t);
    /// Fills entry.gap_rise and returns their maximum (+inf when a gap never rises).
    double overlap_time(Entry& entry, double t);

    // Front maintenance
    int32_t create_entry(int32_t list, int32_t a, int32_t b, const NodePair* father, bool overlapping_leaf, double t);
    void remove_entry(int32_t id);
    void expand(int32_t list, int32_t a, int32_t b, double t);
    void remove_descendants(int32_t list, int32_t a, int32_t b);
    /// Runs the narrow phase on every step of a leaf pair from the one
    /// containing time code t (or after what is already tested) until one ends
    /// at or after `until`.
    void cover(Entry& entry, double t, double until);
    bool share_vertex(int32_t mesh, int32_t tri_a, int32_t tri_b) const;
    /// Key of a leaf pair of `list` in leaf_tested_until_.
    uint64_t tester_key(const List& list, int32_t a, int32_t b) const;
    void schedule(int32_t id, double t);
    void enqueue(int32_t id, double when, double t);
    /// After box changes: recomputes only the entry's stale gaps.
    void reschedule_stale_gaps(int32_t id, double t);

    // Events
    void process_tree_event(int64_t handle, double t);
    void process_entry_event(int32_t id, double t);
    /// @brief Counts one unit of work; calls progress every kProgressEveryWork units.
    void worked(double t);
    void node_changed(int32_t mesh, int32_t node, int slot);

    std::vector<NodeRef>& node_entries(int32_t mesh, int32_t node) { return node_entries_[mesh][node]; }

    const Scene& scene_;
    TrianglePairTester& tester_;
    Counters& counters_;
    double t_begin_, t_end_, thickness_;
    bool initializing_ = false;
    const ProgressCallback* progress_ = nullptr;  // set while run() runs
    int64_t work_ = 0;                            // entries scheduled and narrow-phase runs

    std::vector<std::unique_ptr<KineticAabbTree>> trees_;  // per mesh, null when unused
    std::vector<int64_t> tree_handle_base_;                // per mesh
    std::vector<std::vector<std::vector<NodeRef>>> node_entries_;
    int64_t entry_handle_base_ = 0;
    std::vector<List> lists_;
    std::vector<Entry> entries_;
    std::vector<int32_t> free_entries_;
    std::vector<double> margin_;  // per list: contact distance of its two meshes
    /// tested_until of leaf pairs whose entry was removed from the front, so a
    /// pair that returns does not run its narrow phase on the same steps again.
    std::unordered_map<uint64_t, double> leaf_tested_until_;
    EventQueue queue_;
    std::vector<int32_t> pending_reschedule_;
};

} // namespace usdksl
