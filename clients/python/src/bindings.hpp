// The module's parts, each binding its own classes into the module.
#pragma once

#include <pybind11/pybind11.h>

namespace rigid::python {

void bind_world(pybind11::module_& m);
void bind_states(pybind11::module_& m);
void bind_client(pybind11::module_& m);

}  // namespace rigid::python
