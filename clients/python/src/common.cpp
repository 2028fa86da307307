#include "common.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>

namespace rigid::python {

Exceptions& exceptions() {
  // Never destroyed: the interpreter may be finalizing when static destructors run.
  static auto* e = new Exceptions();
  return *e;
}

void raise(const py::object& type, const std::string& message) {
  PyErr_SetString(type.ptr(), message.c_str());
  throw py::error_already_set();
}

std::string num(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.9g", v);
  return buffer;
}

std::string vec_text(const std::array<double, 3>& v) {
  return "(" + num(v[0]) + ", " + num(v[1]) + ", " + num(v[2]) + ")";
}

std::chrono::milliseconds to_ms(double seconds) {
  if (!(seconds >= 0.0)) {
    raise(py::reinterpret_borrow<py::object>(PyExc_ValueError),
          "timeout must be >= 0 seconds, got " + num(seconds));
  }
  return std::chrono::milliseconds(
      static_cast<std::int64_t>(std::min(seconds, 1e9) * 1000.0 + 0.5));
}

std::array<double, 3> to_array3(const py::handle& value, std::string_view what) {
  return to_array<3>(value, what);
}

template <std::size_t N>
std::array<double, N> to_array(const py::handle& value, std::string_view what) {
  const std::string n = std::to_string(N);
  py::array_t<double, py::array::c_style | py::array::forcecast> a;
  try {
    a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
  } catch (const py::error_already_set&) {
    a = {};
  }
  if (!a) {
    PyErr_Clear();
    raise(py::reinterpret_borrow<py::object>(PyExc_TypeError),
          std::string(what) + " must be " + n + " numbers, got " +
              std::string(py::str(py::type::of(value).attr("__name__"))));
  }
  if (a.ndim() != 1 || a.shape(0) != static_cast<py::ssize_t>(N)) {
    std::string shape = "(";
    for (py::ssize_t i = 0; i < a.ndim(); ++i)
      shape += std::to_string(a.shape(i)) + (a.ndim() == 1 ? "," : i + 1 < a.ndim() ? ", " : "");
    raise(py::reinterpret_borrow<py::object>(PyExc_ValueError),
          std::string(what) + " must have " + n + " components, got shape " + shape + ")");
  }
  std::array<double, N> out{};
  for (std::size_t i = 0; i < N; ++i)
    out[i] = a.at(static_cast<py::ssize_t>(i));
  return out;
}
template std::array<double, 3> to_array<3>(const py::handle&, std::string_view);
template std::array<double, 4> to_array<4>(const py::handle&, std::string_view);

physics::Vec3 to_vec3(const py::handle& value, std::string_view what) {
  const auto a = to_array3(value, what);
  return {a[0], a[1], a[2]};
}

bool finite(const std::array<double, 3>& v) {
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

physics::Frame to_frame(const py::handle& value, std::string_view what) {
  if (py::isinstance<py::str>(value)) {
    const auto s = value.cast<std::string>();
    if (s == "world") return physics::Frame::kWorld;
    if (s == "body") return physics::Frame::kBody;
  }
  raise(py::reinterpret_borrow<py::object>(PyExc_ValueError),
        std::string(what) + " must be 'world' or 'body', got " + std::string(py::repr(value)));
}

py::array readonly_view(const double* data, py::ssize_t rows, py::ssize_t cols,
                        const py::object& owner) {
  constexpr auto kSize = static_cast<py::ssize_t>(sizeof(double));
  py::array a = cols == 0 ? py::array(py::dtype::of<double>(), {rows}, {kSize}, data, owner)
                          : py::array(py::dtype::of<double>(), {rows, cols}, {cols * kSize, kSize},
                                      data, owner);
  // A view of state the module owns: writing to it would corrupt what the next reader sees, and
  // NumPy refuses to make it writeable again because its base is not a writeable buffer.
  a.attr("flags").attr("writeable") = false;
  return a;
}

}  // namespace rigid::python
