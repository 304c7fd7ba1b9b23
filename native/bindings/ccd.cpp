/// @file ccd.cpp
/// @brief Batch bindings of the narrow phase: arrays in, arrays out, GIL released.

#include "usdksl/ccd/edge_edge_ccd.hpp"
#include "usdksl/geometry/exact_predicates.hpp"
#include "usdksl/geometry/triangle_triangle_static.hpp"
#include "usdksl/ccd/vertex_face_ccd.hpp"
#include "usdksl/narrow_phase/triangle_pair.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <stdexcept>
#include <string>

namespace py = pybind11;
using namespace usdksl;

namespace {

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using IndexArray = py::array_t<int32_t, py::array::c_style | py::array::forcecast>;

void require_shape(const py::array& array, std::initializer_list<py::ssize_t> tail, const char* name) {
    const py::ssize_t rank = static_cast<py::ssize_t>(tail.size()) + 1;
    bool ok = array.ndim() == rank;
    py::ssize_t axis = 1;
    for (py::ssize_t extent : tail) {
        ok = ok && array.shape(axis) == extent;
        ++axis;
    }
    if (!ok) throw std::invalid_argument(std::string(name) + " has the wrong shape");
}

Vec3 point_at(const double* data, py::ssize_t index) {
    return Vec3(data[3 * index], data[3 * index + 1], data[3 * index + 2]);
}

CCDSettings make_settings(double tolerance, double thickness, int64_t max_iterations) {
    CCDSettings settings;
    settings.tolerance = tolerance;
    settings.thickness = thickness;
    settings.max_iterations = max_iterations;
    return settings;
}

template <typename Query>
py::tuple run_primitive_batch(const DoubleArray& queries, const CCDSettings& settings, Query query) {
    require_shape(queries, {8, 3}, "queries (expected (Q, 8, 3))");
    const py::ssize_t count = queries.shape(0);
    py::array_t<bool> hit(count);
    py::array_t<double> toi(count);
    py::array_t<double> reached(count);
    py::array_t<bool> undecided(count);
    py::array_t<int64_t> iterations(count);
    const double* data = queries.data();
    bool* hit_out = hit.mutable_data();
    double* toi_out = toi.mutable_data();
    double* reached_out = reached.mutable_data();
    bool* undecided_out = undecided.mutable_data();
    int64_t* iterations_out = iterations.mutable_data();
    {
        py::gil_scoped_release release;
        for (py::ssize_t q = 0; q < count; ++q) {
            const py::ssize_t base = 8 * q;
            const CCDResult r = query(point_at(data, base), point_at(data, base + 1),
                                      point_at(data, base + 2), point_at(data, base + 3),
                                      point_at(data, base + 4), point_at(data, base + 5),
                                      point_at(data, base + 6), point_at(data, base + 7), settings);
            hit_out[q] = r.hit;
            toi_out[q] = r.toi;
            reached_out[q] = r.reached_tolerance;
            undecided_out[q] = r.undecided;
            iterations_out[q] = r.iterations;
        }
    }
    return py::make_tuple(hit, toi, reached, undecided, iterations);
}

std::array<Vec3, 3> triangle_at(const double* data, py::ssize_t index) {
    return {point_at(data, 3 * index), point_at(data, 3 * index + 1), point_at(data, 3 * index + 2)};
}

Triangle ids_at(const int32_t* data, py::ssize_t index) {
    return {data[3 * index], data[3 * index + 1], data[3 * index + 2]};
}

} // namespace

void define_ccd(py::module_& m) {
    m.def(
        "vertex_face_ccd_batch",
        [](const DoubleArray& queries, double tolerance, double thickness, int64_t max_iterations) {
            return run_primitive_batch(
                queries, make_settings(tolerance, thickness, max_iterations),
                [](const Vec3& p0, const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& p1,
                   const Vec3& a1, const Vec3& b1, const Vec3& c1, const CCDSettings& s) {
                    return vertex_face_ccd(p0, a0, b0, c0, p1, a1, b1, c1, s);
                });
        },
        py::arg("queries"), py::arg("tolerance"), py::arg("thickness"), py::arg("max_iterations"),
        "Vertex-face CCD over (Q,8,3) queries -> (hit, toi, reached_tolerance, undecided, iterations).");
    m.def(
        "edge_edge_ccd_batch",
        [](const DoubleArray& queries, double tolerance, double thickness, int64_t max_iterations) {
            return run_primitive_batch(
                queries, make_settings(tolerance, thickness, max_iterations),
                [](const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1, const Vec3& c0,
                   const Vec3& c1, const Vec3& d0, const Vec3& d1, const CCDSettings& s) {
                    return edge_edge_ccd(a0, a1, b0, b1, c0, c1, d0, d1, s);
                });
        },
        py::arg("queries"), py::arg("tolerance"), py::arg("thickness"), py::arg("max_iterations"),
        "Edge-edge CCD over (Q,8,3) queries -> (hit, toi, reached_tolerance, undecided, iterations).");

    m.def(
        "triangle_pair_ccd_batch",
        [](const DoubleArray& a_t0, const DoubleArray& a_t1, const DoubleArray& b_t0,
           const DoubleArray& b_t1, const IndexArray& ids_a, const IndexArray& ids_b, bool same_mesh,
           double tolerance, double thickness, int64_t max_iterations, bool reuse) {
            for (const auto* array : {&a_t0, &a_t1, &b_t0, &b_t1}) require_shape(*array, {3, 3}, "triangles (expected (Q, 3, 3))");
            require_shape(ids_a, {3}, "ids_a (expected (Q, 3))");
            require_shape(ids_b, {3}, "ids_b (expected (Q, 3))");
            const py::ssize_t count = a_t0.shape(0);
            for (const py::array* array : {static_cast<const py::array*>(&a_t1), static_cast<const py::array*>(&b_t0),
                                           static_cast<const py::array*>(&b_t1), static_cast<const py::array*>(&ids_a),
                                           static_cast<const py::array*>(&ids_b)})
                if (array->shape(0) != count) throw std::invalid_argument("batch sizes differ");
            const CCDSettings settings = make_settings(tolerance, thickness, max_iterations);
            py::array_t<bool> hit(count);
            py::array_t<double> toi(count);
            py::array_t<int8_t> feature(count);
            py::array_t<bool> undecided(count);
            py::array_t<int32_t> queries(count);
            auto* hit_out = hit.mutable_data();
            auto* toi_out = toi.mutable_data();
            auto* feature_out = feature.mutable_data();
            auto* undecided_out = undecided.mutable_data();
            auto* queries_out = queries.mutable_data();
            py::array_t<int32_t> reused(count);
            auto* reused_out = reused.mutable_data();
            const double *pa0 = a_t0.data(), *pa1 = a_t1.data(), *pb0 = b_t0.data(), *pb1 = b_t1.data();
            const int32_t *ia = ids_a.data(), *ib = ids_b.data();
            {
                py::gil_scoped_release release;
                VertexFaceMemo memo;
                for (py::ssize_t q = 0; q < count; ++q) {
                    const MovingTriangle a{ids_at(ia, q), triangle_at(pa0, q), triangle_at(pa1, q)};
                    const MovingTriangle b{ids_at(ib, q), triangle_at(pb0, q), triangle_at(pb1, q)};
                    const TrianglePairContact c = triangle_pair_ccd(a, b, same_mesh, settings, reuse ? &memo : nullptr);
                    hit_out[q] = c.hit;
                    toi_out[q] = c.toi;
                    feature_out[q] = static_cast<int8_t>(c.feature);
                    undecided_out[q] = c.undecided;
                    queries_out[q] = c.queries;
                    reused_out[q] = c.reused_queries;
                }
            }
            return py::make_tuple(hit, toi, feature, undecided, queries, reused);
        },
        py::arg("a_t0"), py::arg("a_t1"), py::arg("b_t0"), py::arg("b_t1"), py::arg("ids_a"),
        py::arg("ids_b"), py::arg("same_mesh"), py::arg("tolerance"), py::arg("thickness"),
        py::arg("max_iterations"), py::arg("reuse") = true,
        "Triangle-pair CCD over Q pairs -> (hit, toi, feature, undecided, primitive_queries, reused_queries); "
        "with reuse, repeated vertex-face queries within the batch are answered from a memo (same answers).");

    m.def(
        "triangles_intersect_static_batch",
        [](const DoubleArray& a, const DoubleArray& b, double thickness) {
            require_shape(a, {3, 3}, "a (expected (Q, 3, 3))");
            require_shape(b, {3, 3}, "b (expected (Q, 3, 3))");
            const py::ssize_t count = a.shape(0);
            if (b.shape(0) != count) throw std::invalid_argument("batch sizes differ");
            py::array_t<bool> out(count);
            auto* result = out.mutable_data();
            const double *pa = a.data(), *pb = b.data();
            {
                py::gil_scoped_release release;
                for (py::ssize_t q = 0; q < count; ++q)
                    result[q] = triangles_intersect_static(triangle_at(pa, q), triangle_at(pb, q), thickness);
            }
            return out;
        },
        py::arg("a"), py::arg("b"), py::arg("thickness"),
        "Static closed triangle-triangle test over Q pairs -> bool[Q].");

    m.def(
        "triangle_pair_intersect_static_batch",
        [](const IndexArray& ids_a, const DoubleArray& a, const IndexArray& ids_b, const DoubleArray& b,
           bool same_mesh, double thickness) {
            require_shape(a, {3, 3}, "a (expected (Q, 3, 3))");
            require_shape(b, {3, 3}, "b (expected (Q, 3, 3))");
            require_shape(ids_a, {3}, "ids_a (expected (Q, 3))");
            require_shape(ids_b, {3}, "ids_b (expected (Q, 3))");
            const py::ssize_t count = a.shape(0);
            if (b.shape(0) != count || ids_a.shape(0) != count || ids_b.shape(0) != count)
                throw std::invalid_argument("batch sizes differ");
            py::array_t<bool> out(count);
            auto* result = out.mutable_data();
            const double *pa = a.data(), *pb = b.data();
            const int32_t *ia = ids_a.data(), *ib = ids_b.data();
            {
                py::gil_scoped_release release;
                for (py::ssize_t q = 0; q < count; ++q)
                    result[q] = triangle_pair_intersect_static(ids_at(ia, q), triangle_at(pa, q), ids_at(ib, q),
                                                               triangle_at(pb, q), same_mesh, thickness);
            }
            return out;
        },
        py::arg("ids_a"), py::arg("a"), py::arg("ids_b"), py::arg("b"), py::arg("same_mesh"),
        py::arg("thickness"),
        "Static triangle-pair test skipping shared-vertex primitives -> bool[Q].");

    m.def(
        "orient3d_batch",
        [](const DoubleArray& points) {
            require_shape(points, {4, 3}, "points (expected (Q, 4, 3))");
            const py::ssize_t count = points.shape(0);
            py::array_t<int8_t> out(count);
            auto* result = out.mutable_data();
            const double* p = points.data();
            {
                py::gil_scoped_release release;
                for (py::ssize_t q = 0; q < count; ++q)
                    result[q] = static_cast<int8_t>(orient3d(point_at(p, 4 * q), point_at(p, 4 * q + 1),
                                                             point_at(p, 4 * q + 2), point_at(p, 4 * q + 3)));
            }
            return out;
        },
        py::arg("points"), "Exact orientation sign of det[a-d, b-d, c-d] over (Q,4,3) -> int8[Q].");
}
