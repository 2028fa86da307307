// rigid.World: a physics::World compiled from a scene, stepped from Python.
//
// State arrays: the physics keeps each body model's state in its own arrays, about the principal
// frame P (model.hpp), so there is no (N, 3) world-frame array to view without copying. The world
// therefore owns persistent (N, 3) / (N, 4) buffers that World::state() fills, and hands out
// read-only NumPy views of them whose contents follow the world: after a step() or reset() the
// buffers are refreshed at once if a view of them is alive outside the world, and otherwise on the
// next read of a state property (so stepping a world nobody reads costs nothing extra).
#include "physics/world.hpp"

#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bindings.hpp"
#include "common.hpp"
#include "physics/integrator.hpp"
#include "scene/scene.hpp"

namespace rigid::python {
namespace {

using physics::Frame;
using physics::Vec3;

// The refreshed copies of the state; shared with every view, so a view outlives its world.
struct StateBuffers {
  explicit StateBuffers(std::size_t n)
      : positions(3 * n), orientations(4 * n), velocities(3 * n), angular_velocities(3 * n) {}
  std::vector<double> positions;           // (N, 3) p_WBo
  std::vector<double> orientations;        // (N, 4) q_WB, w first
  std::vector<double> velocities;          // (N, 3) v_WBo in W
  std::vector<double> angular_velocities;  // (N, 3) w_WB in W
};

class PyWorld {
  // Runs f with the world locked and the GIL released (another Python thread may be stepping).
  // Defined first: its return type is deduced, so it must be seen before its uses.
  template <class F>
  auto locked(F&& f) const {
    py::gil_scoped_release nogil;
    const std::lock_guard lock(mutex_);
    return f();
  }

 public:
  PyWorld(scene::Scene scene, const std::optional<std::string>& integrator,
          const std::optional<double>& dt)
      : scene_(std::move(scene)), world_(compile(scene_, integrator, dt)) {
    const auto n = static_cast<std::size_t>(world_.body_count());
    buffers_ = std::make_shared<StateBuffers>(n);
    // The capsule owns one reference to the buffers; each view keeps the capsule alive.
    auto* keep = new std::shared_ptr<StateBuffers>(buffers_);
    owner_ =
        py::capsule(keep, [](void* p) { delete static_cast<std::shared_ptr<StateBuffers>*>(p); });
    const auto rows = static_cast<py::ssize_t>(n);
    views_[0] = readonly_view(buffers_->positions.data(), rows, 3, owner_);
    views_[1] = readonly_view(buffers_->orientations.data(), rows, 4, owner_);
    views_[2] = readonly_view(buffers_->velocities.data(), rows, 3, owner_);
    views_[3] = readonly_view(buffers_->angular_velocities.data(), rows, 3, owner_);
    refresh();
    for (const std::string& w : scene_.warnings) {
      if (PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1) != 0) throw py::error_already_set();
    }
  }

  static std::unique_ptr<PyWorld> load(const std::string& path,
                                       const std::optional<std::string>& integrator,
                                       const std::optional<double>& dt) {
    std::optional<scene::Scene> s;
    {
      py::gil_scoped_release nogil;  // parsing a large scene takes a while
      s.emplace(scene::load_scene(path));
    }
    return std::make_unique<PyWorld>(std::move(*s), integrator, dt);
  }

  static std::unique_ptr<PyWorld> from_string(const std::string& text, const std::string& name,
                                              const std::optional<std::string>& integrator,
                                              const std::optional<double>& dt) {
    std::optional<scene::Scene> s;
    {
      py::gil_scoped_release nogil;
      s.emplace(scene::parse_scene(text, name));
    }
    return std::make_unique<PyWorld>(std::move(*s), integrator, dt);
  }

  void step(std::int64_t n) {
    if (n < 0) raise(value_error(), "step: n must be >= 0, got " + std::to_string(n));
    const bool live = views_live();
    {
      const std::lock_guard lock(mutex_);
      contacts_.clear();
      contacts_dropped_ = 0;
    }
    std::int64_t done = 0;
    std::int64_t chunk = 1;
    while (done < n) {
      {
        py::gil_scoped_release nogil;
        const std::lock_guard lock(mutex_);
        // World::step(n) is n single steps, so stepping in chunks gives the same bits; the chunks
        // grow until one takes ~50 ms, between them Ctrl-C is looked at.
        const auto t0 = std::chrono::steady_clock::now();
        while (done < n && std::chrono::steady_clock::now() - t0 < std::chrono::milliseconds(50)) {
          const std::int64_t k = std::min(chunk, n - done);
          world_.step(k);
          keep_contacts();
          done += k;
          if (chunk < (std::int64_t{1} << 40)) chunk *= 2;
        }
        if (done == n) {
          if (live) {
            refresh();
          } else {
            dirty_ = true;
          }
        } else {
          dirty_ = true;
        }
      }
      if (done < n && PyErr_CheckSignals() != 0) throw py::error_already_set();
    }
  }

  void reset() {
    const bool live = views_live();
    py::gil_scoped_release nogil;
    const std::lock_guard lock(mutex_);
    world_.reset();
    if (live) {
      refresh();
    } else {
      dirty_ = true;
    }
  }

  int body(const py::handle& b) const {
    if (py::isinstance<py::str>(b)) {
      const auto name = b.cast<std::string>();
      const int id = world_.find_body(name);
      if (id < 0) {
        raise(exceptions().unknown_body_error,
              "no body '" + name + "' in the scene (bodies: " + body_list() + ")");
      }
      return id;
    }
    if (py::isinstance<py::bool_>(b) || !py::isinstance<py::int_>(b)) {
      raise(type_error(), "a body is a name (str) or an index (int), got " +
                              std::string(py::str(py::type::of(b).attr("__name__"))));
    }
    const auto id = b.cast<long long>();
    if (id < 0 || id >= world_.body_count()) {
      raise(exceptions().unknown_body_error,
            "no body with index " + std::to_string(id) + " (the scene has " +
                std::to_string(world_.body_count()) + " bodies: " + body_list() + ")");
    }
    return static_cast<int>(id);
  }

  std::vector<std::string> body_names() const {
    std::vector<std::string> names;
    names.reserve(static_cast<std::size_t>(world_.body_count()));
    for (int i = 0; i < world_.body_count(); ++i)
      names.emplace_back(world_.body_name(i));
    return names;
  }

  py::object view(int which) {
    {
      py::gil_scoped_release nogil;
      const std::lock_guard lock(mutex_);
      if (dirty_) refresh();
    }
    return views_[which];
  }

  void add_force(const py::handle& b, const py::handle& force, const py::handle& at,
                 const py::handle& frame) {
    const int id = body(b);
    const auto f = to_array3(force, "force");
    const auto p = at.is_none() ? std::array<double, 3>{} : to_array3(at, "at");
    const Frame fr = to_frame(frame, "frame");
    check_finite("add_force", id, "force", f);
    check_finite("add_force", id, "at", p);
    locked([&] { world_.add_force(id, {f[0], f[1], f[2]}, {p[0], p[1], p[2]}, fr); });
  }

  void add_torque(const py::handle& b, const py::handle& torque, const py::handle& frame) {
    const int id = body(b);
    const auto t = to_array3(torque, "torque");
    const Frame fr = to_frame(frame, "frame");
    check_finite("add_torque", id, "torque", t);
    locked([&] { world_.add_torque(id, {t[0], t[1], t[2]}, fr); });
  }

  void apply_impulse(const py::handle& b, const py::handle& impulse, const py::handle& at,
                     const py::handle& frame) {
    const int id = body(b);
    const auto j = to_array3(impulse, "impulse");
    const auto p = at.is_none() ? std::array<double, 3>{} : to_array3(at, "at");
    const Frame fr = to_frame(frame, "frame");
    check_finite("apply_impulse", id, "impulse", j);
    check_finite("apply_impulse", id, "at", p);
    locked([&] { world_.apply_impulse(id, {j[0], j[1], j[2]}, {p[0], p[1], p[2]}, fr); });
  }

  void clear_applied(const py::handle& b) {
    if (b.is_none()) {
      locked([&] { world_.clear_applied(); });
    } else {
      const int id = body(b);
      locked([&] { world_.clear_applied(id); });
    }
  }

  void set_state(const py::handle& b, const py::handle& position, const py::handle& orientation,
                 const py::handle& velocity, const py::handle& angular_velocity) {
    const int id = body(b);
    physics::BodyState s = locked([&] { return world_.state(id); });
    if (!position.is_none()) s.p_WBo = to_vec3(position, "position");
    if (!orientation.is_none()) {
      py::array_t<double, py::array::c_style | py::array::forcecast> q =
          py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(orientation);
      if (!q || q.ndim() != 1 || q.shape(0) != 4) {
        PyErr_Clear();
        raise(value_error(), "orientation must be 4 numbers (w, x, y, z)");
      }
      s.q_WB = physics::Quat(q.at(0), q.at(1), q.at(2), q.at(3));
    }
    if (!velocity.is_none()) s.v_WBo = to_vec3(velocity, "velocity");
    if (!angular_velocity.is_none()) s.w_WB = to_vec3(angular_velocity, "angular_velocity");
    const bool live = views_live();
    try {
      locked([&] {
        world_.set_state(id, s);
        if (live) {
          refresh();
        } else {
          dirty_ = true;
        }
      });
    } catch (const std::invalid_argument& e) {
      raise(value_error(), e.what());
    }
  }

  double kinetic_energy(const py::handle& b) const {
    if (b.is_none()) {
      return locked([&] {
        double e = 0.0;
        for (int i = 0; i < world_.body_count(); ++i)
          e += world_.kinetic_energy(i);
        return e;
      });
    }
    const int id = body(b);
    return locked([&] { return world_.kinetic_energy(id); });
  }

  double total_energy() const {
    return locked([&] { return world_.total_energy(); });
  }

  py::array_t<double> linear_momentum(const py::handle& b) const {
    const std::optional<int> id = b.is_none() ? std::nullopt : std::optional<int>(body(b));
    const Vec3 p = locked([&] {
      Vec3 sum = Vec3::Zero();
      for (int i = id.value_or(0); i < (id ? *id + 1 : world_.body_count()); ++i) {
        const physics::BodySpec spec = world_.body_spec(i);
        if (spec.kinematic) continue;  // no mass that forces act on
        sum += spec.mass * world_.state(i).v_WBo;
      }
      return sum;
    });
    return vec3_array(p);
  }

  py::array_t<double> angular_momentum(const py::handle& b) const {
    if (!b.is_none()) {
      const int id = body(b);
      return vec3_array(locked([&] { return world_.angular_momentum_W(id); }));
    }
    // The whole world's, about the world origin: each body's own (about its centre of mass) plus
    // that of its centre of mass's motion.
    const Vec3 total = locked([&] {
      Vec3 sum = Vec3::Zero();
      for (int i = 0; i < world_.body_count(); ++i) {
        const physics::BodySpec spec = world_.body_spec(i);
        if (spec.kinematic) continue;
        const physics::BodyState s = world_.state(i);
        sum += world_.angular_momentum_W(i) + s.p_WBo.cross(spec.mass * s.v_WBo);
      }
      return sum;
    });
    return vec3_array(total);
  }

  py::array_t<double> masses() const {
    py::array_t<double> m(world_.body_count());
    auto r = m.mutable_unchecked<1>();
    for (int i = 0; i < world_.body_count(); ++i)
      r(i) = world_.body_spec(i).mass;
    return m;
  }

  py::array_t<double> inertia(const py::handle& b) const {
    const int id = body(b);
    const physics::BodySpec spec = world_.body_spec(id);
    py::array_t<double> a({3, 3});
    auto r = a.mutable_unchecked<2>();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        r(i, j) = spec.has_inertia ? spec.I_B(i, j) : 0.0;
    return a;
  }

  py::array_t<double> principal_moments(const py::handle& b) const {
    const int id = body(b);
    return vec3_array(world_.principal_moments(id));
  }

  std::string body_motion(const py::handle& b) const {
    return std::string(physics::to_string(world_.body_motion(body(b))));
  }

  // The contact events of the last step() call, in order (World::contact_events of each of its
  // chunks), as rigid.Contact objects named by the scene.
  py::list contacts() const {
    std::vector<physics::ContactEvent> events = locked([&] { return contacts_; });
    py::list out;
    for (const physics::ContactEvent& e : events) {
      Contact c;
      c.kind = std::string(physics::to_string(e.kind));
      c.body = std::string(world_.body_name(e.body));
      // A separate event has no one part (-1): the body left all its supports.
      c.part = e.part >= 0 ? std::string(world_.static_part_name(e.part)) : std::string();
      c.body_index = e.body;
      c.part_index = e.part;
      c.time = e.time;
      c.point = {e.p_W.x(), e.p_W.y(), e.p_W.z()};
      c.normal = {e.n_W.x(), e.n_W.y(), e.n_W.z()};
      c.impulse = {e.impulse_W.x(), e.impulse_W.y(), e.impulse_W.z()};
      out.append(py::cast(std::move(c)));
    }
    return out;
  }
  std::int64_t contacts_dropped() const {
    return locked([&] { return contacts_dropped_; });
  }

  std::vector<int> frozen_bodies() const {
    return locked([&] {
      const auto f = world_.frozen_bodies();
      return std::vector<int>(f.begin(), f.end());
    });
  }

  std::string repr() const {
    return "<rigid.World '" + scene_.path + "': " + std::to_string(world_.body_count()) +
           " bodies, " + std::string(world_.integrator().name) + ", dt=" + num(world_.dt()) +
           ", t=" + num(world_.time()) + ">";
  }

  const scene::Scene& scene() const { return scene_; }
  const physics::World& world() const { return world_; }

 private:
  static physics::World compile(const scene::Scene& scene,
                                const std::optional<std::string>& integrator,
                                const std::optional<double>& dt) {
    physics::WorldSpec spec = scene.world;
    if (integrator) spec.integrator = *integrator;
    if (dt) spec.dt = *dt;
    try {
      return physics::World(spec);
    } catch (const physics::SpecError& e) {
      // The scene itself was validated by the loader: only the overrides can be at fault.
      raise(exceptions().spec_error,
            std::string("the scene does not accept these options: ") + e.what());
    }
  }

  static py::object value_error() { return py::reinterpret_borrow<py::object>(PyExc_ValueError); }
  static py::object type_error() { return py::reinterpret_borrow<py::object>(PyExc_TypeError); }

  static py::array_t<double> vec3_array(const Vec3& v) {
    py::array_t<double> a(3);
    auto r = a.mutable_unchecked<1>();
    for (int i = 0; i < 3; ++i)
      r(i) = v[i];
    return a;
  }

  std::string body_list() const {
    std::string text;
    for (int i = 0; i < world_.body_count(); ++i)
      text += (i == 0 ? "" : ", ") + std::string(world_.body_name(i));
    return text.empty() ? "none" : text;
  }

  // The rule that "nothing changes" on an error: every argument is checked before the world is
  // touched.
  void check_finite(const char* op, int id, const char* what,
                    const std::array<double, 3>& v) const {
    if (!finite(v)) {
      raise(value_error(), std::string(op) + ": body '" + std::string(world_.body_name(id)) +
                               "': " + what + " " + vec_text(v) + " is not finite");
    }
  }

  // A view is alive outside the world when someone besides views_ holds it.
  bool views_live() const {
    for (const py::object& v : views_)
      if (v.ref_count() > 1) return true;
    return false;
  }

  // Fills the buffers from the world; called with mutex_ held.
  void refresh() {
    StateBuffers& b = *buffers_;
    world_.write_states({b.positions.data(), b.orientations.data(), b.velocities.data(),
                         b.angular_velocities.data()});
    dirty_ = false;
  }

  scene::Scene scene_;
  physics::World world_;
  mutable std::mutex mutex_;  // World is not thread-safe; Python threads run step() without GIL
  // The last step() call's contact events: at most kMaxKeptContacts, the rest counted (a long
  // step() of a scene with many contacts must not hold unbounded memory).
  static constexpr std::size_t kMaxKeptContacts = 1 << 20;
  std::vector<physics::ContactEvent> contacts_;
  std::int64_t contacts_dropped_ = 0;
  void keep_contacts() {
    const auto events = world_.contact_events();
    const std::size_t room = kMaxKeptContacts - contacts_.size();
    const std::size_t n = std::min(room, events.size());
    contacts_.insert(contacts_.end(), events.begin(),
                     events.begin() + static_cast<std::ptrdiff_t>(n));
    contacts_dropped_ += static_cast<std::int64_t>(events.size() - n);
  }
  std::shared_ptr<StateBuffers> buffers_;
  py::capsule owner_;
  std::array<py::object, 4> views_;
  bool dirty_ = true;
};

constexpr const char* kWorldDoc =
    R"doc(A rigid-body world, compiled from a scene file (protobuf text format).

Create one with World.load(path) or World.from_string(text); step it with step(n); read its state
as NumPy arrays (positions, orientations, velocities, angular_velocities), apply forces, torques
and impulses, and read its energy and momenta. The physics is the C++ rigid::physics::World
itself: the same scene and forces give the same numbers bit for bit as rigid-sim.

Frames: W is the world frame; B is a body's own frame (origin at its centre of mass), the one the
scene file uses. Orientations are unit quaternions (w, x, y, z) mapping B vectors to W.

State arrays are read-only NumPy views of buffers the world owns and refreshes after every step()
and reset(): a view you keep shows the current state (copy it, e.g. positions.copy(), to keep a
snapshot). They are copies of the physics state, not views of it: the physics keeps each body
model's state in its principal frame, so the world-frame values are computed when they are
refreshed (World::write_states, one pass over each model's bodies, on the world's threads for
large worlds: bench/step_bench's write_states, about 8 us for 10^3 general bodies, 0.45 ms for
10^5 on two threads). A view stays valid (and keeps its last
contents) after the world is gone.

Errors raise exceptions with the C++ tools' one-line messages and change nothing: SceneError
("FILE:LINE:COL: message"), UnknownBodyError (names the body and lists the scene's),
ValueError (a non-finite force names its value). The GIL is released while the world steps.
)doc";

py::tuple tuple3(const std::array<double, 3>& v) {
  return py::make_tuple(v[0], v[1], v[2]);
}

}  // namespace

void bind_world(py::module_& m) {
  // pybind11 would show py::handle arguments as "handle": the docstrings carry the signatures.
  py::options options;
  options.disable_function_signatures();
  py::class_<Contact>(m, "Contact", R"doc(One contact event: kind ("impact", "resting", "sliding",
"rolling" or "separate"), body and part (names; body_index and part_index their indices), time
(the world's time it happened at, s; part "" and part_index -1 for a separate event: the body
left all its supports), point, normal (the part's, towards the body) and impulse
(on the body, N s; zero but for an impact), all in the world frame.)doc")
      .def_readonly("kind", &Contact::kind)
      .def_readonly("body", &Contact::body)
      .def_readonly("part", &Contact::part)
      .def_readonly("body_index", &Contact::body_index)
      .def_readonly("part_index", &Contact::part_index)
      .def_readonly("time", &Contact::time)
      .def_property_readonly("point", [](const Contact& c) { return tuple3(c.point); })
      .def_property_readonly("normal", [](const Contact& c) { return tuple3(c.normal); })
      .def_property_readonly("impulse", [](const Contact& c) { return tuple3(c.impulse); })
      .def("__repr__", [](const Contact& c) {
        return "<rigid.Contact " + c.kind + " of '" + c.body + "' on '" + c.part +
               "' at t=" + num(c.time) + ", point " + vec_text(c.point) + ", impulse " +
               vec_text(c.impulse) + ">";
      });
  py::class_<PyWorld>(m, "World", kWorldDoc)
      .def_static(
          "load", &PyWorld::load, py::arg("path"), py::kw_only(),
          py::arg("integrator") = py::none(), py::arg("dt") = py::none(),
          R"doc(load(path: str, *, integrator: str | None = None, dt: float | None = None) -> World

Load a scene file and compile its world.

integrator, dt: override the scene's integrator (a name from rigid.integrators()) and physics
step in seconds, as rigid-sim --integrator/--dt do.

Raises SceneError ("FILE:LINE:COL: message") for a bad scene, SpecError when the scene does not
accept the overrides. The scene's warnings are issued as UserWarning.)doc")
      .def_static(
          "from_string", &PyWorld::from_string, py::arg("text"), py::arg("name") = "<string>",
          py::kw_only(), py::arg("integrator") = py::none(), py::arg("dt") = py::none(),
          R"doc(from_string(text: str, name: str = "<string>", *, integrator: str | None = None, dt: float | None = None) -> World

Compile a world from scene text; `name` stands for the file in messages.

Otherwise as World.load.)doc")
      .def("step", &PyWorld::step, py::arg("n") = 1,
           R"doc(step(n: int = 1) -> None

Advance by n physics steps of dt (n >= 0), with the GIL released.

Exactly World::step() n times: the same bits as one C++ call. Ctrl-C stops between steps (after
a whole number of them).)doc")
      .def("reset", &PyWorld::reset,
           "reset() -> None\n\nBack to the scene's initial state at time 0; applied loads and "
           "pending impulses are "
           "cleared and frozen bodies thawed.")
      .def("body", &PyWorld::body, py::arg("body"),
           R"doc(body(body: str | int) -> int

The index of a body, from its name (or an index, checked).

Raises UnknownBodyError naming the body and listing the scene's bodies.)doc")
      .def_property_readonly("body_names", &PyWorld::body_names,
                             "The bodies' names, in index order (a new list).")
      .def_property_readonly(
          "body_count", [](const PyWorld& w) { return w.world().body_count(); },
          "The number of bodies.")
      .def("__len__", [](const PyWorld& w) { return w.world().body_count(); })
      .def_property_readonly(
          "positions", [](PyWorld& w) { return w.view(0); },
          "(N, 3) read-only view: each body's centre of mass p_WBo in W (m). Refreshed after "
          "each step() and reset() (a copy of the physics state, not a view of it).")
      .def_property_readonly(
          "orientations", [](PyWorld& w) { return w.view(1); },
          "(N, 4) read-only view: each body's orientation q_WB as a unit quaternion (w, x, y, z), "
          "mapping body-frame vectors to W. Refreshed like positions.")
      .def_property_readonly(
          "velocities", [](PyWorld& w) { return w.view(2); },
          "(N, 3) read-only view: each centre of mass's velocity v_WBo in W (m/s). Refreshed like "
          "positions.")
      .def_property_readonly(
          "angular_velocities", [](PyWorld& w) { return w.view(3); },
          "(N, 3) read-only view: each body's angular velocity w_WB in W (rad/s). Refreshed like "
          "positions.")
      .def(
          "add_force", &PyWorld::add_force, py::arg("body"), py::arg("force"),
          py::arg("at") = py::none(), py::arg("frame") = "world",
          R"doc(add_force(body: str | int, force: ArrayLike, at: ArrayLike | None = None, frame: str = "world") -> None

Apply a force (N) at a body point until clear_applied().

body: name or index. at: the point from the centre of mass in the body frame B (m); None: the
centre of mass. frame: "world" (force in W) or "body" (in B: it turns with the body).
Applied loads add to the scene's loads and stay until cleared (rigidd rebuilds them every tick
from its wrenches; here the caller decides). Raises UnknownBodyError, ValueError for a
non-finite value (named), and then changes nothing.)doc")
      .def(
          "add_torque", &PyWorld::add_torque, py::arg("body"), py::arg("torque"),
          py::arg("frame") = "world",
          "add_torque(body: str | int, torque: ArrayLike, frame: str = \"world\") -> None\n\nApply "
          "a pure torque (N m), in W or in B (frame=\"body\"), until clear_applied(). "
          "Errors as add_force.")
      .def(
          "apply_impulse", &PyWorld::apply_impulse, py::arg("body"), py::arg("impulse"),
          py::arg("at") = py::none(), py::arg("frame") = "world",
          R"doc(apply_impulse(body: str | int, impulse: ArrayLike, at: ArrayLike | None = None, frame: str = "world") -> None

An instantaneous momentum change J (N s) at a body point (from the centre of mass,
in B), in W or B: applied at the start of the next step, then forgotten. Errors as add_force.)doc")
      .def("clear_applied", &PyWorld::clear_applied, py::arg("body") = py::none(),
           "clear_applied(body: str | int | None = None) -> None\n\nRemove the forces and torques "
           "applied so far (of one body, or of all).")
      .def(
          "set_state", &PyWorld::set_state, py::arg("body"), py::kw_only(),
          py::arg("position") = py::none(), py::arg("orientation") = py::none(),
          py::arg("velocity") = py::none(), py::arg("angular_velocity") = py::none(),
          R"doc(set_state(body: str | int, *, position=None, orientation=None, velocity=None, angular_velocity=None) -> None

Overwrite parts of a body's state (world frame; orientation w first); the others
are kept. Raises ValueError for a non-finite state or a zero quaternion, and changes nothing.)doc")
      .def("kinetic_energy", &PyWorld::kinetic_energy, py::arg("body") = py::none(),
           "kinetic_energy(body: str | int | None = None) -> float\n\nKinetic energy (J) of one "
           "body, or of all (body=None).")
      .def("total_energy", &PyWorld::total_energy,
           "total_energy() -> float\n\nKinetic energy of every body plus the gravitational "
           "potential -m g . p of "
           "gravity-affected ones (J).")
      .def("linear_momentum", &PyWorld::linear_momentum, py::arg("body") = py::none(),
           "linear_momentum(body: str | int | None = None) -> ndarray (3,)\n\nm v (N s) in W of "
           "one body, or the sum over the world (kinematic bodies excluded).")
      .def("angular_momentum", &PyWorld::angular_momentum, py::arg("body") = py::none(),
           R"doc(angular_momentum(body: str | int | None = None) -> ndarray (3,)

Angular momentum (N m s) in W: one body's about its centre of mass, or (body=None)
the whole world's about the world origin (kinematic bodies excluded).)doc")
      .def_property_readonly("masses", &PyWorld::masses, "(N,) the bodies' masses (kg), a copy.")
      .def("inertia", &PyWorld::inertia, py::arg("body"),
           "inertia(body: str | int) -> ndarray (3, 3)\n\nThe inertia tensor about the centre of "
           "mass in B (kg m^2), as the scene gives it "
           "(zeros for a point mass).")
      .def("principal_moments", &PyWorld::principal_moments, py::arg("body"),
           "principal_moments(body: str | int) -> ndarray (3,)\n\nPrincipal moments of inertia, "
           "ascending (kg m^2).")
      .def("body_motion", &PyWorld::body_motion, py::arg("body"),
           "body_motion(body: str | int) -> str\n\nThe motion group the body compiled to, named by "
           "the cheapest exact motion for it: translation (never turns), steady_spin (turns about "
           "an axis fixed in the body: isotropic bodies, hinges, kinematic spinning bodies), "
           "precession (axisymmetric) or tumbling (general).")
      .def_property_readonly(
          "time", [](const PyWorld& w) { return w.world().time(); },
          "Simulated time (s): step_count * dt.")
      .def_property_readonly(
          "step_count", [](const PyWorld& w) { return w.world().step_count(); },
          "Steps taken since the start or the last reset().")
      .def_property_readonly(
          "dt", [](const PyWorld& w) { return w.world().dt(); }, "The physics step (s).")
      .def_property_readonly(
          "integrator", [](const PyWorld& w) { return std::string(w.world().integrator().name); },
          "The integrator's name.")
      .def_property_readonly(
          "rate_hz", [](const PyWorld& w) { return w.scene().rate_hz; },
          "The scene's tick rate (rigidd's; rate_hz * substeps = 1 / dt unless dt was overridden).")
      .def_property_readonly(
          "substeps", [](const PyWorld& w) { return w.scene().substeps; },
          "Physics steps per tick, from the scene.")
      .def_property_readonly(
          "path", [](const PyWorld& w) { return w.scene().path; },
          "The scene file (or the name given to from_string).")
      .def_property_readonly("frozen_bodies", &PyWorld::frozen_bodies,
                             "Bodies the physics guard froze (non-finite or absurd state), in "
                             "order; reset() thaws them.")
      .def_property_readonly(
          "large_rotation_steps", [](const PyWorld& w) { return w.world().large_rotation_steps(); },
          "Body-steps that turned a body by more than pi under an integrator not exact for it.")
      .def("contacts", &PyWorld::contacts,
           R"doc(contacts() -> list[Contact]

The contact events of the last step() call, in order of step, then body, then time: every impact
and every change of how a body is supported (starts resting, sliding, rolling, leaves its
supports) by the scene's planes and static shapes. Empty for a scene without them. At most 2^20
are kept; contacts_dropped counts the rest (and the physics keeps at most 4096 a step).)doc")
      .def_property_readonly("contacts_dropped", &PyWorld::contacts_dropped,
                             "Contact events of the last step() call beyond what contacts() "
                             "keeps.")
      .def_property_readonly(
          "static_parts",
          [](const PyWorld& w) {
            std::vector<std::string> names;
            for (int i = 0; i < w.world().static_part_count(); ++i)
              names.emplace_back(w.world().static_part_name(i));
            return names;
          },
          "The static parts' names (planes, then static shapes), in index order (a new list).")
      .def("__repr__", &PyWorld::repr);
}

}  // namespace rigid::python
