#pragma once
/// @file mesh_arrays.hpp
/// @brief One mesh as Python hands it to the core, (times, points,
///        triangles, triangle_face): read and checked once for every binding
///        that takes meshes.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

namespace usdksl {

/// @brief The arrays of one mesh, held for as long as a binding reads them.
struct MeshArrays {
    /// @brief Sample times (time codes).
    pybind11::array_t<double, pybind11::array::c_style | pybind11::array::forcecast> times;
    /// @brief Points [len(times), N, 3] (scene units): float as they are (a
    ///        loader's authored world-space points, read as the same
    ///        doubles, with no double copy made), anything else as double.
    pybind11::array points;
    bool float_points = false;
    pybind11::array_t<int32_t, pybind11::array::c_style | pybind11::array::forcecast> triangles;
    pybind11::array_t<int32_t, pybind11::array::c_style | pybind11::array::forcecast> triangle_face;

    int32_t vertex_count() const { return static_cast<int32_t>(points.shape(1)); }
};

/// @brief Points as every binding hands them to the core: float32 in
///        C order as they are (`is_float`; the loader's authored world-space
///        points, read as the same doubles), anything else as C-order double.
struct PointsArray {
    pybind11::array array;
    bool is_float = false;
};

inline PointsArray read_points_array(const pybind11::handle& points) {
    namespace py = pybind11;
    using FloatArray = py::array_t<float, py::array::c_style>;
    using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
    PointsArray out;
    out.is_float = py::isinstance<FloatArray>(points) &&
                   (py::reinterpret_borrow<py::array>(points).flags() & py::array::c_style);
    out.array = out.is_float ? py::array(points.cast<FloatArray>()) : py::array(points.cast<DoubleArray>());
    return out;
}

/// @brief The arrays of mesh `index` of a call (`item`, a 4-tuple); throws
///        std::invalid_argument (ValueError) naming the mesh when a shape is
///        wrong. `samples_required`: the mesh must have at least one sample.
inline MeshArrays read_mesh_arrays(const pybind11::handle& item, size_t index, bool samples_required) {
    namespace py = pybind11;
    using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
    using IntArray = py::array_t<int32_t, py::array::c_style | py::array::forcecast>;
    const py::tuple t = py::reinterpret_borrow<py::tuple>(item);
    if (t.size() != 4) throw std::invalid_argument("mesh must be (times, points, triangles, triangle_face)");
    MeshArrays mesh;
    mesh.times = t[0].cast<DoubleArray>();
    PointsArray points = read_points_array(t[1]);
    mesh.points = std::move(points.array);
    mesh.float_points = points.is_float;
    mesh.triangles = t[2].cast<IntArray>();
    mesh.triangle_face = t[3].cast<IntArray>();
    const std::string where = "mesh " + std::to_string(index) + ": ";
    if (mesh.times.ndim() != 1 || (samples_required && mesh.times.shape(0) < 1))
        throw std::invalid_argument(where + (samples_required ? "times must be 1-D, not empty" : "times must be 1-D"));
    if (mesh.points.ndim() != 3 || mesh.points.shape(0) != mesh.times.shape(0) || mesh.points.shape(2) != 3)
        throw std::invalid_argument(where + "points must have shape (len(times), N, 3)");
    if (mesh.triangles.ndim() != 2 || mesh.triangles.shape(1) != 3)
        throw std::invalid_argument(where + "triangles must be (M, 3)");
    if (mesh.triangle_face.ndim() != 1 || mesh.triangle_face.shape(0) != mesh.triangles.shape(0))
        throw std::invalid_argument(where + "triangle_face must have one entry per triangle");
    return mesh;
}

} // namespace usdksl
