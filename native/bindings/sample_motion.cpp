/// @file sample_motion.cpp
/// @brief Binds the one-pass motion summary of a mesh's samples (longest step
///        per interval, box per sample) that the loader's blow-up scan reads.

#include "mesh_arrays.hpp"

#include "usdksl/flightplan/sample_motion.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <stdexcept>
#include <utility>
#include <vector>

namespace py = pybind11;
using namespace usdksl;

namespace {

/// Calls `use(data, samples, vertices)` on points [K, N, 3] as read_points_array reads them.
template <typename Use>
auto with_points(const py::array& points_in, Use use) {
    if (points_in.ndim() != 3 || points_in.shape(2) != 3) throw std::invalid_argument("points must have shape (K, N, 3)");
    const int64_t samples = points_in.shape(0), vertices = points_in.shape(1);
    const PointsArray points = read_points_array(points_in);
    py::gil_scoped_release release;
    if (points.is_float) return use(static_cast<const float*>(points.array.data()), samples, vertices);
    return use(static_cast<const double*>(points.array.data()), samples, vertices);
}

py::array_t<double> longest_steps_py(const py::array& points, int32_t threads) {
    std::vector<double> longest = with_points(points, [&](const auto* data, int64_t samples, int64_t vertices) {
        return longest_steps(data, samples, vertices, threads);
    });
    py::array_t<double> out(static_cast<py::ssize_t>(longest.size()));
    std::copy(longest.begin(), longest.end(), out.mutable_data());
    return out;
}

py::tuple sample_boxes_py(const py::array& points, int32_t threads) {
    const py::ssize_t samples = points.ndim() == 3 ? points.shape(0) : 0;
    py::array_t<double> lowest({samples, static_cast<py::ssize_t>(3)});
    py::array_t<double> highest({samples, static_cast<py::ssize_t>(3)});
    double* low = lowest.mutable_data();
    double* high = highest.mutable_data();
    with_points(points, [&](const auto* data, int64_t count, int64_t vertices) {
        sample_boxes(data, count, vertices, low, high, threads);
        return 0;
    });
    return py::make_tuple(lowest, highest);
}

} // namespace

void define_sample_motion(py::module_& m) {
    m.def("longest_steps", &longest_steps_py, py::arg("points"), py::arg("threads") = 1,
          "float64[K - 1]: per sample interval of points [K, N, 3] (float32 read as they are, anything else as "
          "float64), the longest displacement of any vertex, sqrt of the largest dx*dx + dy*dy + dz*dz in double; "
          "up to `threads` threads, the same answer for any count.");
    m.def("sample_boxes", &sample_boxes_py, py::arg("points"), py::arg("threads") = 1,
          "(lowest, highest): float64[K, 3] per sample of points [K, N, 3], the least and greatest coordinate "
          "along each axis; up to `threads` threads, the same answer for any count.");
}
