// The low-level client: rigid::client::Session for Python (rigid/__init__.py wraps it as
// rigid.Client). Answers come back as plain values (dicts, State); turning a refusal into an
// exception is the Python layer's, so that its messages live in one readable place.
//
// Threads: every call that waits for the bus releases the GIL while it waits. The states go
// to Python through states.hpp (streams, and callbacks run on the receive thread); a call made
// inside such a callback must not wait for the bus, which that thread would have to receive.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "bindings.hpp"
#include "common.hpp"
#include "rigid/client/names.hpp"
#include "session_api.hpp"
#include "states.hpp"

namespace rigid::python {
namespace {

py::dict reply_dict(const ControlReply& r) {
  py::dict d;
  d["command"] = std::string(sdk::control_name(r.command));
  d["ok"] = r.outcome == Outcome::kOk;
  d["outcome"] = std::string(sdk::outcome_name(r.outcome));
  d["message"] = r.message;
  d["tick"] = r.tick;
  d["seq"] = r.seq;
  return d;
}

py::tuple vec_tuple(const rigid::Vec3& v) {
  return py::make_tuple(v[0], v[1], v[2]);
}

py::dict accepted_dict(const AcceptedCommand& a) {
  py::dict d;
  d["tick"] = a.tick;
  d["seq"] = a.seq;
  d["body"] = a.body_id;
  d["force"] = vec_tuple(a.force);
  d["at"] = vec_tuple(a.point);
  d["frame"] = std::string(rigid::frame_name(a.force_frame));
  d["torque"] = vec_tuple(a.torque);
  d["torque_frame"] = std::string(rigid::frame_name(a.torque_frame));
  d["ttl"] = a.ttl;
  return d;
}

py::dict scene_dict(const SceneDescription& s) {
  py::dict d;
  d["name"] = s.scene_name;
  d["dt"] = s.dt;
  d["substeps"] = s.substeps;
  d["publish_every"] = s.publish_every;
  d["gravity"] = vec_tuple(s.gravity);
  d["integrator"] = s.integrator;
  d["max_force"] = s.max_force;
  d["max_torque"] = s.max_torque;
  d["max_ttl"] = s.max_ttl;
  d["max_wrenches_per_source"] = s.max_wrenches_per_source;
  d["max_commands_per_second"] = s.max_commands_per_second;
  py::list bodies;
  for (std::size_t i = 0; i < s.body_count(); ++i) {
    py::dict b;
    b["id"] = s.ids[i];
    b["name"] = s.names[i];
    b["mass"] = s.masses[i];
    const double* I = &s.inertia[6 * i];  // Ixx, Iyy, Izz, Ixy, Ixz, Iyz
    b["inertia"] =
        py::make_tuple(py::make_tuple(I[0], I[3], I[4]), py::make_tuple(I[3], I[1], I[5]),
                       py::make_tuple(I[4], I[5], I[2]));
    b["shape"] = std::string(rigid::client::shape_name(s.shape_kinds[i]));
    b["dims"] =
        py::make_tuple(s.shape_dims[3 * i], s.shape_dims[3 * i + 1], s.shape_dims[3 * i + 2]);
    bodies.append(b);
  }
  d["bodies"] = bodies;
  return d;
}

py::dict stats_dict(const StatsReport& s) {
  py::dict d;
  d["tick"] = s.tick;
  d["sim_time"] = s.sim_time;
  d["mode"] = std::string(rigid::mode_name(s.mode));
  d["paused"] = s.paused;
  d["rtf_last_second"] = s.rtf_last_second;
  d["rtf_since_start"] = s.rtf_since_start;
  d["lateness_p50_us"] = s.lateness_p50_us;
  d["lateness_p99_us"] = s.lateness_p99_us;
  d["lateness_max_us"] = s.lateness_max_us;
  d["overruns"] = s.overruns;
  d["step_cost_p50_us"] = s.step_cost_p50_us;
  d["step_cost_max_us"] = s.step_cost_max_us;
  d["bodies_frozen"] = s.bodies_frozen;
  d["large_rotation_steps"] = s.large_rotation_steps;
  d["states_skipped"] = s.states_skipped;
  d["commands_accepted"] = s.commands_accepted;
  const rigid::RejectCounts& r = s.rejected;
  py::dict rejected;
  rejected["non_finite"] = r.non_finite;
  rejected["unknown_body"] = r.unknown_body;
  rejected["over_limit"] = r.over_limit;
  rejected["undecodable"] = r.undecodable;
  rejected["stale_sequence"] = r.stale_sequence;
  rejected["queue_full"] = r.queue_full;
  rejected["invalid"] = r.invalid;
  rejected["over_share"] = r.over_share;
  rejected["rate_limited"] = r.rate_limited;
  rejected["not_permitted"] = r.not_permitted;
  d["rejected"] = rejected;
  for (const auto& [name, c] :
       {std::pair<const char*, const rigid::TransportCounts*>{"dds", &s.dds}, {"lcm", &s.lcm}}) {
    py::dict t;
    t["sent"] = c->sent;
    t["send_failures"] = c->send_failures;
    t["received"] = c->received;
    t["decode_failures"] = c->decode_failures;
    d[name] = t;
  }
  py::list refused;
  for (const rigid::SourceRefusals& r2 : s.refused_by_source) {
    py::dict e;
    e["sender"] = r2.sender;
    e["count"] = r2.count;
    e["last_reason"] = r2.last_reason;
    refused.append(e);
  }
  d["refused_by_source"] = refused;
  return d;
}

rigid::Frame wire_frame(const py::handle& value, std::string_view what) {
  if (py::isinstance<py::str>(value)) {
    if (const auto f = rigid::frame_named(value.cast<std::string>())) return *f;
  }
  raise(py::reinterpret_borrow<py::object>(PyExc_ValueError),
        std::string(what) + " must be 'world' or 'body', got " + std::string(py::repr(value)));
}

// The functions Client.on_contact() registered, called on the receive thread with each event of
// each tick (rigid.Contact, named by the newest SceneInfo). `mutex` is held while they run and is
// taken by Python threads only with the GIL released; an exception ends its function (reported
// through sys.unraisablehook), as an on_state callback's.
struct ContactCallbacks {
  std::mutex mutex;
  std::vector<py::function> fns;  // touched with the GIL (and the mutex, but at close())
  std::atomic<std::thread::id> delivering{};
  bool in_callback() const { return delivering.load() == std::this_thread::get_id(); }

  void deliver(const ContactEvents& e, sdk::Session& session) {
    const std::lock_guard lock(mutex);
    if (fns.empty() || !e.lengths_agree() || finalizing()) return;
    const std::optional<SceneDescription> scene = session.wait_scene(std::chrono::milliseconds(0));
    const auto name = [](const std::vector<std::string>* names, std::int32_t i) {
      if (names != nullptr && i >= 0 && static_cast<std::size_t>(i) < names->size())
        return (*names)[static_cast<std::size_t>(i)];
      return i < 0 ? std::string() : std::to_string(i);
    };
    std::vector<std::string> body_names;  // by id
    if (scene) {
      for (std::size_t i = 0; i < scene->ids.size() && i < scene->names.size(); ++i) {
        const auto id = static_cast<std::size_t>(std::max(0, scene->ids[i]));
        if (id >= kMaxBodies) continue;
        if (id >= body_names.size()) body_names.resize(id + 1);
        body_names[id] = scene->names[i];
      }
    }
    delivering.store(std::this_thread::get_id());
    {
      const py::gil_scoped_acquire gil;
      for (std::size_t k = 0; k < e.event_count() && !fns.empty(); ++k) {
        Contact c;
        c.kind = std::string(rigid::contact_name(e.kinds[k]));
        c.body_index = e.bodies[k];
        c.part_index = e.parts[k];
        c.body = name(&body_names, e.bodies[k]);
        c.part = name(scene ? &scene->part_names : nullptr, e.parts[k]);
        c.time = e.times[k];
        for (std::size_t j = 0; j < 3; ++j) {
          c.point[j] = e.position[3 * k + j];
          c.normal[j] = e.normal[3 * k + j];
          c.impulse[j] = e.impulse[3 * k + j];
        }
        const py::object o = py::cast(std::move(c));
        for (std::size_t f = 0; f < fns.size();) {
          try {
            fns[f](o);
            ++f;
          } catch (py::error_already_set& x) {
            x.discard_as_unraisable("rigid.Client.on_contact callback");
            fns.erase(fns.begin() + static_cast<std::ptrdiff_t>(f));
          }
        }
      }
    }
    delivering.store(std::thread::id{});
  }
};

class PySession {
 public:
  PySession(const std::string& transport, const std::string& prefix, std::uint32_t domain,
            const std::optional<std::string>& url, const std::optional<std::string>& security) {
    sdk::BusOptions o;
    if (transport == "dds") {
      o.bus = rigid::Bus::kDds;
    } else if (transport == "lcm") {
      o.bus = rigid::Bus::kLcm;
    } else {
      raise(py::reinterpret_borrow<py::object>(PyExc_ValueError),
            "transport must be 'dds' or 'lcm', got '" + transport + "'");
    }
    o.prefix = prefix;
    o.dds_domain = domain;
    o.lcm_url = url.value_or("");
    o.security = security.value_or("");
    delivery_ = std::make_shared<StateDelivery>();
    try {
      py::gil_scoped_release nogil;  // joining a DDS domain takes a moment
      session_ = std::make_shared<sdk::Session>(o);
    } catch (const sdk::BusError& e) {
      raise(exceptions().transport_error, e.what());
    }
    contacts_ = std::make_shared<ContactCallbacks>();
    std::weak_ptr<ContactCallbacks> contacts = contacts_;
    sdk::Session* session = session_.get();  // the handler is cleared before the session goes
    session_->on_each_contacts([contacts, session](const ContactEvents& e) {
      if (auto c = contacts.lock()) c->deliver(e, *session);
    });
    std::weak_ptr<StateDelivery> delivery = delivery_;
    session_->on_each_state_shared([delivery](const std::shared_ptr<const StateFrame>& f) {
      if (auto d = delivery.lock()) d->deliver(f);
    });
    describe_ = sdk::describe(o);
  }

  ~PySession() {
    // Dropped inside one of its own callbacks, the session cannot stop the thread that runs it.
    if (!delivery_->in_callback() && !contacts_->in_callback()) close();
  }
  PySession(const PySession&) = delete;
  PySession& operator=(const PySession&) = delete;

  void close() {
    if (!session_) return;
    if (delivery_->in_callback() || contacts_->in_callback()) {
      raise(py::reinterpret_borrow<py::object>(PyExc_RuntimeError),
            "Client.close() inside an on_state callback would stop the thread running it: "
            "close the callback instead (or close the client outside it)");
    }
    std::shared_ptr<sdk::Session> s = std::move(session_);
    {
      py::gil_scoped_release nogil;
      s->on_each_state_shared({});  // waits for a delivery in progress
      s->on_each_contacts({});
      s.reset();  // the bus stops here unless a call in another thread still holds it
    }
    delivery_->end_callbacks();
    contacts_->fns.clear();  // (no delivery runs any more)
  }

  // Client.on_contact(fn): fn(contact) on the receive thread for every contact event from now on.
  void on_contact(const py::function& fn) {
    (void)live();
    if (contacts_->in_callback()) {
      raise(py::reinterpret_borrow<py::object>(PyExc_RuntimeError),
            "Client.on_contact() inside an on_contact callback");
    }
    py::function f = fn;  // a reference taken with the GIL
    py::gil_scoped_release nogil;
    const std::lock_guard lock(contacts_->mutex);
    contacts_->fns.push_back(std::move(f));
  }

  // Client.on_state(fn): fn(state) on the receive thread for every state from now on.
  PyStateCallback on_state(const py::function& fn) {
    (void)live();
    auto c = std::make_shared<StateCallback>(fn);
    delivery_->add_callback(c);
    return PyStateCallback(delivery_, std::move(c));
  }

  const std::string& describe() const { return describe_; }
  std::int64_t source() const { return live()->source(); }

  py::object scene(double timeout) {
    const auto session = live();
    const auto patience = wait_for(timeout);
    std::optional<SceneDescription> s;
    {
      py::gil_scoped_release nogil;
      s = session->wait_scene(patience);
    }
    if (!s) nothing_yet_in_callback("Client.scene()", "SceneInfo");
    return s ? py::object(scene_dict(*s)) : py::none();
  }

  std::uint64_t scene_generation() const { return live()->scene_generation(); }

  py::object stats(double timeout) {
    const auto session = live();
    const auto patience = wait_for(timeout);
    std::optional<StatsReport> s;
    {
      py::gil_scoped_release nogil;
      s = session->wait_stats(patience);
    }
    if (!s) nothing_yet_in_callback("Client.stats()", "Stats");
    return s ? py::object(stats_dict(*s)) : py::none();
  }

  bool wait_server(double timeout) {
    const auto session = live();
    const auto ms = wait_for(timeout);
    py::gil_scoped_release nogil;
    return session->wait_server(ms);
  }

  py::object latest() const {
    const auto session = live();
    std::shared_ptr<const StateFrame> s;
    {
      py::gil_scoped_release nogil;
      s = session->latest_state_shared();
    }
    if (!s) return py::none();
    return py::cast(PyState(std::move(s)));
  }

  std::unique_ptr<PyStateStream> states(double timeout, std::size_t max_queue) {
    // (a stream may be opened inside a callback; only waiting for its next state is refused)
    (void)to_ms(timeout);  // checked now, not at the first next()
    return std::make_unique<PyStateStream>(delivery_, max_queue, timeout, describe_);
  }

  // "pause", "resume", "step", "reset", "rate": rigidd's answer as a dict, None on no answer.
  py::object request(const std::string& kind, std::int64_t steps, double rtf, double timeout) {
    no_answer_in_callback("Client." + (kind == "rate" ? std::string("set_rate") : kind) + "()");
    const auto patience = to_ms(timeout);
    if (kind != "pause" && kind != "resume" && kind != "step" && kind != "reset" &&
        kind != "rate") {
      raise(py::reinterpret_borrow<py::object>(PyExc_ValueError),
            "unknown control '" + kind + "' (pause, resume, step, reset, rate)");
    }
    const auto s = live();
    std::optional<ControlReply> r;
    {
      py::gil_scoped_release nogil;
      if (kind == "pause") {
        r = s->pause(patience);
      } else if (kind == "resume") {
        r = s->resume(patience);
      } else if (kind == "step") {
        r = s->step(steps, patience);
      } else if (kind == "reset") {
        r = s->reset(patience);
      } else {
        r = s->set_rtf(rtf, patience);
      }
    }
    return r ? py::object(reply_dict(*r)) : py::none();
  }

  // "set_state" (the parts given, None for the others) or "reset_body" of one body (an id from
  // resolve()): rigidd's answer as a dict, None on no answer. Numbers are checked here first
  // (ValueError naming the argument and its value); rigidd checks them again.
  py::object edit(const std::string& kind, std::int32_t body, const py::handle& position,
                  const py::handle& orientation, const py::handle& velocity,
                  const py::handle& velocity_frame, const py::handle& angular_velocity,
                  const py::handle& angular_velocity_frame, double timeout) {
    const auto value_error = [](const std::string& message) {
      raise(py::reinterpret_borrow<py::object>(PyExc_ValueError), message);
    };
    no_answer_in_callback("Client." + kind + "()");
    const auto patience = to_ms(timeout);
    EditCommand e;
    e.body_id = body;
    if (kind == "reset_body") {
      e.kind = EditKind::kResetBody;
    } else if (kind == "set_state") {
      e.kind = EditKind::kSetState;
      if (!position.is_none()) {
        e.set |= kSetPosition;
        e.position = to_array3(position, "position");
        if (!finite(e.position)) value_error("position " + vec_text(e.position) + " is not finite");
      }
      if (!orientation.is_none()) {
        e.set |= kSetOrientation;
        e.orientation = to_array<4>(orientation, "orientation");
        const auto& q = e.orientation;
        const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        if (!(std::abs(n - 1.0) <= 1e-3)) {
          value_error("orientation (" + num(q[0]) + ", " + num(q[1]) + ", " + num(q[2]) + ", " +
                      num(q[3]) + ") must be a unit quaternion w, x, y, z (|q| " + num(n) +
                      ", 1 within 1e-3)");
        }
      }
      if (!velocity.is_none()) {
        e.set |= kSetLinearVelocity;
        e.linear_velocity = to_array3(velocity, "velocity");
        if (!finite(e.linear_velocity)) {
          value_error("velocity " + vec_text(e.linear_velocity) + " is not finite");
        }
      }
      if (!angular_velocity.is_none()) {
        e.set |= kSetAngularVelocity;
        e.angular_velocity = to_array3(angular_velocity, "angular_velocity");
        if (!finite(e.angular_velocity)) {
          value_error("angular_velocity " + vec_text(e.angular_velocity) + " is not finite");
        }
      }
      e.velocity_frame = wire_frame(velocity_frame, "velocity_frame");
      e.angular_velocity_frame = wire_frame(angular_velocity_frame, "angular_velocity_frame");
      if (e.set == 0) {
        value_error(
            "set_state: nothing to set (position, orientation, velocity, angular_velocity)");
      }
    } else {
      value_error("unknown edit '" + kind + "' (set_state, reset_body)");
    }
    const auto s = live();
    std::optional<ControlReply> r;
    {
      py::gil_scoped_release nogil;
      r = s->edit(e, patience);
    }
    if (!r) return py::none();
    py::dict d = reply_dict(*r);
    d["command"] = kind;
    return d;
  }

  // The id of a body by name or id in the current scene, with rigidctl's message when unknown.
  std::int32_t resolve(const py::handle& body, double timeout) {
    std::string key;
    if (py::isinstance<py::str>(body)) {
      key = body.cast<std::string>();
    } else if (py::isinstance<py::int_>(body) && !py::isinstance<py::bool_>(body)) {
      key = std::to_string(body.cast<long long>());
    } else {
      raise(py::reinterpret_borrow<py::object>(PyExc_TypeError),
            "a body is a name (str) or an id (int), got " +
                std::string(py::str(py::type::of(body).attr("__name__"))));
    }
    const auto session = live();
    const auto patience = wait_for(timeout);
    std::optional<SceneDescription> scene;
    {
      py::gil_scoped_release nogil;
      scene = session->wait_scene(patience);
    }
    if (!scene) nothing_yet_in_callback("resolving a body", "SceneInfo");
    if (!scene) {
      raise(py::reinterpret_borrow<py::object>(PyExc_TimeoutError),
            "no SceneInfo from rigidd within " + num(timeout) + " s on " + describe_ +
                " (is rigidd running, with the same transport, prefix and domain?)");
    }
    const auto id = sdk::find_body(*scene, key);
    if (!id) {
      raise(exceptions().unknown_body_error,
            "no body '" + key + "' in the scene (bodies: " + sdk::body_list(*scene) + ")");
    }
    return *id;
  }

  WrenchCommand wrench(std::int32_t body, const py::handle& force, const py::handle& at,
                       const py::handle& frame, const py::handle& torque,
                       const py::handle& torque_frame, double ttl) const {
    WrenchCommand w;
    w.body_id = body;
    w.force = force.is_none() ? rigid::Vec3{} : to_array3(force, "force");
    w.point = at.is_none() ? rigid::Vec3{} : to_array3(at, "at");
    w.force_frame = wire_frame(frame, "frame");
    w.torque = torque.is_none() ? rigid::Vec3{} : to_array3(torque, "torque");
    w.torque_frame = wire_frame(torque_frame, "torque_frame");
    w.ttl = ttl;
    w.stamp_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                     std::chrono::system_clock::now().time_since_epoch())
                     .count();
    return w;
  }

  // (accepted dict, None) | (None, rigidd's reason) | (None, None) on no answer.
  py::tuple push(const WrenchCommand& w, double timeout) {
    no_answer_in_callback("Client.push()");
    const auto patience = to_ms(timeout);
    const auto session = live();
    std::optional<AcceptedCommand> accepted;
    std::string refused;
    {
      py::gil_scoped_release nogil;
      accepted = session->push(w, patience, &refused);
    }
    if (accepted) return py::make_tuple(accepted_dict(*accepted), py::none());
    if (!refused.empty()) return py::make_tuple(py::none(), refused);
    return py::make_tuple(py::none(), py::none());
  }

  std::int64_t send(const WrenchCommand& w) {
    const auto session = live();
    py::gil_scoped_release nogil;
    return session->send(w);
  }

  py::object take_refusal() {
    const auto r = live()->take_refusal();
    return r ? py::object(py::str(r->message)) : py::none();
  }

  std::int64_t wrenches_refused() const { return live()->wrenches_refused(); }

 private:
  // How long a call may wait for the bus: inside an on_state callback not at all (the answer
  // would have to come through the very thread that runs the callback), so it takes what the
  // session already has.
  std::chrono::milliseconds wait_for(double timeout) const {
    const auto ms = to_ms(timeout);
    return delivery_->in_callback() ? std::chrono::milliseconds(0) : ms;
  }
  void nothing_yet_in_callback(const std::string& call, const std::string& what) const {
    if (!delivery_->in_callback()) return;
    raise(py::reinterpret_borrow<py::object>(PyExc_RuntimeError),
          call + " inside an on_state callback: no " + what +
              " has arrived yet, and waiting here would block the thread that receives it");
  }
  void no_answer_in_callback(const std::string& call) const {
    if (!delivery_->in_callback()) return;
    raise(py::reinterpret_borrow<py::object>(PyExc_RuntimeError),
          call +
              " inside an on_state callback would wait for rigidd's answer, which this "
              "thread has to receive: use send() there (refusals: take_refusal())");
  }

  // A reference for the call: close() from another thread cannot free the session under it.
  std::shared_ptr<sdk::Session> live() const {
    if (!session_) {
      raise(py::reinterpret_borrow<py::object>(PyExc_RuntimeError), "the client is closed");
    }
    return session_;
  }

  std::shared_ptr<StateDelivery> delivery_;
  std::shared_ptr<ContactCallbacks> contacts_;
  std::shared_ptr<sdk::Session> session_;
  std::string describe_;
};

}  // namespace

void bind_client(py::module_& m) {
  py::class_<WrenchCommand>(m, "_Wrench");

  py::class_<PySession>(m, "_Session", "The C++ rigid::client::Session (use rigid.Client).")
      .def(py::init<const std::string&, const std::string&, std::uint32_t,
                    const std::optional<std::string>&, const std::optional<std::string>&>(),
           py::arg("transport"), py::arg("prefix"), py::arg("domain"), py::arg("url"),
           py::arg("security"))
      .def("close", &PySession::close)
      .def_property_readonly("describe", &PySession::describe)
      .def_property_readonly("source", &PySession::source)
      .def("scene", &PySession::scene, py::arg("timeout"))
      .def("scene_generation", &PySession::scene_generation)
      .def("stats", &PySession::stats, py::arg("timeout"))
      .def("wait_server", &PySession::wait_server, py::arg("timeout"))
      .def("latest", &PySession::latest)
      .def("states", &PySession::states, py::arg("timeout"), py::arg("max_queue"))
      .def("on_state", &PySession::on_state, py::arg("fn"))
      .def("on_contact", &PySession::on_contact, py::arg("fn"))
      .def("request", &PySession::request, py::arg("kind"), py::arg("steps"), py::arg("rtf"),
           py::arg("timeout"))
      .def("edit", &PySession::edit, py::arg("kind"), py::arg("body"), py::arg("position"),
           py::arg("orientation"), py::arg("velocity"), py::arg("velocity_frame"),
           py::arg("angular_velocity"), py::arg("angular_velocity_frame"), py::arg("timeout"))
      .def("resolve", &PySession::resolve, py::arg("body"), py::arg("timeout"))
      .def("wrench", &PySession::wrench, py::arg("body"), py::arg("force"), py::arg("at"),
           py::arg("frame"), py::arg("torque"), py::arg("torque_frame"), py::arg("ttl"))
      .def("push", &PySession::push, py::arg("wrench"), py::arg("timeout"))
      .def("send", &PySession::send, py::arg("wrench"))
      .def("take_refusal", &PySession::take_refusal)
      .def_property_readonly("wrenches_refused", &PySession::wrenches_refused);
}

}  // namespace rigid::python
