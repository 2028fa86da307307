#include "states.hpp"

#include <algorithm>
#include <chrono>
#include <utility>

#include "bindings.hpp"

namespace rigid::python {
namespace {

using std::chrono::milliseconds;

py::array int_view(const std::int32_t* data, py::ssize_t n, const py::object& owner) {
  py::array a(py::dtype::of<std::int32_t>(), {n}, {static_cast<py::ssize_t>(sizeof(std::int32_t))},
              data, owner);
  a.attr("flags").attr("writeable") = false;
  return a;
}

}  // namespace

bool finalizing() {
#if PY_VERSION_HEX >= 0x030D0000
  return Py_IsFinalizing() != 0;
#else
  return _Py_IsFinalizing() != 0;
#endif
}

PyState::PyState(std::shared_ptr<const StateFrame> frame) : frame_(std::move(frame)) {
  auto* keep = new std::shared_ptr<const StateFrame>(frame_);
  owner_ =
      py::capsule(keep, [](void* p) { delete static_cast<std::shared_ptr<const StateFrame>*>(p); });
}
py::array PyState::ids() const {
  return int_view(frame_->ids.data(), n(), owner_);
}
py::array PyState::positions() const {
  return readonly_view(frame_->position.data(), n(), 3, owner_);
}
py::array PyState::orientations() const {
  return readonly_view(frame_->orientation.data(), n(), 4, owner_);
}
py::array PyState::velocities() const {
  return readonly_view(frame_->linear_velocity.data(), n(), 3, owner_);
}
py::array PyState::angular_velocities() const {
  return readonly_view(frame_->angular_velocity.data(), n(), 3, owner_);
}
std::string PyState::repr() const {
  return "<rigid.State tick " + std::to_string(frame_->tick) + ", t=" + num(frame_->sim_time) +
         ", " + std::to_string(frame_->body_count()) + " bodies>";
}

StateCallback::~StateCallback() {
  // The last reference may go on a thread without the GIL (a session closing); the Python
  // objects it holds need it to be released.
  if (finalizing()) {
    (void)fn.release();  // leaked rather than touched: the interpreter is going away
    (void)error.release();
    return;
  }
  const py::gil_scoped_acquire gil;
  fn = py::function();
  error = py::object();
}

void StateDelivery::deliver(const std::shared_ptr<const StateFrame>& state) {
  {
    const std::lock_guard lock(queues_mutex_);
    for (const auto& q : queues_) {
      {
        const std::lock_guard ql(q->mutex);
        if (q->frames.size() >= q->capacity) {
          q->frames.pop_front();
          ++q->dropped;
        }
        q->frames.push_back(state);
      }
      q->changed.notify_all();
    }
  }
  if (any_callback_.load()) run_callbacks(state);
}

void StateDelivery::run_callbacks(const std::shared_ptr<const StateFrame>& state) {
  const std::lock_guard lock(callbacks_mutex_);
  if (callbacks_.empty() || finalizing()) return;
  delivering_.store(std::this_thread::get_id());
  {
    const py::gil_scoped_acquire gil;
    const py::object s = py::cast(PyState(state));
    for (const auto& c : callbacks_) {
      if (!c->active.load()) continue;
      try {
        c->fn(s);
        c->calls.fetch_add(1);
      } catch (py::error_already_set& e) {
        // As a thread ends on an uncaught exception: this callback stops, the others go on;
        // the exception is reported once (sys.unraisablehook) and kept on its handle.
        c->active.store(false);
        c->error = e.value();
        e.discard_as_unraisable("rigid.Client.on_state callback");
      }
    }
    // Handles closed from inside a callback, and callbacks that raised, leave the list here;
    // callbacks added from inside one join it (they get the next state).
    std::erase_if(callbacks_, [](const auto& c) { return !c->active.load(); });
    callbacks_.insert(callbacks_.end(), added_.begin(), added_.end());
    added_.clear();
    any_callback_.store(!callbacks_.empty());
  }
  delivering_.store(std::thread::id{});
}

void StateDelivery::add_queue(const std::shared_ptr<StateQueue>& q) {
  const std::lock_guard lock(queues_mutex_);
  queues_.push_back(q);
}

void StateDelivery::remove_queue(const std::shared_ptr<StateQueue>& q) {
  const std::lock_guard lock(queues_mutex_);
  std::erase(queues_, q);
}

void StateDelivery::add_callback(const std::shared_ptr<StateCallback>& c) {
  if (in_callback()) {  // this thread holds the lock and walks the list: joins it after the walk
    added_.push_back(c);
    return;
  }
  const py::gil_scoped_release nogil;  // the receive thread may hold the lock, waiting for the GIL
  const std::lock_guard lock(callbacks_mutex_);
  callbacks_.push_back(c);
  any_callback_.store(true);
}

void StateDelivery::remove_callback(const std::shared_ptr<StateCallback>& c) {
  c->active.store(false);
  if (in_callback()) return;  // this thread holds the lock: the running delivery drops it
  const py::gil_scoped_release nogil;
  const std::lock_guard lock(callbacks_mutex_);  // waits for a delivery in progress
  std::erase(callbacks_, c);  // the caller still holds `c`: nothing Python is released here
  any_callback_.store(!callbacks_.empty());
}

void StateDelivery::end_callbacks() {
  std::vector<std::shared_ptr<StateCallback>> ended;
  {
    const py::gil_scoped_release nogil;
    const std::lock_guard lock(callbacks_mutex_);
    ended.swap(callbacks_);
    any_callback_.store(false);
  }
  for (const auto& c : ended)
    c->active.store(false);
}  // `ended` goes here, with the GIL

PyStateStream::PyStateStream(std::shared_ptr<StateDelivery> delivery, std::size_t capacity,
                             double timeout, std::string bus)
    : delivery_(std::move(delivery)), timeout_(timeout), bus_(std::move(bus)) {
  queue_ = std::make_shared<StateQueue>();
  queue_->capacity = std::max<std::size_t>(capacity, 1);
  delivery_->add_queue(queue_);
}

PyState PyStateStream::next() {
  if (delivery_->in_callback()) {
    raise(py::reinterpret_borrow<py::object>(PyExc_RuntimeError),
          "StateStream.__next__ inside an on_state callback would wait for the next state, "
          "which this thread has to receive: use the state the callback was given");
  }
  const auto deadline = std::chrono::steady_clock::now() + to_ms(timeout_);
  for (;;) {
    std::shared_ptr<const StateFrame> frame;
    bool closed = false;
    {
      const py::gil_scoped_release nogil;
      std::unique_lock lock(queue_->mutex);
      queue_->changed.wait_until(
          lock, std::min(deadline, std::chrono::steady_clock::now() + milliseconds(100)),
          [&] { return !queue_->frames.empty() || queue_->closed; });
      closed = queue_->closed;
      if (!queue_->frames.empty()) {
        frame = std::move(queue_->frames.front());
        queue_->frames.pop_front();
      }
    }
    if (frame) return PyState(std::move(frame));
    if (closed) throw py::stop_iteration();
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    if (std::chrono::steady_clock::now() >= deadline) {
      raise(py::reinterpret_borrow<py::object>(PyExc_TimeoutError),
            "no state from rigidd within " + num(timeout_) + " s on " + bus_ +
                " (is rigidd running, with the same transport, prefix and domain?)");
    }
  }
}

void PyStateStream::close() {
  if (!queue_) return;
  delivery_->remove_queue(queue_);
  {
    const std::lock_guard lock(queue_->mutex);
    queue_->closed = true;
    queue_->frames.clear();
  }
  queue_->changed.notify_all();
}

std::int64_t PyStateStream::dropped() const {
  const std::lock_guard lock(queue_->mutex);
  return queue_->dropped;
}

std::size_t PyStateStream::pending() const {
  const std::lock_guard lock(queue_->mutex);
  return queue_->frames.size();
}

void PyStateCallback::close() {
  if (const auto d = delivery_.lock()) {
    d->remove_callback(callback_);
  } else {
    callback_->active.store(false);  // its client is gone, and the deliveries with it
  }
}

void bind_states(py::module_& m) {
  py::class_<PyState>(m, "State", R"doc(One state rigidd published (immutable).

tick, time (simulated s), stamp_ns (rigidd's wall clock at publish, CLOCK_REALTIME ns), and per
body, in the order of ids: positions (N, 3), orientations (N, 4, w first), velocities (N, 3) and
angular_velocities (N, 3), all in the world frame; read-only NumPy views of the received message
(no copy beyond the one taken off the bus).)doc")
      .def_property_readonly("tick", [](const PyState& s) { return s.frame().tick; })
      .def_property_readonly("time", [](const PyState& s) { return s.frame().sim_time; })
      .def_property_readonly("stamp_ns", [](const PyState& s) { return s.frame().stamp_ns; })
      .def_property_readonly("ids", &PyState::ids, "(N,) int32 body ids, one per row.")
      .def_property_readonly("positions", &PyState::positions, "(N, 3) p_WBo (m).")
      .def_property_readonly("orientations", &PyState::orientations, "(N, 4) q_WB as (w, x, y, z).")
      .def_property_readonly("velocities", &PyState::velocities, "(N, 3) v_WBo in W (m/s).")
      .def_property_readonly("angular_velocities", &PyState::angular_velocities,
                             "(N, 3) w_WB in W (rad/s).")
      .def("__len__", [](const PyState& s) { return s.n(); })
      .def("__repr__", &PyState::repr);

  py::class_<PyStateStream>(m, "StateStream", R"doc(An iterator over the states rigidd publishes
from now on, in the order they arrive (Client.states()). next() waits up to `timeout` seconds with
the GIL released and raises TimeoutError after that; close() (or leaving a `with` block) ends it.
A reader slower than the bus loses the oldest queued states (counted in `dropped`).)doc")
      .def("__iter__", [](py::object self) { return self; })
      .def("__next__", &PyStateStream::next)
      .def("close", &PyStateStream::close)
      .def("__enter__", [](py::object self) { return self; })
      .def("__exit__", [](PyStateStream& s, const py::args&) { s.close(); })
      .def_property_readonly("dropped", &PyStateStream::dropped,
                             "States lost because this stream's queue was full.")
      .def_property_readonly("pending", &PyStateStream::pending, "States queued, not yet read.");

  py::class_<PyStateCallback>(m, "StateCallback", R"doc(A function called with each state as it
arrives (Client.on_state()). close() (or leaving a `with` block) ends it: once close() returns
from another thread, the function is not running and will not run again.)doc")
      .def("close", &PyStateCallback::close)
      .def("__enter__", [](py::object self) { return self; })
      .def("__exit__", [](PyStateCallback& c, const py::args&) { c.close(); })
      .def_property_readonly("active", &PyStateCallback::active,
                             "False once closed, its client closed, or after it raised.")
      .def_property_readonly("calls", &PyStateCallback::calls,
                             "How many times it returned normally.")
      .def_property_readonly("error", &PyStateCallback::error,
                             "The exception that ended it, or None.");
}

}  // namespace rigid::python
