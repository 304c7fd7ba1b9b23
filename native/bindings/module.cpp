/// @file module.cpp
/// @brief The private `usdksl._native` module: one define_<topic> per binding file.

#include "usdksl/constants.hpp"

#include <pybind11/pybind11.h>

namespace py = pybind11;

void define_ccd(py::module_& m);
void define_check_options(py::module_& m);
void define_collision(py::module_& m);
void define_regions(py::module_& m);
void define_sample_motion(py::module_& m);

PYBIND11_MODULE(_native, m) {
    m.doc() = "usdksl native core (private; use the usdksl package)";
    // The defaults Python reads instead of writing them again (usdksl/ccd.py).
    m.attr("DEFAULT_CCD_TOLERANCE") = usdksl::DEFAULT_CCD_TOLERANCE;
    m.attr("DEFAULT_CCD_MAX_ITERATIONS") = usdksl::DEFAULT_CCD_MAX_ITERATIONS;
    m.attr("DEFAULT_THICKNESS") = usdksl::DEFAULT_THICKNESS;
    define_ccd(m);
    define_check_options(m);   // before find_contacts, whose signature names it
    define_collision(m);
    define_regions(m);
    define_sample_motion(m);
}
