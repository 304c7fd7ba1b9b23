/// @file module.cpp
/// @brief The private `usdksl._native` module: one define_<topic> per binding file.

#include <pybind11/pybind11.h>

namespace py = pybind11;

void define_ccd(py::module_& m);
void define_collision(py::module_& m);

PYBIND11_MODULE(_native, m) {
    m.doc() = "usdksl native core (private; use the usdksl package)";
    define_ccd(m);
    define_collision(m);
}
