/// @file region_grouping.cpp
/// @brief Contact walks per row on threads, then union-find over rows chained
///        per (mesh pair, vertex) in span order.

#include "usdksl/regions/region_grouping.hpp"

#include "usdksl/narrow_phase/triangle_pair.hpp"
#include "usdksl/run_on_threads.hpp"

#include <algorithm>
#include <array>
#include <numeric>
#include <stdexcept>

namespace usdksl {
namespace {

/// Rows handed to a thread at a time: enough to outweigh the hand-out.
constexpr int64_t ROWS_PER_TASK = 1024;

/// One face's triangles (ids and positions) at one sample.
struct PlacedFace {
    std::vector<Triangle> ids;
    std::vector<std::array<Vec3, 3>> points;

    void place(const MeshView& mesh, const FaceIndex& faces, int32_t face, const SampleBlend& blend) {
        ids.clear();
        points.clear();
        for (int64_t i = faces.triangle_begin(face); i < faces.triangle_end(face); ++i) {
            const int32_t tri = faces.triangles[static_cast<size_t>(i)];
            ids.push_back(mesh.triangle(tri));
            points.push_back(triangle_at(mesh, blend, tri));
        }
    }
};

/// True when a triangle of `a` and one of `b` are in contact. `first` (in,
/// out): the pair (i * b's triangles + j) to try first, the one that touched
/// last time: a contact that lasts usually stays on the same triangles.
bool faces_touch(const PlacedFace& a, const PlacedFace& b, bool same_mesh, double thickness, size_t& first) {
    const size_t pairs = a.ids.size() * b.ids.size();
    for (size_t k = 0; k < pairs; ++k) {
        const size_t pair = (first + k) % pairs;
        const size_t i = pair / b.ids.size(), j = pair % b.ids.size();
        if (triangle_pair_intersect_static(a.ids[i], a.points[i], b.ids[j], b.points[j], same_mesh, thickness)) {
            first = pair;
            return true;
        }
    }
    return false;
}

class UnionFind {
public:
    explicit UnionFind(int64_t count) : parent_(static_cast<size_t>(count)) {
        std::iota(parent_.begin(), parent_.end(), 0);
    }
    int64_t find(int64_t x) {
        while (parent_[x] != x) {
            parent_[x] = parent_[parent_[x]];
            x = parent_[x];
        }
        return x;
    }
    void unite(int64_t x, int64_t y) {
        x = find(x);
        y = find(y);
        if (x == y) return;
        if (x < y) std::swap(x, y);
        parent_[x] = y;  // the smaller row is the root
    }

private:
    std::vector<int64_t> parent_;
};

} // namespace

RegionGrouping group_regions(const std::vector<MeshView>& meshes, const ContactRows& rows,
                             const std::vector<double>& sample_times, double thickness, int32_t threads) {
    if (sample_times.empty() && rows.count > 0) throw std::invalid_argument("no sample times");
    check_contact_rows(meshes, rows);
    const int64_t count = rows.count;
    const int32_t last_sample = static_cast<int32_t>(sample_times.size()) - 1;
    RegionGrouping out;
    out.row_region.assign(static_cast<size_t>(count), -1);
    out.row_last_sampled.assign(static_cast<size_t>(count), 0.0);
    out.row_span_first.assign(static_cast<size_t>(count), 0);
    out.row_span_last.assign(static_cast<size_t>(count), 0);
    if (count == 0) return out;

    const std::vector<FaceIndex> faces = face_indexes_of_rows(meshes, rows);
    const std::vector<std::vector<SampleBlend>> blends = sample_blends_of_rows(meshes, rows, sample_times);
    // next_move[m][s]: the first sample at or after s at which mesh m may stand elsewhere than at the
    // sample before (the sample count when none). Between two samples at which both meshes hold still
    // (a static mesh, or times before a mesh's first sample or after its last) a contact cannot change.
    std::vector<std::vector<int32_t>> next_move(meshes.size());
    for (size_t m = 0; m < meshes.size(); ++m) {
        if (blends[m].empty()) continue;
        std::vector<int32_t>& next = next_move[m];
        next.assign(sample_times.size() + 1, last_sample + 1);
        for (int32_t s = last_sample; s >= 1; --s) {
            const SampleBlend& here = blends[m][s];
            const SampleBlend& before = blends[m][s - 1];
            const bool still = here.w == 0.0 && before.w == 0.0 && here.k0 == before.k0;
            next[s] = still ? next[s + 1] : s;
        }
        next[0] = 0;
    }

    // Spans: each row's walk through the samples while its faces stay in contact.
    const int64_t tasks = (count + ROWS_PER_TASK - 1) / ROWS_PER_TASK;
    parallel_for(std::max(threads, 1), static_cast<int32_t>(tasks), [&](int32_t task) {
        PlacedFace a, b;
        const int64_t end = std::min(count, (task + 1) * ROWS_PER_TASK);
        for (int64_t r = task * ROWS_PER_TASK; r < end; ++r) {
            const double time = rows.time[r];
            const int32_t ma = rows.mesh_a[r], mb = rows.mesh_b[r];
            const int32_t i0 = last_sample_at_or_before(sample_times, time);
            int32_t contact_last = -1;
            size_t first_pair = 0;
            for (int32_t s = first_sample_at_or_after(sample_times, time); s <= last_sample;) {
                a.place(meshes[ma], faces[ma], rows.face_a[r], blends[ma][s]);
                b.place(meshes[mb], faces[mb], rows.face_b[r], blends[mb][s]);
                if (!faces_touch(a, b, ma == mb, thickness, first_pair)) break;
                // while neither mesh moves, the contact holds: on to the next sample where one does
                const int32_t moves = std::min(next_move[ma][s + 1], next_move[mb][s + 1]);
                contact_last = moves - 1;
                s = moves;
            }
            out.row_last_sampled[r] = contact_last >= 0 ? sample_times[contact_last] : time;
            out.row_span_first[r] = i0;
            out.row_span_last[r] = std::min(std::max(i0 + 1, contact_last), last_sample);
        }
    });

    // Rows in span-start order (stable: table order among equal starts).
    std::vector<int64_t> by_start(static_cast<size_t>(count));
    {
        std::vector<int64_t> start_count(sample_times.size() + 1, 0);
        for (int64_t r = 0; r < count; ++r) ++start_count[out.row_span_first[r] + 1];
        for (size_t s = 1; s < start_count.size(); ++s) start_count[s] += start_count[s - 1];
        for (int64_t r = 0; r < count; ++r) by_start[static_cast<size_t>(start_count[out.row_span_first[r]]++)] = r;
    }

    // Rows per mesh pair, each list in span-start order.
    std::vector<int64_t> pair_key(static_cast<size_t>(count));
    const int64_t mesh_count = static_cast<int64_t>(meshes.size());
    for (int64_t r = 0; r < count; ++r) pair_key[r] = static_cast<int64_t>(rows.mesh_a[r]) * mesh_count + rows.mesh_b[r];
    std::vector<int64_t> by_pair(by_start);
    std::stable_sort(by_pair.begin(), by_pair.end(), [&](int64_t x, int64_t y) { return pair_key[x] < pair_key[y]; });

    UnionFind components(count);
    std::vector<int32_t> key_count;   // per vertex key of the current pair; zero between pairs
    std::vector<int64_t> key_start;
    std::vector<int32_t> touched;
    std::vector<int64_t> bucket;
    for (size_t begin = 0; begin < by_pair.size();) {
        size_t end = begin;
        while (end < by_pair.size() && pair_key[by_pair[end]] == pair_key[by_pair[begin]]) ++end;
        const int32_t ma = rows.mesh_a[by_pair[begin]], mb = rows.mesh_b[by_pair[begin]];
        const bool self = ma == mb;
        // Vertex keys: side a's vertices, then side b's (one set for a mesh with itself).
        const int64_t offset_b = self ? 0 : meshes[ma].vertex_count;
        const size_t keys = static_cast<size_t>(offset_b + meshes[mb].vertex_count);
        if (key_count.size() < keys) {
            key_count.resize(keys, 0);
            key_start.resize(keys, 0);
        }
        const auto for_each_key = [&](int64_t r, auto visit) {
            const FaceIndex& fa = faces[ma];
            const FaceIndex& fb = faces[mb];
            for (int64_t i = fa.vertex_begin(rows.face_a[r]); i < fa.vertex_end(rows.face_a[r]); ++i)
                visit(fa.vertices[static_cast<size_t>(i)]);
            for (int64_t i = fb.vertex_begin(rows.face_b[r]); i < fb.vertex_end(rows.face_b[r]); ++i)
                visit(offset_b + fb.vertices[static_cast<size_t>(i)]);
        };
        // Counting sort of (vertex key, row) by key, rows staying in span order.
        touched.clear();
        int64_t entries = 0;
        for (size_t i = begin; i < end; ++i) {
            for_each_key(by_pair[i], [&](int64_t key) {
                if (key_count[key]++ == 0) touched.push_back(static_cast<int32_t>(key));
                ++entries;
            });
        }
        int64_t next = 0;
        for (int32_t key : touched) {
            key_start[key] = next;
            next += key_count[key];
        }
        bucket.resize(static_cast<size_t>(entries));
        for (size_t i = begin; i < end; ++i) {
            const int64_t r = by_pair[i];
            for_each_key(r, [&](int64_t key) { bucket[static_cast<size_t>(key_start[key]++)] = r; });
        }
        // Per key: join each row to the row reaching furthest among those before it, when they overlap.
        int64_t at = 0;
        for (int32_t key : touched) {
            int32_t reach = -1;
            int64_t reaching = -1;
            for (int64_t i = at; i < at + key_count[key]; ++i) {
                const int64_t r = bucket[static_cast<size_t>(i)];
                if (out.row_span_first[r] <= reach) components.unite(r, reaching);
                if (out.row_span_last[r] > reach) {
                    reach = out.row_span_last[r];
                    reaching = r;
                }
            }
            at += key_count[key];
            key_count[key] = 0;
        }
        begin = end;
    }

    // Labels in the order of each region's first row.
    std::vector<int32_t> label(static_cast<size_t>(count), -1);
    for (int64_t r = 0; r < count; ++r) {
        const int64_t root = components.find(r);
        if (label[root] < 0) label[root] = out.region_count++;
        out.row_region[r] = label[root];
    }
    return out;
}

} // namespace usdksl
