/// @file inclusion_root_finder.cpp
/// @brief Earliest-time-first subdivision of the (t,u,v) parameter box.
///
/// F is multilinear in (t,u,v) (no u*v term), so over a parameter box its
/// exact image lies in the axis-aligned hull of its 8 corner values. Each
/// corner is computed in floating point with a known error bound, so a box is
/// discarded only when the hull, widened by that bound, misses the cube
/// [-thickness, thickness]^3 on some axis: no root can hide there. A box
/// whose float hull on some axis lies within that bound of excluding it is
/// decided again in exact arithmetic, so a near miss smaller than the
/// rounding bound is not a contact.

#include "inclusion_root_finder.hpp"
#include "rounding_bounds.hpp"
#include "whole_step_exclusion.hpp"

#include "usdksl/ccd/ccd_constants.hpp"
#include "usdksl/ccd/corner_sign.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace usdksl {
namespace {

/// Heap order: earliest t_lo on top; among equal t_lo the deepest box, so the
/// search dives (depth first) into the earliest candidate region.
struct LaterFirst {
    bool operator()(const ParameterBox& a, const ParameterBox& b) const {
        if (a.t_lo != b.t_lo) return a.t_lo > b.t_lo;
        return a.depth < b.depth;
    }
};

/// Point-pair indices (minuend, subtrahend) of W, E1, E2 per primitive kind.
constexpr PairIndices VERTEX_FACE_PAIRS{0, 1, 2, 1, 3, 1};
constexpr PairIndices EDGE_EDGE_PAIRS{0, 2, 0, 1, 3, 2};

/// Distance-function values at the 8 corners of the last evaluated box:
/// per world axis, and projected on each separating direction (corner index
/// it*4 + iu*2 + iv).
struct BoxImage {
    /// Up to 4 chosen once per search, 3 more per box (add_box_directions)
    /// and, above thickness 0, the box's closest-point direction.
    static constexpr int MAX_DIRECTIONS = 8;
    double corner[2][2][2][3];
    double projected[MAX_DIRECTIONS][8];
    /// Per world axis: the hull of the float corner values.
    double axis_lo[3], axis_hi[3];
};

/// W, E1, E2 at one time, computed in the exact operation order the error
/// bound CCD_CORNER_ERROR_FACTOR was derived for.
struct TermsAtTime {
    double w[3], e1[3], e2[3];
};

/// The face of a vertex-face pair at one end of the step: edge lengths (edge
/// opposite each corner 1..3) and a normal crossed at the corner opposite the
/// longest edge, from the two shortest edges (on a sliver, crossing its two
/// long edges would cancel).
struct FaceShape {
    double opposite_length[4];
    int widest_corner;
    Vec3 normal;

    explicit FaceShape(const std::array<Vec3, 4>& points) : points_(points) {
        widest_corner = 1;
        for (int corner = 1; corner <= 3; ++corner) {
            opposite_length[corner] = (points[corner % 3 + 1] - points[(corner + 1) % 3 + 1]).norm();
            if (opposite_length[corner] > opposite_length[widest_corner]) widest_corner = corner;
        }
        const Vec3& origin = points[widest_corner];
        normal = (points[widest_corner % 3 + 1] - origin).cross(points[(widest_corner + 1) % 3 + 1] - origin);
    }

    /// Barycentric weight of `corner` in the projection of the vertex (point
    /// 0) onto the face's plane; NaN for a degenerate face.
    double projected_weight(int corner) const {
        const Vec3& next = points_[corner % 3 + 1];
        const Vec3& last = points_[(corner + 1) % 3 + 1];
        return (last - next).cross(points_[0] - next).dot(normal) / normal.squaredNorm();
    }

private:
    const std::array<Vec3, 4>& points_;
};

/// Order in which the root search takes the four points of a vertex-face
/// pair: the vertex, then the face corners, first the one that becomes the
/// origin of the (u,v) parameters. Boxes are axis-aligned in (u,v), so the
/// two face edges through the origin are axis-aligned, but the edge opposite
/// it, u + v = 1, cuts boxes diagonally. Two things make an origin costly:
/// a narrow angle there (E1 and E2 nearly parallel, F varying with u + v
/// alone: on a sliver whose corner was blown far away, taking that corner
/// first cost one query over 10^5 boxes) and a root set running along the
/// opposite edge. So the origin is the corner opposite the longest edge (its
/// angle is the widest), unless the vertex projects within
/// FACE_ORIGIN_NEAR_EDGE_WEIGHT of that edge (barycentrically, at either end
/// of the step); then it is the wide corner (opposite edge at least
/// FACE_ORIGIN_WIDE_EDGE_RATIO of the longest at both ends) with the largest
/// weight. The face is the same point set in any order, so only the cost
/// changes, never the answer; NaN and ties keep the given order.
std::array<int, 4> face_corner_order(const MultilinearDistance& f) {
    const FaceShape shapes[2] = {FaceShape(f.at_start), FaceShape(f.at_end)};
    auto weight = [&](int corner) {
        const double at_start = shapes[0].projected_weight(corner);
        const double at_end = shapes[1].projected_weight(corner);
        // A face degenerate at one end is judged by the other end alone.
        return std::isnan(at_start) ? at_end : std::isnan(at_end) ? at_start : std::min(at_start, at_end);
    };
    int origin = 1;
    double origin_length = -1.0;
    for (int corner = 1; corner <= 3; ++corner) {
        const double summed = shapes[0].opposite_length[corner] * shapes[0].opposite_length[corner] +
                              shapes[1].opposite_length[corner] * shapes[1].opposite_length[corner];
        if (summed > origin_length) {
            origin_length = summed;
            origin = corner;
        }
    }
    double best = weight(origin);
    if (best < FACE_ORIGIN_NEAR_EDGE_WEIGHT) {
        for (int corner = 1; corner <= 3; ++corner) {
            bool wide = true;
            for (const FaceShape& shape : shapes) {
                const double longest = shape.opposite_length[shape.widest_corner];
                wide = wide && !(shape.opposite_length[corner] < FACE_ORIGIN_WIDE_EDGE_RATIO * longest);
            }
            if (!wide || corner == origin) continue;
            const double candidate = weight(corner);
            if (candidate > best) {
                best = candidate;
                origin = corner;
            }
        }
    }
    return {0, origin, origin % 3 + 1, (origin + 1) % 3 + 1};
}

class RootSearch {
public:
    RootSearch(const MultilinearDistance& f, const CCDSettings& settings)
        : pairs_(f.kind == PrimitivePairKind::VertexFace ? VERTEX_FACE_PAIRS : EDGE_EDGE_PAIRS),
          is_vertex_face_(f.kind == PrimitivePairKind::VertexFace) {
        const std::array<int, 4> order =
            is_vertex_face_ ? face_corner_order(f) : std::array<int, 4>{0, 1, 2, 3};
        double max_abs[3] = {0.0, 0.0, 0.0};
        bool finite = true;
        for (int i = 0; i < 4; ++i) {
            const int source = order[i];
            for (int k = 0; k < 3; ++k) {
                start_[i][k] = f.at_start[source][k];
                end_[i][k] = f.at_end[source][k];
                displacement_[i][k] = f.at_end[source][k] - f.at_start[source][k];
                max_abs[k] = std::max({max_abs[k], std::abs(f.at_start[source][k]),
                                       std::abs(f.at_end[source][k])});
                finite = finite && std::isfinite(start_[i][k]) && std::isfinite(end_[i][k]);
            }
        }
        thickness_ = std::max(settings.thickness, 0.0);
        const double thickness = thickness_;
        double error[3];
        for (int k = 0; k < 3; ++k) {
            error[k] = corner_error(max_abs[k]);
            bound_[k] = axis_bound(thickness, error[k]);
            exact_margin_[k] = EXACT_CHECK_ERROR_MULTIPLE * error[k];
            corner_error_[k] = error[k];
            vanishes_[k] = true;
            for (int i = 1; i < 4; ++i)
                vanishes_[k] = vanishes_[k] && start_[i][k] == start_[0][k] && end_[i][k] == end_[0][k];
        }
        euclidean_ = thickness > 0.0;
        double error_squared = 0.0;
        for (int k = 0; k < 3; ++k) error_squared += error[k] * error[k];
        const double ball_reach = (thickness + std::sqrt(error_squared)) * CCD_BOUND_INFLATION;
        ball_reach_squared_ = ball_reach * ball_reach * CCD_BOUND_INFLATION;
        exact_possible_ = finite && std::isfinite(thickness) &&
                          std::max({max_abs[0], max_abs[1], max_abs[2], thickness}) <= EXACT_CHECK_MAX_MAGNITUDE;
        for (int k = 0; k < 3; ++k) max_abs_[k] = max_abs[k];
    }

    /// The separating directions, chosen on first use: most queries end
    /// on their first box, many before a direction is needed.
    void ensure_directions() {
        if (directions_chosen_) return;
        directions_chosen_ = true;
        choose_separating_directions(thickness_, corner_error_, max_abs_);
        search_direction_count_ = direction_count_;
        for (int k = 0; k < 3; ++k) {
            rates_.w[k] = displacement_[pairs_.w_plus][k] - displacement_[pairs_.w_minus][k];
            rates_.e1[k] = displacement_[pairs_.e1_plus][k] - displacement_[pairs_.e1_minus][k];
            rates_.e2[k] = displacement_[pairs_.e2_plus][k] - displacement_[pairs_.e2_minus][k];
        }
    }

    /// Directions that each isolate one parameter near the box: the rows of
    /// the inverse Jacobian of F at the box's centre, up to scale (n_t is
    /// orthogonal to dF/du and dF/dv, so n_t.F varies with t alone to first
    /// order, and likewise n_u, n_v). Clipping along them narrows every
    /// parameter to second-order terms of the box's widths, where the world
    /// axes and the fixed directions narrow it only by a constant factor per
    /// split (the face normal turns during the step). At thickness 0 their
    /// bounds hold the whole thickness cube (DirectionBound::Cube), so they
    /// exclude nothing the world axes accept: what a search accepts stays the
    /// same whatever the motion (a still pair gets none of them), only found
    /// sooner. Above 0 the contact region is the thickness ball, which the
    /// final decision tests along the closest-point direction, so they take
    /// the ball's tighter bound. Appended after the search's own directions
    /// (ensure_directions first).
    void add_box_directions(const ParameterBox& box) {
        const double t = 0.5 * (box.t_lo + box.t_hi);
        const double u = 0.5 * (box.u_lo + box.u_hi);
        const double v = 0.5 * (box.v_lo + box.v_hi);
        const TermsAtTime at = terms_at(t);
        Vec3 along_t, along_u, along_v;
        for (int k = 0; k < 3; ++k) {
            along_t[k] = rates_.w[k] - u * rates_.e1[k] - v * rates_.e2[k];
            along_u[k] = at.e1[k];
            along_v[k] = at.e2[k];
        }
        const Vec3 isolates_t = along_u.cross(along_v);
        // A singular Jacobian (coplanar motion, parallel edges) has no such
        // rows: the directions would separate no better than the fixed ones.
        const double volume = std::abs(isolates_t.dot(along_t));
        if (!(volume > BOX_DIRECTIONS_MIN_SINE * isolates_t.norm() * along_t.norm())) return;
        const DirectionBound bound = euclidean_ ? DirectionBound::Euclidean : DirectionBound::Cube;
        add_direction(isolates_t, thickness_, corner_error_, max_abs_, bound);
        add_direction(along_v.cross(along_t), thickness_, corner_error_, max_abs_, bound);
        add_direction(along_t.cross(along_u), thickness_, corner_error_, max_abs_, bound);
    }

    /// The part of a box's (u, v) range inside the parameter domain, as a
    /// convex polygon (counter-clockwise): the range itself for edge-edge,
    /// cut by u + v <= 1 for vertex-face (up to 5 vertices). Cut points are
    /// rounded away from the domain, so the polygon holds the exact part.
    struct DomainPolygon {
        int count = 0;
        double u[5], v[5];
    };

    DomainPolygon domain_polygon(const ParameterBox& box) const {
        const double us[4] = {box.u_lo, box.u_hi, box.u_hi, box.u_lo};
        const double vs[4] = {box.v_lo, box.v_lo, box.v_hi, box.v_hi};
        DomainPolygon polygon;
        for (int i = 0; i < 4; ++i) {
            const bool inside = !is_vertex_face_ || us[i] + vs[i] <= 1.0;
            if (inside) {
                polygon.u[polygon.count] = us[i];
                polygon.v[polygon.count++] = vs[i];
            }
            const int j = (i + 1) % 4;
            const bool next_inside = !is_vertex_face_ || us[j] + vs[j] <= 1.0;
            if (inside == next_inside || polygon.count >= 5) continue;
            // The side runs along u (v fixed) or along v (u fixed).
            const bool along_u = vs[i] == vs[j];
            polygon.u[polygon.count] = along_u ? std::nextafter(1.0 - vs[i], INFINITY) : us[i];
            polygon.v[polygon.count++] = along_u ? vs[i] : std::nextafter(1.0 - us[i], INFINITY);
        }
        return polygon;
    }

    /// Above thickness 0: the direction from the origin to the point of F's
    /// image nearest to it at the box's middle time (over the box's part of
    /// the domain), so that the box's slab along it measures its Euclidean
    /// distance from the origin to first order. This slab, bounded by the
    /// thickness ball, is what makes the accepted region the ball rather than
    /// the cube the world axes bound: a box no direction excludes is narrowed
    /// to the tolerance, where its hull lies within the thickness of the
    /// origin along this direction, up to rounding and the box's size.
    void add_closest_point_direction(const ParameterBox& box) {
        const TermsAtTime at = terms_at(0.5 * (box.t_lo + box.t_hi));
        const Vec3 w(at.w[0], at.w[1], at.w[2]);
        const Vec3 e1(at.e1[0], at.e1[1], at.e1[2]);
        const Vec3 e2(at.e2[0], at.e2[1], at.e2[2]);
        add_direction(nearest_in_polygon(w, e1, e2, domain_polygon(box)), thickness_, corner_error_, max_abs_,
                      DirectionBound::Euclidean);
    }

    /// The point w - u e1 - v e2 nearest the origin over (u, v) in a convex
    /// polygon (a convex quadratic: the free minimum when it lies inside,
    /// else the nearest point of the sides, each a clamped 1-D minimum).
    static Vec3 nearest_in_polygon(const Vec3& w, const Vec3& e1, const Vec3& e2, const DomainPolygon& polygon) {
        const double a = e1.squaredNorm(), b = e1.dot(e2), c = e2.squaredNorm();
        const double det = a * c - b * b;
        if (det > NEAREST_POINT_MIN_SINE_SQUARED * a * c) {
            const double d = w.dot(e1), e = w.dot(e2);
            const double u = (c * d - b * e) / det;
            const double v = (a * e - b * d) / det;
            bool inside = true;
            for (int i = 0; i < polygon.count && inside; ++i) {
                const int j = (i + 1) % polygon.count;
                const double cross = (polygon.u[j] - polygon.u[i]) * (v - polygon.v[i]) -
                                     (polygon.v[j] - polygon.v[i]) * (u - polygon.u[i]);
                inside = cross >= 0.0;
            }
            if (inside) return w - u * e1 - v * e2;
        }
        Vec3 best = w - polygon.u[0] * e1 - polygon.v[0] * e2;
        for (int i = 0; i < polygon.count; ++i) {
            const int j = (i + 1) % polygon.count;
            const Vec3 from = w - polygon.u[i] * e1 - polygon.v[i] * e2;
            const Vec3 side = (w - polygon.u[j] * e1 - polygon.v[j] * e2) - from;
            const double length_squared = side.squaredNorm();
            const double s = length_squared > 0.0 ? std::clamp(-from.dot(side) / length_squared, 0.0, 1.0) : 0.0;
            const Vec3 p = from + s * side;
            if (p.squaredNorm() < best.squaredNorm()) best = p;
        }
        return best;
    }

    /// A vertex-face box reaching past the face's edge u + v = 1 (its corner
    /// (u_hi, v_hi) lies outside the face).
    bool crosses_face_edge(const ParameterBox& box) const { return is_vertex_face_ && box.u_hi + box.v_hi > 1.0; }

    /// F at the vertices of a box's domain polygon, at t_lo and t_hi.
    struct FaceImage {
        DomainPolygon polygon;
        double values[2][5][3];
    };

    FaceImage face_image(const ParameterBox& box) const {
        FaceImage face;
        face.polygon = domain_polygon(box);
        for (int it = 0; it < 2; ++it) {
            const TermsAtTime at = terms_at(it == 0 ? box.t_lo : box.t_hi);
            for (int i = 0; i < face.polygon.count; ++i) {
                for (int k = 0; k < 3; ++k)
                    face.values[it][i][k] = at.w[k] - face.polygon.u[i] * at.e1[k] - face.polygon.v[i] * at.e2[k];
            }
        }
        return face;
    }

    /// Narrows [lower, upper] (fractions of a vertex-face box's time range
    /// reaching past the face's edge) to where a root inside the face can
    /// lie: at any time F over the domain polygon ranges between its values
    /// at the polygon's vertices (F is affine in (u, v)), each linear in t, so
    /// clip_constraint's rule holds with those lines in place of the box's
    /// edges along t. The box's corners beyond the edge cannot pin its early
    /// end where the face's nearest point lies on that edge (Newton's cards
    /// beside each other's diagonal: a box's time range then shrank by 1/64
    /// per split, over 10^5 boxes a query).
    void clip_time_within_face(const ParameterBox& box, double& lower, double& upper) const {
        const FaceImage face = face_image(box);
        const int count = face.polygon.count;
        double values[10];
        auto narrow = [&](double bound) {
            if (!holds_everywhere(values, 2 * count, bound))
                narrow_to_lines(values, values + count, count, bound, lower, upper);
        };
        for (int k = 0; k < 3; ++k) {
            for (int i = 0; i < count; ++i) {
                values[i] = face.values[0][i][k];
                values[count + i] = face.values[1][i][k];
            }
            narrow(bound_[k]);
        }
        for (int d = 0; d < direction_count_; ++d) {
            const double* n = directions_[d].n;
            for (int it = 0; it < 2; ++it) {
                for (int i = 0; i < count; ++i) values[it * count + i] = projected_on(n, face.values[it][i]);
            }
            narrow(directions_[d].bound);
        }
    }

    /// Above thickness 0: a corner of the box at its earliest time, inside
    /// the parameter domain, whose float value lies within the thickness ball
    /// widened by its rounding bound: F is that close at time t_lo.
    bool corner_in_ball_at_start(const ParameterBox& box, const double corner[2][2][2][3]) const {
        const double us[2] = {box.u_lo, box.u_hi};
        const double vs[2] = {box.v_lo, box.v_hi};
        for (int iu = 0; iu < 2; ++iu) {
            for (int iv = 0; iv < 2; ++iv) {
                if (is_vertex_face_ && us[iu] + vs[iv] > 1.0) continue;
                const double* f = corner[0][iu][iv];
                if (f[0] * f[0] + f[1] * f[1] + f[2] * f[2] <= ball_reach_squared_) return true;
            }
        }
        return false;
    }

    TermsAtTime terms_at(double t) const {
        double position[4][3];
        for (int i = 0; i < 4; ++i)
            for (int k = 0; k < 3; ++k) position[i][k] = start_[i][k] + t * displacement_[i][k];
        TermsAtTime terms;
        for (int k = 0; k < 3; ++k) {
            terms.w[k] = position[pairs_.w_plus][k] - position[pairs_.w_minus][k];
            terms.e1[k] = position[pairs_.e1_plus][k] - position[pairs_.e1_minus][k];
            terms.e2[k] = position[pairs_.e2_plus][k] - position[pairs_.e2_minus][k];
        }
        return terms;
    }

    /// Outcome of evaluating one box. Straddles is not final: the box may
    /// still be excluded exactly (excluded_exactly), which the caller asks
    /// last, as any exclusion drops the box alike and the exact one costs
    /// most.
    enum class Verdict { Excluded, Inside, Straddles };

    /// Which parameter-variation measure the split rule asks for.
    enum class SplitRule { Targeted, Overall };

    /// Evaluates the 8 corners; on Straddles, fills `variation` with how much
    /// each parameter (t, u, v) moves F: for the Targeted rule, the
    /// constraint that most nearly excludes the box; for the Overall rule,
    /// any component of the distance function.
    Verdict evaluate(const ParameterBox& box, SplitRule rule, double variation[3], BoxImage& image) {
        const TermsAtTime at[2] = {terms_at(box.t_lo), terms_at(box.t_hi)};
        const double us[2] = {box.u_lo, box.u_hi};
        const double vs[2] = {box.v_lo, box.v_hi};
        auto& corner = image.corner;
        bool inside = true;
        double* axis_lo = image.axis_lo;
        double* axis_hi = image.axis_hi;
        for (int k = 0; k < 3; ++k) {
            double lo = INFINITY, hi = -INFINITY;
            for (int it = 0; it < 2; ++it) {
                for (int iu = 0; iu < 2; ++iu) {
                    const double partial = at[it].w[k] - us[iu] * at[it].e1[k];
                    for (int iv = 0; iv < 2; ++iv) {
                        const double value = partial - vs[iv] * at[it].e2[k];
                        corner[it][iu][iv][k] = value;
                        lo = std::min(lo, value);
                        hi = std::max(hi, value);
                    }
                }
            }
            // Negated comparisons so that NaN never excludes a box.
            if (!(lo <= bound_[k]) || !(hi >= -bound_[k])) {
                if (!std::isnan(lo) && !std::isnan(hi)) return Verdict::Excluded;
            }
            if (!(lo >= -bound_[k] && hi <= bound_[k])) inside = false;
            axis_lo[k] = lo;
            axis_hi[k] = hi;
        }
        // Above thickness 0 the contact region is the ball, which a box
        // inside the cube need not meet; a corner at its earliest time inside
        // the ball is a contact then.
        if (euclidean_ ? corner_in_ball_at_start(box, corner) : inside)
            return excluded_exactly(box, image) ? Verdict::Excluded : Verdict::Inside;
        ensure_directions();
        auto& projected = image.projected;
        direction_count_ = search_direction_count_;
        if (excluded_by_directions(corner, projected, 0)) return Verdict::Excluded;
        add_box_directions(box);
        if (euclidean_) add_closest_point_direction(box);
        if (excluded_by_directions(corner, projected, search_direction_count_)) return Verdict::Excluded;

        variation[0] = variation[1] = variation[2] = 0.0;
        if (rule == SplitRule::Overall) {
            for (int a = 0; a < 2; ++a) {
                for (int b = 0; b < 2; ++b) {
                    for (int k = 0; k < 3; ++k) {
                        variation[0] = std::max(variation[0], std::abs(corner[1][a][b][k] - corner[0][a][b][k]));
                        variation[1] = std::max(variation[1], std::abs(corner[a][1][b][k] - corner[a][0][b][k]));
                        variation[2] = std::max(variation[2], std::abs(corner[a][b][1][k] - corner[a][b][0][k]));
                    }
                }
            }
            return Verdict::Straddles;
        }
        // Refine where it can pay: pick the constraint (axis or direction)
        // whose hull lies most outside its bound, then report how much each
        // parameter moves that constraint.
        double best_fraction = -1.0;
        int best_constraint = 0;
        auto consider = [&](double lo, double hi, double bound, int id) {
            const double width = hi - lo;
            if (!(width > 0.0)) return;
            const double fraction = std::max(hi - bound, -bound - lo) / width;
            if (fraction > best_fraction) {
                best_fraction = fraction;
                best_constraint = id;
            }
        };
        for (int k = 0; k < 3; ++k) consider(axis_lo[k], axis_hi[k], bound_[k], k);
        for (int i = 0; i < direction_count_; ++i) {
            double lo = INFINITY, hi = -INFINITY;
            for (int c = 0; c < 8; ++c) {
                lo = std::min(lo, projected[i][c]);
                hi = std::max(hi, projected[i][c]);
            }
            consider(lo, hi, directions_[i].bound, 3 + i);
        }
        auto value = [&](int it, int iu, int iv) {
            return best_constraint < 3 ? corner[it][iu][iv][best_constraint]
                                       : projected[best_constraint - 3][it * 4 + iu * 2 + iv];
        };
        for (int a = 0; a < 2; ++a) {
            for (int b = 0; b < 2; ++b) {
                variation[0] = std::max(variation[0], std::abs(value(1, a, b) - value(0, a, b)));
                variation[1] = std::max(variation[1], std::abs(value(a, 1, b) - value(a, 0, b)));
                variation[2] = std::max(variation[2], std::abs(value(a, b, 1) - value(a, b, 0)));
            }
        }
        return Verdict::Straddles;
    }

    /// Fixed directions n along which the scalar n.F (still multilinear, so
    /// still bounded by its corners) separates far better than the world
    /// axes: the triangle normal for vertex-face; for edge-edge the common
    /// normal and, for (nearly) parallel edges, the offset between the lines.
    void choose_separating_directions(double thickness, const double error[3], const double max_abs[3]) {
        direction_count_ = 0;
        for (const double t : {0.0, 1.0}) {
            const TermsAtTime terms = terms_at(t);
            const Vec3 w(terms.w[0], terms.w[1], terms.w[2]);
            const Vec3 e1(terms.e1[0], terms.e1[1], terms.e1[2]);
            const Vec3 e2(terms.e2[0], terms.e2[1], terms.e2[2]);
            add_direction(Vec3(e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                               e1[0] * e2[1] - e1[1] * e2[0]),
                          thickness, error, max_abs);
            if (!is_vertex_face_) {
                const double length_squared = e1.squaredNorm();
                if (length_squared > 0.0) add_direction(w - (w.dot(e1) / length_squared) * e1, thickness, error, max_abs);
            }
        }
    }

    /// What the thickness bounds along a direction n: |n.F| <= thickness |n|
    /// for F in the Euclidean ball, <= thickness |n|_1 for F anywhere in the
    /// cube the world axes accept.
    enum class DirectionBound { Euclidean, Cube };

    void add_direction(const Vec3& n, double thickness, const double error[3], const double max_abs[3],
                       DirectionBound kind = DirectionBound::Euclidean) {
        if (direction_count_ >= MAX_DIRECTIONS) return;
        const double scale = n.cwiseAbs().maxCoeff();
        if (!(scale > 0.0) || !std::isfinite(scale)) return;
        const Vec3 unit_ish = n / scale;
        const double length =
            (kind == DirectionBound::Cube ? unit_ish.lpNorm<1>() : unit_ish.norm()) * CCD_BOUND_INFLATION;
        Direction& d = directions_[direction_count_++];
        for (int k = 0; k < 3; ++k) d.n[k] = unit_ish[k];
        d.bound = direction_bound(unit_ish, length, thickness, error, max_abs);
    }

    bool excluded_by_directions(const double corner[2][2][2][3], double projected[][8], int from) const {
        for (int i = from; i < direction_count_; ++i) {
            const Direction& d = directions_[i];
            double lo = INFINITY, hi = -INFINITY;
            for (int c = 0; c < 8; ++c) {
                const double g = projected_on(d.n, corner[c >> 2][(c >> 1) & 1][c & 1]);
                projected[i][c] = g;
                lo = std::min(lo, g);
                hi = std::max(hi, g);
            }
            if (lo > d.bound || hi < -d.bound) return true;
        }
        return false;
    }

    /// Widths of t, u and v below which a box needs no further split. Time
    /// keeps the requested tolerance (a fraction of the step). The face or
    /// edge parameters are resolved spatially: to tolerance times the
    /// largest distance F moves across the whole range of any parameter
    /// (divided by SPATIAL_TOLERANCE_MARGIN), and never finer than
    /// `tolerance` itself, so a parameter whose edge is far shorter than the
    /// query is refined no finer than it matters (on a sliver blown 10^7
    /// away, resolving its 0.1-long edge to 10^-6 of its length cost
    /// thousands of boxes along a flat contact with thickness), while
    /// ordinary queries keep the parametric tolerance. A parameter F does not
    /// depend on is never split for accuracy. This only decides how early a
    /// box may answer, and a box answers at its t_lo only once everything
    /// earlier is excluded, so times of impact stay conservative.
    void parameter_tolerances(double tolerance, double out[3]) const {
        const TermsAtTime at[2] = {terms_at(0.0), terms_at(1.0)};
        double reach[3] = {0.0, 0.0, 0.0};
        for (int k = 0; k < 3; ++k) {
            for (int it = 0; it < 2; ++it) {
                reach[1] = std::max(reach[1], std::abs(at[it].e1[k]));
                reach[2] = std::max(reach[2], std::abs(at[it].e2[k]));
            }
            for (const double u : {0.0, 1.0}) {
                for (const double v : {0.0, 1.0}) {
                    const double start = at[0].w[k] - u * at[0].e1[k] - v * at[0].e2[k];
                    const double end = at[1].w[k] - u * at[1].e1[k] - v * at[1].e2[k];
                    reach[0] = std::max(reach[0], std::abs(end - start));
                }
            }
        }
        const double scale = std::max({reach[0], reach[1], reach[2]});
        out[0] = out[1] = out[2] = tolerance;
        if (!(scale > 0.0) || !std::isfinite(scale)) return;
        for (int d = 1; d < 3; ++d)
            out[d] = reach[d] > 0.0 ? std::max(tolerance, tolerance * (scale / reach[d]) / SPATIAL_TOLERANCE_MARGIN)
                                    : INFINITY;
    }

    /// True when a box the float corners (hull [axis_lo, axis_hi] per axis)
    /// could not exclude is in fact excluded: on some axis every exact corner
    /// value lies beyond the thickness (F is multilinear in (t,u,v), so its
    /// exact image over the box lies in the hull of its exact corner values).
    /// Only axes whose float hull lies within a few rounding bounds of
    /// excluding are evaluated exactly; on any other axis exact values
    /// cannot exclude either. `image` holds the box's float corner values
    /// and their hull, as evaluate() left them.
    bool excluded_exactly(const ParameterBox& box, const BoxImage& image) const {
        if (!exact_possible_) return false;
        const double* axis_lo = image.axis_lo;
        const double* axis_hi = image.axis_hi;
        const auto& corner = image.corner;
        for (int k = 0; k < 3; ++k) {
            // Exactly zero everywhere: never beyond the thickness, so no exact
            // corner can exclude (flat cloth at rest asks this of most pairs).
            if (vanishes_[k]) continue;
            const bool maybe_above = axis_lo[k] > thickness_ - exact_margin_[k];
            const bool maybe_below = axis_hi[k] < -thickness_ + exact_margin_[k];
            if (!maybe_above && !maybe_below) continue;
            const CornerAxis axis = corner_axis(k);
            bool above = maybe_above, below = maybe_below;
            for (int c = 0; c < 8 && (above || below); ++c) {
                const double t = (c & 4) ? box.t_hi : box.t_lo;
                const double u = (c & 2) ? box.u_hi : box.u_lo;
                const double v = (c & 1) ? box.v_hi : box.v_lo;
                // The float corner value lies within corner_error_ of the
                // exact one: far enough from the thickness, it tells the
                // exact sign already (see FLOAT_DECIDES_SIGN_*).
                const double error = corner_error_[k];
                const double value = corner[c >> 2][(c >> 1) & 1][c & 1][k];
                if (above) {
                    const double beyond = value - thickness_;
                    if (beyond < -FLOAT_DECIDES_SIGN_BELOW * error) above = false;
                    else if (!(beyond > FLOAT_DECIDES_SIGN_ABOVE * error) && exact_corner_sign(axis, t, u, v, -1.0) <= 0)
                        above = false;
                }
                if (below) {
                    const double beyond = -value - thickness_;
                    if (beyond < -FLOAT_DECIDES_SIGN_BELOW * error) below = false;
                    else if (!(beyond > FLOAT_DECIDES_SIGN_ABOVE * error) && exact_corner_sign(axis, t, u, v, 1.0) >= 0)
                        below = false;
                }
            }
            if (above || below) return true;
        }
        return false;
    }

    /// World axis k of the four points, for exact_corner_sign.
    CornerAxis corner_axis(int k) const {
        CornerAxis axis;
        for (int i = 0; i < 4; ++i) {
            axis.start[i] = start_[i][k];
            axis.end[i] = end_[i][k];
        }
        axis.pairs = pairs_;
        axis.thickness = thickness_;
        return axis;
    }

    bool outside_domain(const ParameterBox& box) const {
        return is_vertex_face_ && box.u_lo + box.v_lo > 1.0;
    }

    /// Narrows `box` to the part of each parameter range where a root can
    /// still lie, from the corner values of the last evaluate() (Straddles).
    /// For one parameter, F restricted to each of the 4 box edges along it is
    /// linear (F is multilinear), and at any value of that parameter F ranges
    /// between the 4 edge values (a multilinear function takes its extremes
    /// at the corners of the remaining 2-D box). So a root needs
    /// min_e l_e <= bound and max_e l_e >= -bound, per axis and direction;
    /// the earliest and latest parameter values meeting both bound the root.
    /// Corner rounding errors are already inside the bounds, and the cut
    /// points are rounded outward. Returns false when no root can remain.
    bool clip(ParameterBox& box, const BoxImage& image) const {
        double lower[3] = {0.0, 0.0, 0.0};
        double upper[3] = {1.0, 1.0, 1.0};
        for (int k = 0; k < 3; ++k) {
            double values[8];
            for (int c = 0; c < 8; ++c) values[c] = image.corner[c >> 2][(c >> 1) & 1][c & 1][k];
            clip_constraint(values, bound_[k], lower, upper);
        }
        for (int i = 0; i < direction_count_; ++i)
            clip_constraint(image.projected[i], directions_[i].bound, lower, upper);
        if (euclidean_ && crosses_face_edge(box)) clip_time_within_face(box, lower[0], upper[0]);
        double* ends[3][2] = {{&box.t_lo, &box.t_hi}, {&box.u_lo, &box.u_hi}, {&box.v_lo, &box.v_hi}};
        for (int p = 0; p < 3; ++p) {
            if (lower[p] > upper[p]) return false;
            const double lo = *ends[p][0], hi = *ends[p][1], width = hi - lo;
            double new_lo = lo, new_hi = hi;
            if (lower[p] > 0.0)
                new_lo = std::max(lo, std::nextafter(lo + width * (lower[p] * CLIP_FRACTION_SHRINK), -INFINITY));
            if (upper[p] < 1.0)
                new_hi = std::min(hi, std::nextafter(lo + width * std::min(1.0, upper[p] * CLIP_FRACTION_GROW), INFINITY));
            if (new_lo > new_hi) return false;
            *ends[p][0] = new_lo;
            *ends[p][1] = new_hi;
        }
        if (is_vertex_face_) {
            box.u_hi = std::min(box.u_hi, std::max(box.u_lo, std::nextafter(1.0 - box.v_lo, INFINITY)));
            box.v_hi = std::min(box.v_hi, std::max(box.v_lo, std::nextafter(1.0 - box.u_lo, INFINITY)));
        }
        return true;
    }

private:
    /// Intersects [lower[p], upper[p]] (fractions of the box along parameter
    /// p) with the range where constraint |g| <= bound can hold, g given by
    /// its 8 corner values (index it*4 + iu*2 + iv).
    static void clip_constraint(const double g[8], double bound, double lower[3], double upper[3]) {
        if (holds_everywhere(g, 8, bound)) return;
        for (int p = 0; p < 3; ++p) {
            const int bit = 4 >> p;
            double from[4], to[4];
            int count = 0;
            for (int c = 0; c < 8; ++c) {
                if (c & bit) continue;
                from[count] = g[c];
                to[count++] = g[c | bit];
            }
            narrow_to_lines(from, to, count, bound, lower[p], upper[p]);
        }
    }

    /// n.f, a value of F projected on a separating direction.
    static double projected_on(const double n[3], const double f[3]) { return n[0] * f[0] + n[1] * f[1] + n[2] * f[2]; }

    /// True when all `count` values of a constraint lie within [-bound, bound]
    /// (every line between them then holds it over its whole length), or one
    /// is not finite (nothing can be cut then).
    static bool holds_everywhere(const double* g, int count, double bound) {
        bool within = true;
        for (int c = 0; c < count; ++c) {
            if (!std::isfinite(g[c])) return true;
            within = within && g[c] <= bound && g[c] >= -bound;
        }
        return within;
    }

    /// Intersects [lower, upper] (fractions along one parameter) with the
    /// range where some of `count` lines, from from[i] to to[i], is <= bound
    /// and some is >= -bound: F at any value of the parameter ranges between
    /// the lines' values there, so a root needs both.
    static void narrow_to_lines(const double* from, const double* to, int count, double bound, double& lower,
                                double& upper) {
        double first_below = INFINITY, last_below = -INFINITY;
        double first_above = INFINITY, last_above = -INFINITY;
        for (int i = 0; i < count; ++i) {
            const double a = from[i], b = to[i];
            if (a <= bound) {
                first_below = 0.0;
                last_below = std::max(last_below, b <= bound ? 1.0 : (bound - a) / (b - a));
            } else if (b <= bound) {
                first_below = std::min(first_below, (a - bound) / (a - b));
                last_below = 1.0;
            }
            if (a >= -bound) {
                first_above = 0.0;
                last_above = std::max(last_above, b >= -bound ? 1.0 : (a + bound) / (a - b));
            } else if (b >= -bound) {
                first_above = std::min(first_above, (-bound - a) / (b - a));
                last_above = 1.0;
            }
        }
        lower = std::max({lower, first_below, first_above});
        upper = std::min({upper, last_below, last_above});
    }

    struct Direction {
        double n[3];
        double bound;
    };
    static constexpr int MAX_DIRECTIONS = BoxImage::MAX_DIRECTIONS;
    Direction directions_[MAX_DIRECTIONS];
    int direction_count_ = 0;
    /// Directions chosen once per search (the first of directions_).
    int search_direction_count_ = 0;
    /// Rates of W, E1 and E2 per step (constant: the points move linearly),
    /// set with the search's directions.
    TermsAtTime rates_;
    double start_[4][3];
    double end_[4][3];
    double displacement_[4][3];
    double bound_[3];
    /// Per world axis: largest absolute input coordinate (scene units).
    double max_abs_[3];
    bool directions_chosen_ = false;
    double exact_margin_[3];
    /// Per world axis: bound on the rounding error of one float corner value (scene units).
    double corner_error_[3];
    /// Per world axis: the four points share their coordinate at the step's
    /// start and share it at its end, so every point sits at the same exact
    /// coordinate at every time and F's component is exactly zero.
    bool vanishes_[3];
    double thickness_ = 0.0;
    /// Thickness above 0: the contact region is the Euclidean ball of that
    /// radius (at 0 the ball and the cube the world axes bound are the origin).
    bool euclidean_ = false;
    /// Squared radius a float corner value's length must stay within to be a
    /// contact: the thickness plus the corner's rounding bound, inflated for
    /// the rounding of the sum and the squares (scene units squared).
    double ball_reach_squared_ = 0.0;
    bool exact_possible_ = false;
    PairIndices pairs_;
    bool is_vertex_face_;
};

} // namespace

namespace {

/// The search loop, from `heap` after `iterations` boxes; `first`, when
/// given, is the box to take before any from the heap (as if just popped).
/// With a `fork`, the first box on which a search at fork->finer_tolerance
/// would split differently is recorded there (see FinerSearchFork).
CCDResult search_boxes(RootSearch& search, const CCDSettings& settings, double t_max,
                       std::vector<ParameterBox>& heap, int64_t iterations, const ParameterBox* first,
                       FinerSearchFork* fork) {
    CCDResult result;
    const double tolerance = std::max(settings.tolerance, CCD_MIN_TOLERANCE);
    // Computed at the first split: most queries end on their first box.
    double tolerances[3] = {0.0, 0.0, 0.0};
    double finer_tolerances[3] = {0.0, 0.0, 0.0};
    bool tolerances_known = false;
    const int64_t max_iterations = settings.max_iterations;
    const LaterFirst later_first;
    BoxImage image;

    while (first || !heap.empty()) {
        ParameterBox box;
        if (first) {
            box = *first;
            first = nullptr;
        } else {
            std::pop_heap(heap.begin(), heap.end(), later_first);
            box = heap.back();
            heap.pop_back();
        }
        if (box.t_lo >= t_max) break;

        if (max_iterations > 0 && iterations >= max_iterations) {
            // Every remaining box starts at or after box.t_lo: a safe early bound.
            result.hit = true;
            result.undecided = true;
            result.toi = box.t_lo;
            result.reached_tolerance = box.t_hi - box.t_lo;
            result.iterations = iterations;
            return result;
        }
        ++iterations;
        if (search.outside_domain(box)) continue;

        // Interleave the two split rules by depth (two targeted splits, then
        // one overall): the targeted rule alone can stall on a parameter that
        // never excludes (neighbouring cloth triangles hit the iteration cap),
        // the overall rule alone blows up with thickness; interleaved, each
        // keeps the other making progress.
        const RootSearch::SplitRule rule =
            (box.depth % 3 != 2) ? RootSearch::SplitRule::Targeted : RootSearch::SplitRule::Overall;
        double variation[3];
        const auto verdict = search.evaluate(box, rule, variation, image);
        if (verdict == RootSearch::Verdict::Excluded) continue;
        if (verdict == RootSearch::Verdict::Inside) {
            // Already within thickness at the corners of time t_lo.
            result.hit = true;
            result.toi = box.t_lo;
            result.reached_tolerance = 0.0;
            result.iterations = iterations;
            return result;
        }

        if (box.final_check) {
            if (search.excluded_exactly(box, image)) continue;
            result.hit = true;
            result.toi = box.t_lo;
            result.reached_tolerance = box.t_hi - box.t_lo;
            result.iterations = iterations;
            return result;
        }

        ParameterBox clipped = box;
        if (!search.clip(clipped, image)) continue;
        if (search.excluded_exactly(box, image)) continue;
        if (!tolerances_known) {
            search.parameter_tolerances(tolerance, tolerances);
            if (fork) search.parameter_tolerances(std::max(fork->finer_tolerance, CCD_MIN_TOLERANCE), finer_tolerances);
            tolerances_known = true;
        }
        const double old_widths[3] = {box.t_hi - box.t_lo, box.u_hi - box.u_lo, box.v_hi - box.v_lo};
        const double widths[3] = {clipped.t_hi - clipped.t_lo, clipped.u_hi - clipped.u_lo,
                                  clipped.v_hi - clipped.v_lo};
        // Fraction of each parameter range the clip kept. F is linear along
        // each parameter, so its variation shrinks by the same fraction.
        double kept[3] = {1.0, 1.0, 1.0};
        for (int d = 0; d < 3; ++d) {
            if (old_widths[d] > 0.0) kept[d] = widths[d] / old_widths[d];
            variation[d] *= kept[d];
        }
        if (fork && !fork->diverged) {
            // Tolerances only decide which parameters may split; while they
            // agree on that, the finer search takes the same steps.
            for (int d = 0; d < 3; ++d) {
                if ((widths[d] > tolerances[d]) != (widths[d] > finer_tolerances[d])) {
                    fork->diverged = true;
                    fork->box = box;
                    fork->heap = heap;
                    fork->iterations = iterations - 1;
                    break;
                }
            }
        }
        int split_axis = -1;
        double best_variation = -1.0;
        for (int d = 0; d < 3; ++d) {
            if (widths[d] > tolerances[d] && variation[d] > best_variation) {
                best_variation = variation[d];
                split_axis = d;
            }
        }
        if (split_axis >= 0 && !(best_variation > 0.0)) {
            split_axis = -1;
            double widest = 0.0;
            for (int d = 0; d < 3; ++d) {
                if (widths[d] > tolerances[d] && widths[d] > widest) {
                    widest = widths[d];
                    split_axis = d;
                }
            }
        }
        if (split_axis < 0) {
            // A clipped box is evaluated once more before it may answer (its
            // own corners may exclude it), and then only if still earliest.
            const bool was_clipped = clipped.t_lo != box.t_lo || clipped.t_hi != box.t_hi ||
                                     clipped.u_lo != box.u_lo || clipped.u_hi != box.u_hi ||
                                     clipped.v_lo != box.v_lo || clipped.v_hi != box.v_hi;
            if (was_clipped) {
                clipped.final_check = true;
                heap.push_back(clipped);
                std::push_heap(heap.begin(), heap.end(), later_first);
                continue;
            }
            result.hit = true;
            result.toi = clipped.t_lo;
            result.reached_tolerance = widths[0];
            result.iterations = iterations;
            return result;
        }

        // A clip that removed most of the box is likely to cut again: worth
        // one more evaluation before committing to a split.
        if (kept[0] * kept[1] * kept[2] < CLIP_AGAIN_BELOW_KEPT_VOLUME) {
            heap.push_back(clipped);
            std::push_heap(heap.begin(), heap.end(), later_first);
            continue;
        }
        ParameterBox low = clipped, high = clipped;
        low.depth = high.depth = box.depth + 1;
        if (split_axis == 0) {
            const double mid = clipped.t_lo + TIME_SPLIT_FRACTION * (clipped.t_hi - clipped.t_lo);
            low.t_hi = mid;
            high.t_lo = mid;
        } else if (split_axis == 1) {
            const double mid = 0.5 * (clipped.u_lo + clipped.u_hi);
            low.u_hi = mid;
            high.u_lo = mid;
        } else {
            const double mid = 0.5 * (clipped.v_lo + clipped.v_hi);
            low.v_hi = mid;
            high.v_lo = mid;
        }
        heap.push_back(high);
        std::push_heap(heap.begin(), heap.end(), later_first);
        heap.push_back(low);
        std::push_heap(heap.begin(), heap.end(), later_first);
    }
    result.iterations = iterations;
    return result;
}

} // namespace

CCDResult find_earliest_root(const MultilinearDistance& f, const CCDSettings& settings, double t_max,
                             FinerSearchFork* fork) {
    if (fork) fork->diverged = false;
    t_max = std::min(t_max, 1.0);
    if (!(t_max > 0.0)) return CCDResult{};
    // Tolerance plays no part in it: a finer search would be excluded alike (fork not diverged).
    if (excluded_over_whole_step(f, settings.thickness)) return CCDResult{};
    RootSearch search(f, settings);
    thread_local std::vector<ParameterBox> heap;
    heap.clear();
    heap.push_back(ParameterBox{0.0, t_max, 0.0, 1.0, 0.0, 1.0, 0});
    return search_boxes(search, settings, t_max, heap, 0, nullptr, fork);
}

CCDResult resume_finer_search(const MultilinearDistance& f, const CCDSettings& finer_settings, double t_max,
                              const FinerSearchFork& fork) {
    t_max = std::min(t_max, 1.0);
    RootSearch search(f, finer_settings);
    thread_local std::vector<ParameterBox> heap;
    heap = fork.heap;
    return search_boxes(search, finer_settings, t_max, heap, fork.iterations, &fork.box, nullptr);
}

} // namespace usdksl
