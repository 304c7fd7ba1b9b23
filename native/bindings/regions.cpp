/// @file regions.cpp
/// @brief Binds the contact regions: the grouping of contact rows and the
///        depth samples of the regions, numpy arrays in (read in place), numpy
///        arrays out, the GIL released while the core works.

#include "mesh_arrays.hpp"

#include "usdksl/regions/inside_depth.hpp"
#include "usdksl/regions/region_depths.hpp"
#include "usdksl/regions/region_grouping.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace py = pybind11;
using namespace usdksl;

namespace {

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using IntArray = py::array_t<int32_t, py::array::c_style | py::array::forcecast>;
using BoolArray = py::array_t<bool, py::array::c_style | py::array::forcecast>;

/// The arrays the views point into, kept alive for the call.
struct HeldMeshes {
    std::vector<MeshView> views;
    std::vector<MeshArrays> held;
};

HeldMeshes hold_meshes(const py::list& meshes_in) {
    HeldMeshes out;
    for (size_t i = 0; i < meshes_in.size(); ++i) {
        MeshArrays arrays = read_mesh_arrays(meshes_in[i], i, true);
        MeshView view;
        view.times = arrays.times.data();
        view.sample_count = static_cast<int32_t>(arrays.times.shape(0));
        if (arrays.float_points) view.points_float = static_cast<const float*>(arrays.points.data());
        else view.points = static_cast<const double*>(arrays.points.data());
        view.vertex_count = arrays.vertex_count();
        view.triangles = arrays.triangles.data();
        view.triangle_count = static_cast<int32_t>(arrays.triangles.shape(0));
        view.triangle_face = arrays.triangle_face.data();
        out.views.push_back(view);
        out.held.push_back(std::move(arrays));
    }
    return out;
}

/// The contact rows' columns, kept alive for the call.
struct HeldRows {
    ContactRows rows;
    DoubleArray time;
    IntArray mesh_a, face_a, mesh_b, face_b;
};

HeldRows hold_rows(const DoubleArray& time, const IntArray& mesh_a, const IntArray& face_a, const IntArray& mesh_b,
                   const IntArray& face_b) {
    const py::ssize_t count = time.size();
    for (const py::array& column : {py::array(time), py::array(mesh_a), py::array(face_a), py::array(mesh_b), py::array(face_b)}) {
        if (column.ndim() != 1 || column.size() != count)
            throw std::invalid_argument("contact columns must be 1-D and of one length");
    }
    HeldRows held{ContactRows{}, time, mesh_a, face_a, mesh_b, face_b};
    held.rows.count = count;
    held.rows.time = held.time.data();
    held.rows.mesh_a = held.mesh_a.data();
    held.rows.face_a = held.face_a.data();
    held.rows.mesh_b = held.mesh_b.data();
    held.rows.face_b = held.face_b.data();
    return held;
}

std::vector<double> sorted_times(const DoubleArray& sample_times) {
    if (sample_times.ndim() != 1) throw std::invalid_argument("sample_times must be 1-D");
    std::vector<double> times(sample_times.data(), sample_times.data() + sample_times.size());
    if (!std::is_sorted(times.begin(), times.end())) throw std::invalid_argument("sample_times must be sorted");
    return times;
}

template <typename T>
py::array_t<T> to_array(const std::vector<T>& values) {
    py::array_t<T> out(static_cast<py::ssize_t>(values.size()));
    std::copy(values.begin(), values.end(), out.mutable_data());
    return out;
}

py::array_t<double> to_points(const std::vector<double>& values) {
    py::array_t<double> out({static_cast<py::ssize_t>(values.size() / 3), static_cast<py::ssize_t>(3)});
    std::copy(values.begin(), values.end(), out.mutable_data());
    return out;
}

py::dict group_regions_py(const py::list& meshes_in, const DoubleArray& time, const IntArray& mesh_a,
                          const IntArray& face_a, const IntArray& mesh_b, const IntArray& face_b,
                          const DoubleArray& sample_times, double thickness, int32_t threads) {
    const HeldMeshes meshes = hold_meshes(meshes_in);
    const HeldRows rows = hold_rows(time, mesh_a, face_a, mesh_b, face_b);
    const std::vector<double> times = sorted_times(sample_times);
    RegionGrouping grouping;
    {
        py::gil_scoped_release release;
        grouping = group_regions(meshes.views, rows.rows, times, thickness, threads);
    }
    py::dict out;
    out["row_region"] = to_array(grouping.row_region);
    out["region_count"] = grouping.region_count;
    out["row_last_sampled"] = to_array(grouping.row_last_sampled);
    out["row_span_first"] = to_array(grouping.row_span_first);
    out["row_span_last"] = to_array(grouping.row_span_last);
    return out;
}

py::dict region_depths_py(const py::list& meshes_in, const DoubleArray& time, const IntArray& mesh_a,
                          const IntArray& face_a, const IntArray& mesh_b, const IntArray& face_b,
                          const IntArray& row_region, const IntArray& row_span_last, int32_t region_count,
                          const DoubleArray& sample_times, const BoolArray& measured, const BoolArray& closed,
                          int32_t threads) {
    const HeldMeshes meshes = hold_meshes(meshes_in);
    const HeldRows rows = hold_rows(time, mesh_a, face_a, mesh_b, face_b);
    if (row_region.ndim() != 1 || row_region.size() != time.size() || row_span_last.ndim() != 1 ||
        row_span_last.size() != time.size())
        throw std::invalid_argument("row_region and row_span_last need one entry per contact row");
    if (closed.ndim() != 1 || static_cast<size_t>(closed.size()) != meshes.views.size())
        throw std::invalid_argument("closed needs one flag per mesh");
    const std::vector<double> times = sorted_times(sample_times);
    if (measured.ndim() != 1 || static_cast<size_t>(measured.size()) != times.size())
        throw std::invalid_argument("measured needs one flag per sample time");
    const std::vector<char> measured_flags(measured.data(), measured.data() + measured.size());
    const std::vector<char> closed_flags(closed.data(), closed.data() + closed.size());
    RowRegions grouping{row_region.data(), row_span_last.data(), region_count};
    RegionDepthSamples samples;
    {
        py::gil_scoped_release release;
        samples = measure_region_depths(meshes.views, rows.rows, grouping, times, measured_flags, closed_flags,
                                        threads);
    }
    py::dict out;
    out["region"] = to_array(samples.region);
    out["sample"] = to_array(samples.sample);
    out["penetration"] = to_array(samples.penetration);
    out["intersection_length"] = to_array(samples.intersection_length);
    out["box_min"] = to_points(samples.box_min);
    out["box_max"] = to_points(samples.box_max);
    out["depth_evaluations"] = samples.depth_evaluations;
    return out;
}

} // namespace

void define_regions(py::module_& m) {
    m.attr("DEPTH_RELATIVE_ACCURACY") = DEPTH_RELATIVE_ACCURACY;
    m.def("group_regions", &group_regions_py, py::arg("meshes"), py::arg("time"), py::arg("mesh_a"), py::arg("face_a"),
          py::arg("mesh_b"), py::arg("face_b"), py::arg("sample_times"), py::arg("thickness"), py::arg("threads"),
          "Regions of contact rows (time codes; meshes as (times, points, triangles, triangle_face)) -> dict of "
          "row_region, region_count, row_last_sampled, row_span_first, row_span_last.");
    m.def("region_depths", &region_depths_py, py::arg("meshes"), py::arg("time"), py::arg("mesh_a"), py::arg("face_a"),
          py::arg("mesh_b"), py::arg("face_b"), py::arg("row_region"), py::arg("row_span_last"),
          py::arg("region_count"), py::arg("sample_times"), py::arg("measured"), py::arg("closed"),
          py::arg("threads"),
          "Depth samples of every region at its first and last samples and the samples flagged in measured "
          "(bool per sample time) between them -> dict of region, sample (index into sample_times), "
          "penetration, intersection_length, box_min, box_max ((S, 3)), depth_evaluations.");
}
