/// @file collision.cpp
/// @brief Binds find_contacts: numpy arrays and a CheckOptions (check_options.cpp) in, numpy arrays out.

#include "mesh_arrays.hpp"

#include "usdksl/collision/check.hpp"

#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstring>
#include <stdexcept>
#include <string>

namespace py = pybind11;
using namespace usdksl;

namespace {

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using IntArray = py::array_t<int32_t, py::array::c_style | py::array::forcecast>;

/// The mesh of `arrays`, whose points it borrows: the arrays must outlive it.
MeshAnimation to_mesh(const MeshArrays& arrays) {
    MeshAnimation mesh;
    mesh.times.assign(arrays.times.data(), arrays.times.data() + arrays.times.size());
    if (arrays.float_points) mesh.borrowed_float_points = static_cast<const float*>(arrays.points.data());
    else mesh.borrowed_points = static_cast<const double*>(arrays.points.data());
    mesh.borrowed_value_count = static_cast<size_t>(arrays.points.size());
    mesh.vertex_count = arrays.vertex_count();
    mesh.triangles.resize(static_cast<size_t>(arrays.triangles.shape(0)));
    std::memcpy(mesh.triangles.data(), arrays.triangles.data(),
                sizeof(int32_t) * static_cast<size_t>(arrays.triangles.size()));
    mesh.triangle_face.assign(arrays.triangle_face.data(), arrays.triangle_face.data() + arrays.triangle_face.size());
    return mesh;
}

template <typename T, typename F>
py::array_t<T> column(const std::vector<Contact>& contacts, F get) {
    py::array_t<T> out(static_cast<py::ssize_t>(contacts.size()));
    T* data = out.mutable_data();
    for (size_t i = 0; i < contacts.size(); ++i) data[i] = get(contacts[i]);
    return out;
}

py::dict find_contacts_py(const py::list& meshes_in, const IntArray& pairs_in, const CheckOptions& options_in,
                          const py::object& progress) {
    // The shot's points are the largest arrays of a check: the core reads them in place, held here for the
    // call (the caller must not change them meanwhile).
    std::vector<MeshArrays> arrays;
    std::vector<MeshAnimation> meshes;
    arrays.reserve(meshes_in.size());
    meshes.reserve(meshes_in.size());
    for (size_t i = 0; i < meshes_in.size(); ++i) {
        arrays.push_back(read_mesh_arrays(meshes_in[i], i, false));
        meshes.push_back(to_mesh(arrays.back()));
    }
    if (pairs_in.size() != 0 && (pairs_in.ndim() != 2 || pairs_in.shape(1) != 2))
        throw std::invalid_argument("pairs must have shape (P, 2)");
    std::vector<std::pair<int32_t, int32_t>> pairs;
    for (py::ssize_t i = 0; i < (pairs_in.size() ? pairs_in.shape(0) : 0); ++i)
        pairs.emplace_back(pairs_in.at(i, 0), pairs_in.at(i, 1));
    // A copy: the core reads it with the GIL released, while Python may change the caller's.
    CheckOptions options = options_in;
    // Always called back, even without a progress object: with the GIL released Python's signal
    // handlers only run here, so a Ctrl-C, a SIGTERM or a timeout raises in this callback and the
    // exception unwinds through the core (docs/contracts.md, Stopping).
    options.progress = [progress](double t, int64_t contacts) {
        py::gil_scoped_acquire gil;
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
        if (!progress.is_none()) progress(t, contacts);
    };
    CheckResult result;
    {
        py::gil_scoped_release release;
        result = find_contacts(meshes, pairs, options);
    }
    const std::vector<Contact>& c = result.contacts;
    py::dict out;
    out["time"] = column<double>(c, [](const Contact& x) { return x.time; });
    out["mesh_a"] = column<int32_t>(c, [](const Contact& x) { return x.mesh_a; });
    out["tri_a"] = column<int32_t>(c, [](const Contact& x) { return x.tri_a; });
    out["mesh_b"] = column<int32_t>(c, [](const Contact& x) { return x.mesh_b; });
    out["tri_b"] = column<int32_t>(c, [](const Contact& x) { return x.tri_b; });
    out["feature"] = column<int8_t>(c, [](const Contact& x) { return static_cast<int8_t>(x.feature); });
    out["undecided"] = column<bool>(c, [](const Contact& x) { return x.undecided; });
    const Counters& k = result.counters;
    py::dict counters;
    counters["kinetic_tree_events"] = k.kinetic_tree_events;
    counters["bv_overlap_events"] = k.bv_overlap_events;
    counters["fathers_do_not_overlap_events"] = k.fathers_do_not_overlap_events;
    counters["leaves_do_not_overlap_events"] = k.leaves_do_not_overlap_events;
    counters["plane_kept_steps"] = k.plane_kept_steps;
    counters["polygons_collide_events"] = k.polygons_collide_events;
    counters["bv_change_events"] = k.bv_change_events;
    counters["bv_tests"] = k.bv_tests;
    counters["narrow_phase_tests"] = k.narrow_phase_tests;
    counters["cleared_steps"] = k.cleared_steps;
    counters["primitive_queries"] = k.primitive_queries;
    counters["reused_queries"] = k.reused_queries;
    counters["undecided_queries"] = k.undecided_queries;
    counters["raw_confirmations"] = k.raw_confirmations;
    counters["raw_rejections"] = k.raw_rejections;
    counters["time_windows"] = k.time_windows;
    out["counters"] = counters;
    return out;
}

} // namespace

void define_collision(py::module_& m) {
    m.def("find_contacts", &find_contacts_py, py::arg("meshes"), py::arg("pairs"), py::arg("options"),
          py::arg("progress") = py::none(),
          "First contact of every triangle pair of the given mesh pairs over [options.t_begin, options.t_end] "
          "(time codes), as `options` (CheckOptions) say, on options.threads threads (<= 0: every hardware "
          "thread; the answer does not depend on the count); progress(time reached, contacts so far) or None.");
}
