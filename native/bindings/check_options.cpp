/// @file check_options.cpp
/// @brief Binds CheckOptions, how one check runs, as a class with named
///        fields: Python builds it once and hands it to find_contacts.

#include "usdksl/scene/check_options.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <stdexcept>
#include <string>

namespace py = pybind11;
using namespace usdksl;

namespace {

/// The name Python gives each method (usdksl.checking.collision.METHODS).
struct MethodName {
    Method method;
    const char* name;
};
constexpr MethodName METHOD_NAMES[] = {
    {Method::KineticSeparationList, "ksl"},
    {Method::SweptVolume, "swept"},
    {Method::Discrete, "discrete"},
    {Method::BruteForce, "brute"},
};

std::string method_name(Method method) {
    for (const MethodName& known : METHOD_NAMES) {
        if (known.method == method) return known.name;
    }
    throw std::logic_error("a method without a name");
}

Method method_named(const std::string& name) {
    for (const MethodName& known : METHOD_NAMES) {
        if (name == known.name) return known.method;
    }
    throw std::invalid_argument("unknown method '" + name + "' (ksl, swept, discrete, brute)");
}

/// Python's own repr of each value (floats at the shortest digits that read back the same).
py::str describe(const CheckOptions& options) {
    return py::str("CheckOptions(method={!r}, t_begin={!r}, t_end={!r}, tolerance={!r}, thickness={!r}, "
                   "max_iterations={!r}, discrete_substeps={!r}, threads={!r}, frames_per_time_code={!r})")
        .format(method_name(options.method), options.t_begin, options.t_end, options.ccd.tolerance,
                options.ccd.thickness, options.ccd.max_iterations, options.discrete_substeps, options.threads,
                options.frames_per_time_code);
}

} // namespace

void define_check_options(py::module_& m) {
    const CheckOptions defaults;
    py::class_<CheckOptions>(m, "CheckOptions",
                             "How one check runs: the method, the time range (time codes), the narrow phase's "
                             "tolerance (fraction of a step), thickness (scene units) and iteration cap, the "
                             "discrete method's substeps and the threads. Fields are read and written by name; "
                             "the progress callback goes to find_contacts beside it.")
        .def(py::init([](const std::string& method, double t_begin, double t_end, double tolerance,
                         double thickness, int64_t max_iterations, int32_t discrete_substeps, int32_t threads,
                         double frames_per_time_code) {
                 CheckOptions options;
                 options.method = method_named(method);
                 options.t_begin = t_begin;
                 options.t_end = t_end;
                 options.ccd.tolerance = tolerance;
                 options.ccd.thickness = thickness;
                 options.ccd.max_iterations = max_iterations;
                 options.discrete_substeps = discrete_substeps;
                 options.threads = threads;
                 options.frames_per_time_code = frames_per_time_code;
                 return options;
             }),
             py::kw_only(), py::arg("method") = method_name(defaults.method), py::arg("t_begin") = defaults.t_begin,
             py::arg("t_end") = defaults.t_end, py::arg("tolerance") = defaults.ccd.tolerance,
             py::arg("thickness") = defaults.ccd.thickness, py::arg("max_iterations") = defaults.ccd.max_iterations,
             py::arg("discrete_substeps") = defaults.discrete_substeps, py::arg("threads") = defaults.threads,
             py::arg("frames_per_time_code") = defaults.frames_per_time_code)
        .def_property(
            "method", [](const CheckOptions& options) { return method_name(options.method); },
            [](CheckOptions& options, const std::string& name) { options.method = method_named(name); },
            "ksl, swept, discrete or brute.")
        .def_readwrite("t_begin", &CheckOptions::t_begin, "Start of the checked range (time code).")
        .def_readwrite("t_end", &CheckOptions::t_end, "End of the checked range (time code).")
        .def_property(
            "tolerance", [](const CheckOptions& options) { return options.ccd.tolerance; },
            [](CheckOptions& options, double value) { options.ccd.tolerance = value; },
            "Time tolerance of the narrow phase (fraction of one step).")
        .def_property(
            "thickness", [](const CheckOptions& options) { return options.ccd.thickness; },
            [](CheckOptions& options, double value) { options.ccd.thickness = value; },
            "Distance at or below which primitives touch (scene units); every method and the narrow phase "
            "read this one value.")
        .def_property(
            "max_iterations", [](const CheckOptions& options) { return options.ccd.max_iterations; },
            [](CheckOptions& options, int64_t value) { options.ccd.max_iterations = value; },
            "Cap on the narrow phase's refinements of one query (reaching it: undecided, counted as a contact).")
        .def_readwrite("discrete_substeps", &CheckOptions::discrete_substeps,
                       "Discrete method only: static tests per step (1 = at samples only).")
        .def_readwrite("frames_per_time_code", &CheckOptions::frames_per_time_code,
                       "Frames per time code (the stage's clock; 0: unknown): the event-based and swept methods "
                       "step over samples between whole frames, with slack; the answer is the same.")
        .def_readwrite("threads", &CheckOptions::threads,
                       "Threads (<= 0: every hardware thread); the answer does not depend on the count.")
        .def(
            "settle",
            [](CheckOptions& options, const py::array_t<int32_t, py::array::c_style | py::array::forcecast>& pairs) {
                if (pairs.ndim() != 2 || pairs.shape(1) != 4)
                    throw std::invalid_argument("settled pairs must be an (N, 4) array of mesh_a, tri_a, mesh_b, tri_b");
                const auto rows = pairs.unchecked<2>();
                options.settled_pairs.clear();
                options.settled_pairs.reserve(static_cast<size_t>(rows.shape(0)));
                for (py::ssize_t i = 0; i < rows.shape(0); ++i) {
                    options.settled_pairs.push_back({rows(i, 0), rows(i, 1), rows(i, 2), rows(i, 3)});
                }
            },
            py::arg("pairs"),
            "Triangle pairs (N, 4: mesh_a, tri_a, mesh_b, tri_b) whose first contact a run over an earlier range "
            "found, at or before t_begin: not tested again (brute force tests them all the same).")
        .def_property_readonly(
            "settled_count", [](const CheckOptions& options) { return options.settled_pairs.size(); },
            "How many triangle pairs settle() left alone.")
        .def("__repr__", &describe);
}
