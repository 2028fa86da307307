// rigid._rigid: the C++ half of the `rigid` Python package (rigid/__init__.py is the other).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "common.hpp"
#include "physics/integrator.hpp"
#include "physics/world.hpp"
#include "scene/scene.hpp"

namespace py = pybind11;

PYBIND11_MODULE(_rigid, m) {
  using namespace rigid;
  using python::exceptions;
  m.doc() = "The C++ core of the rigid package: World (physics), State and the bus session.";

  auto& e = exceptions();
  e.scene_error = py::reinterpret_steal<py::object>(PyErr_NewExceptionWithDoc(
      "rigid.SceneError",
      "A scene file or text that cannot be loaded; str() is one line, \"FILE:LINE:COL: "
      "message\" (\"FILE: message\" without a position). Attributes: file, line, column "
      "(1-based; 0 without a position), message (without the prefix).",
      PyExc_ValueError, nullptr));
  e.spec_error = py::reinterpret_steal<py::object>(PyErr_NewExceptionWithDoc(
      "rigid.SpecError", "A valid scene that does not accept the given integrator or dt.",
      PyExc_ValueError, nullptr));
  e.unknown_body_error = py::reinterpret_steal<py::object>(PyErr_NewExceptionWithDoc(
      "rigid.UnknownBodyError",
      "A body name or index that is not in the scene; the message lists the scene's bodies.",
      PyExc_LookupError, nullptr));
  e.transport_error = py::reinterpret_steal<py::object>(PyErr_NewExceptionWithDoc(
      "rigid.TransportError",
      "A bus that cannot be set up (one line naming the bus and what to check).",
      PyExc_RuntimeError, nullptr));
  m.attr("SceneError") = e.scene_error;
  m.attr("SpecError") = e.spec_error;
  m.attr("UnknownBodyError") = e.unknown_body_error;
  m.attr("TransportError") = e.transport_error;

  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const scene::SceneError& err) {
      const py::object& type = exceptions().scene_error;
      py::object value = type(err.what());
      value.attr("file") = err.file();
      value.attr("line") = err.line();
      value.attr("column") = err.column();
      value.attr("message") = err.message();
      PyErr_SetObject(type.ptr(), value.ptr());
    } catch (const physics::SpecError& err) {
      PyErr_SetString(exceptions().spec_error.ptr(), err.what());
    }
  });

  m.def(
      "_integrators",
      [] {
        py::list out;
        const physics::IntegratorInfo& def = physics::default_integrator();
        for (const physics::IntegratorInfo& i : physics::all_integrators()) {
          py::dict d;
          d["name"] = std::string(i.name);
          d["order"] = i.order;
          d["symplectic"] = i.symplectic;
          d["gyroscopic"] = i.gyroscopic;
          d["summary"] = std::string(i.summary);
          d["default"] = i.id == def.id;
          out.append(d);
        }
        return out;
      },
      "Every integrator as a dict, in rigid-sim --list-integrators order.");

  python::bind_world(m);
  python::bind_states(m);
  python::bind_client(m);
}
