#pragma once

#include <pybind11/pybind11.h>

namespace blurlab {

void bind_gl(pybind11::module_& m);
void bind_passes(pybind11::module_& m);

}  // namespace blurlab
