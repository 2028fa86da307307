// What the bindings share: the exceptions they raise and the conversions of Python arguments
// (vectors, frames), each refusing a bad value with a one-line message that names it.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <chrono>
#include <string>
#include <string_view>

#include "physics/math.hpp"
#include "physics/spec.hpp"

namespace rigid::python {

namespace py = pybind11;

// The module's exception classes (created in module.cpp, before anything can raise them).
struct Exceptions {
  py::object scene_error;         // SceneError(ValueError): a bad scene file or text
  py::object spec_error;          // SpecError(ValueError): a scene that rejects the overrides
  py::object unknown_body_error;  // UnknownBodyError(LookupError)
  py::object transport_error;     // TransportError(RuntimeError): a bus that cannot be set up
};
Exceptions& exceptions();

// Raises `type(message)` as a Python exception (throws py::error_already_set).
[[noreturn]] void raise(const py::object& type, const std::string& message);

// "%.9g", as rigidd prints numbers in its refusals.
// One contact event (rigid.Contact): what happened (impact, resting, sliding, rolling, separate),
// to which body, at which static part, when (the world's time), where, the part's normal towards
// the body, and the impulse on the body (N s; zero but for an impact), all in the world frame.
struct Contact {
  std::string kind, body, part;
  int body_index = 0, part_index = 0;
  double time = 0.0;
  std::array<double, 3> point{}, normal{}, impulse{};
};

std::string num(double v);
// "(x, y, z)" with num().
std::string vec_text(const std::array<double, 3>& v);

// Three floats from any sequence or array of shape (3,). `what` names the argument in errors:
// "force must have 3 components, got shape (2,)". Finite values are not checked here.
std::array<double, 3> to_array3(const py::handle& value, std::string_view what);
// The same for N numbers (defined for 3 and 4).
template <std::size_t N>
std::array<double, N> to_array(const py::handle& value, std::string_view what);
physics::Vec3 to_vec3(const py::handle& value, std::string_view what);
bool finite(const std::array<double, 3>& v);

// A timeout in seconds as milliseconds (capped at 10^9 s); a negative or NaN one is a ValueError.
std::chrono::milliseconds to_ms(double seconds);

// "world" or "body"; anything else is a ValueError naming the value.
physics::Frame to_frame(const py::handle& value, std::string_view what);

// A read-only NumPy view of `data` (row-major, rows x cols, or 1-D when cols == 0) that keeps
// `owner` alive: the memory stays valid as long as the view does.
py::array readonly_view(const double* data, py::ssize_t rows, py::ssize_t cols,
                        const py::object& owner);

}  // namespace rigid::python
