// Scene loading: text -> rigid.msgs.Scene (with field positions) -> validated physics::WorldSpec.
#include "scene/scene.hpp"

#include <google/protobuf/io/tokenizer.h>
#include <google/protobuf/io/zero_copy_stream_impl_lite.h>
#include <google/protobuf/text_format.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>

#include "physics/inertia.hpp"
#include "physics/integrator.hpp"
#include "physics/world.hpp"
#include "rigid.pb.h"
#include "rigid/messages.hpp"
#include "scene/text_location.hpp"

namespace rigid::scene {

SceneError::SceneError(std::string file, int line, int column, std::string message)
    : std::runtime_error(line > 0 ? file + ":" + std::to_string(line) + ":" +
                                        std::to_string(column) + ": " + message
                                  : file + ": " + message),
      file_(std::move(file)),
      line_(line),
      column_(column),
      message_(std::move(message)) {}

namespace {

namespace pb = google::protobuf;
using physics::Vec3;

// Shortest text that reads back to the same double: messages show exactly the value in the file.
std::string num(double x) {
  std::array<char, 32> buf{};
  const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), x);
  return std::string(buf.data(), r.ptr);
}

std::string pos_text(TextPos p) {
  return std::to_string(p.line) + ":" + std::to_string(p.column);
}

Vec3 vec(const msgs::Vector3& v) {
  return Vec3(v.x(), v.y(), v.z());
}

std::array<bool, 3> axes(const msgs::Axes& a) {
  return {a.x(), a.y(), a.z()};
}

physics::Frame frame(msgs::Force::Frame f) {
  return f == msgs::Force::BODY ? physics::Frame::kBody : physics::Frame::kWorld;
}

// A name as it can be shown in a one-line message: bytes outside printable ASCII as \xHH.
std::string printable(std::string_view name) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  for (const char c : name) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u < 0x7f && c != '\\') {
      out += c;
    } else {
      out += "\\x";
      out += kHex[u >> 4];
      out += kHex[u & 0xf];
    }
  }
  return out;
}

bool valid_name_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
         c == '.' || c == '/' || c == '-';
}

// Keeps the parser's first error (later ones are usually consequences of it) and its warnings.
class CollectErrors : public pb::io::ErrorCollector {
 public:
  void AddError(int line, pb::io::ColumnNumber column, const std::string& message) override {
    if (!error_) error_ = Entry{TextPos{line + 1, column + 1}, message};
  }
  void AddWarning(int line, pb::io::ColumnNumber column, const std::string& message) override {
    warnings_.push_back(Entry{TextPos{line + 1, column + 1}, message});
  }

  struct Entry {
    TextPos pos;
    std::string message;
  };
  const std::optional<Entry>& error() const { return error_; }
  const std::vector<Entry>& warnings() const { return warnings_; }

 private:
  std::optional<Entry> error_;
  std::vector<Entry> warnings_;
};

// Turns a parsed scene into a Scene, checking everything and pointing at the text for each problem.
class Loader {
 public:
  // tree: where the parser saw each field, or null: every message then points at 1:1 (see
  // parse_scene, which loads again with the tree when there is something to say).
  Loader(std::string_view name, const msgs::Scene& msg, const TextNode::Tree* tree)
      : msg_(msg), root_(msgs::Scene::descriptor(), tree) {
    scene_.path = std::string(name);
  }

  Scene load() {
    check_all_finite();
    load_world();
    load_bodies();
    load_forces();
    load_statics();
    check_physics();
    return std::move(scene_);
  }

 private:
  [[noreturn]] void fail(TextPos p, const std::string& message) const {
    throw SceneError(scene_.path, p.line, p.column, message);
  }
  void warn(TextPos p, const std::string& message) {
    scene_.warnings.push_back(scene_.path + ":" + pos_text(p) + ": warning: " + message);
  }

  TextNode world_node() const { return root_.child("world"); }
  TextNode body_node(int i) const { return root_.child("body", i); }
  TextNode force_node(int i) const { return root_.child("force", i); }
  TextNode plane_node(int i) const { return root_.child("plane", i); }
  TextNode static_node(int i) const { return root_.child("static", i); }

  std::string body_label(int i) const {
    const std::string& name = msg_.body(i).name();
    return name.empty() ? "body #" + std::to_string(i + 1) : "body '" + printable(name) + "'";
  }
  std::string force_label(int i) const { return "force #" + std::to_string(i + 1); }
  std::string part_label(const char* kind, const std::string& name, int i) const {
    return name.empty() ? std::string(kind) + " #" + std::to_string(i + 1)
                        : std::string(kind) + " '" + printable(name) + "'";
  }

  // Every double anywhere in the scene must be finite (the text format accepts inf and nan).
  void check_all_finite() {
    check_finite(msg_.world(), world_node(), "world", "");
    for (int i = 0; i < msg_.body_size(); ++i) {
      check_finite(msg_.body(i), body_node(i), body_label(i), "");
    }
    for (int i = 0; i < msg_.force_size(); ++i) {
      check_finite(msg_.force(i), force_node(i), force_label(i), "");
    }
    for (int i = 0; i < msg_.plane_size(); ++i) {
      check_finite(msg_.plane(i), plane_node(i), part_label("plane", msg_.plane(i).name(), i), "");
    }
    for (int i = 0; i < msg_.static__size(); ++i) {
      check_finite(msg_.static_(i), static_node(i), part_label("static", msg_.static_(i).name(), i),
                   "");
    }
  }

  // A material's values over `base` (the world's, for a body or a part); each given value checked.
  physics::Surface load_material(const msgs::Material& m, const TextNode& node,
                                 const std::string& label, physics::Surface base) {
    if (m.has_restitution()) {
      if (!(m.restitution() >= 0.0 && m.restitution() <= 1.0)) {
        fail(node.at("restitution"),
             label + ": material.restitution must be in [0, 1], got " + num(m.restitution()));
      }
      base.restitution = m.restitution();
    }
    if (m.has_friction()) {
      if (!(m.friction() >= 0.0)) {
        fail(node.at("friction"),
             label + ": material.friction must be >= 0, got " + num(m.friction()));
      }
      base.friction = m.friction();
    }
    return base;
  }

  // A static part's name: like a body's, and unique among the parts and the bodies (it names a
  // frame beside theirs on the buses).
  void check_part_name(const std::string& name, const TextNode& node, const std::string& label) {
    if (name.empty()) fail(node.at("name"), label + ": name must not be empty");
    if (name.size() > kMaxBodyNameLength) {
      fail(node.at("name"), label + ": name is " + std::to_string(name.size()) +
                                " characters long; at most " + std::to_string(kMaxBodyNameLength));
    }
    if (!std::all_of(name.begin(), name.end(), valid_name_char)) {
      fail(node.at("name"), label + ": name may contain only letters, digits and _ . / -, got '" +
                                printable(name) + "'");
    }
    if (const auto b = body_index_.find(name); b != body_index_.end()) {
      fail(node.at("name"), label + ": name is already a body's (defined at " +
                                pos_text(body_node(b->second).at("name")) + ")");
    }
    const auto [it, inserted] = part_names_.emplace(name, node.at("name"));
    if (!inserted) {
      fail(node.at("name"), "duplicate static part name '" + name + "' (first defined at " +
                                pos_text(it->second) + ")");
    }
  }

  void load_statics() {
    const physics::Surface world = scene_.world_surface;
    for (int i = 0; i < msg_.plane_size(); ++i) {
      const msgs::Plane& p = msg_.plane(i);
      const TextNode node = plane_node(i);
      const std::string label = part_label("plane", p.name(), i);
      check_part_name(p.name(), node, label);
      physics::PlaneSpec s;
      s.name = p.name();
      const Vec3 n = vec(p.normal());
      const double len = n.stableNorm();
      if (!(len > 0.0) || !std::isfinite(len)) {
        fail(p.has_normal() ? node.at("normal") : node.pos(),
             label + ": normal (" + num(n.x()) + ", " + num(n.y()) + ", " + num(n.z()) +
                 ") must be a non-zero vector");
      }
      if (std::abs(len - 1.0) > 1e-9) {
        warn(node.at("normal"), label + ": normal has length " + num(len) +
                                    "; normalised (offset is along the unit normal)");
      }
      s.n_W = n / len;
      s.offset = p.offset();
      s.surface = load_material(p.material(), node.child("material"), label, world);
      scene_.world.planes.push_back(s);
    }
    for (int i = 0; i < msg_.static__size(); ++i) {
      const msgs::Static& p = msg_.static_(i);
      const TextNode node = static_node(i);
      const std::string label = part_label("static", p.name(), i);
      check_part_name(p.name(), node, label);
      physics::StaticSpec s;
      s.name = p.name();
      if (!p.has_shape()) fail(node.pos(), label + ": needs a shape");
      s.shape = load_shape(p.shape(), node.child("shape"), label);
      if (s.shape.kind == physics::ShapeKind::kEllipsoid) {
        fail(node.child("shape").at("ellipsoid"),
             label + ": a static shape is a box, sphere, capsule or cylinder");
      }
      if (p.has_position()) s.p_WS = vec(p.position());
      if (p.has_orientation()) s.q_WS = load_orientation(p.orientation(), node, label);
      s.surface = load_material(p.material(), node.child("material"), label, world);
      scene_.world.statics.push_back(s);
    }
  }

  void check_finite(const pb::Message& m, const TextNode& node, const std::string& context,
                    const std::string& prefix) {
    const pb::Reflection* r = m.GetReflection();
    std::vector<const pb::FieldDescriptor*> fields;
    r->ListFields(m, &fields);
    for (const pb::FieldDescriptor* f : fields) {
      const int n = f->is_repeated() ? r->FieldSize(m, f) : 1;
      for (int i = 0; i < n; ++i) {
        const std::string name =
            prefix + f->name() + (f->is_repeated() ? "[" + std::to_string(i) + "]" : "");
        if (f->cpp_type() == pb::FieldDescriptor::CPPTYPE_DOUBLE) {
          const double v = f->is_repeated() ? r->GetRepeatedDouble(m, f, i) : r->GetDouble(m, f);
          if (!std::isfinite(v)) {
            fail(node.at(f, i), context + ": " + name + " must be finite, got " + num(v));
          }
        } else if (f->cpp_type() == pb::FieldDescriptor::CPPTYPE_MESSAGE) {
          const pb::Message& sub =
              f->is_repeated() ? r->GetRepeatedMessage(m, f, i) : r->GetMessage(m, f);
          check_finite(sub, node.child(f, i), context, name + ".");
        }
      }
    }
  }

  void load_world() {
    const msgs::World& w = msg_.world();
    const TextNode node = world_node();
    if (w.has_rate_hz()) {
      if (!(w.rate_hz() > 0.0 && w.rate_hz() <= 1e6)) {
        fail(node.at("rate_hz"), "world: rate_hz must be in (0, 1e6], got " + num(w.rate_hz()));
      }
      scene_.rate_hz = w.rate_hz();
    }
    if (w.has_substeps()) {
      if (w.substeps() < 1 || w.substeps() > 10000) {
        fail(node.at("substeps"),
             "world: substeps must be in [1, 10000], got " + std::to_string(w.substeps()));
      }
      scene_.substeps = w.substeps();
    }
    if (w.has_publish_every()) {
      if (w.publish_every() < 1) {
        fail(node.at("publish_every"),
             "world: publish_every must be >= 1, got " + std::to_string(w.publish_every()));
      }
      scene_.publish_every = w.publish_every();
    }
    scene_.world.dt = 1.0 / (scene_.rate_hz * scene_.substeps);
    scene_.world_surface =
        load_material(w.material(), node.child("material"), "world", physics::Surface{});
    if (w.has_gravity()) scene_.world.g_W = vec(w.gravity());
    if (!w.integrator().empty() && physics::find_integrator(w.integrator()) == nullptr) {
      std::string names;
      for (const physics::IntegratorInfo& info : physics::all_integrators()) {
        names += (names.empty() ? "" : ", ") + std::string(info.name);
      }
      fail(node.at("integrator"),
           "world: unknown integrator '" + printable(w.integrator()) + "' (valid: " + names + ")");
    }
    scene_.world.integrator = w.integrator();
    if (w.has_threads()) {
      if (w.threads() < 0 || w.threads() > 256) {
        fail(node.at("threads"),
             "world: threads must be 0 (every core) .. 256, got " + std::to_string(w.threads()));
      }
      scene_.world.threads = w.threads();
      scene_.threads_given = true;
    }

    const msgs::Limits& l = w.limits();
    const TextNode lnode = node.child("limits");
    const auto limit = [&](bool has, double value, const char* field, double& out) {
      if (!has) return;
      if (!(value > 0.0)) {
        fail(lnode.at(field),
             std::string("world: limits.") + field + " must be > 0, got " + num(value));
      }
      out = value;
    };
    limit(l.has_max_force(), l.max_force(), "max_force", scene_.limits.max_force);
    limit(l.has_max_torque(), l.max_torque(), "max_torque", scene_.limits.max_torque);
    limit(l.has_max_ttl(), l.max_ttl(), "max_ttl", scene_.limits.max_ttl);
    limit(l.has_max_commands_per_second(), l.max_commands_per_second(), "max_commands_per_second",
          scene_.limits.max_commands_per_second);
    if (l.has_max_wrenches_per_source()) {
      if (l.max_wrenches_per_source() <= 0) {
        fail(lnode.at("max_wrenches_per_source"),
             "world: limits.max_wrenches_per_source must be > 0, got " +
                 std::to_string(l.max_wrenches_per_source()));
      }
      scene_.limits.max_wrenches_per_source = l.max_wrenches_per_source();
    }
  }

  void load_bodies() {
    std::map<std::string, int, std::less<>>& first = body_index_;  // name -> body index
    for (int i = 0; i < msg_.body_size(); ++i) {
      const std::string& name = msg_.body(i).name();
      const TextNode node = body_node(i);
      if (name.empty()) fail(node.at("name"), body_label(i) + ": name must not be empty");
      if (name.size() > kMaxBodyNameLength) {
        fail(node.at("name"), body_label(i) + ": name is " + std::to_string(name.size()) +
                                  " characters long; at most " +
                                  std::to_string(kMaxBodyNameLength) + " travel on the buses");
      }
      if (!std::all_of(name.begin(), name.end(), valid_name_char)) {
        fail(node.at("name"), body_label(i) +
                                  ": name may contain only letters, digits and _ . / -, got '" +
                                  printable(name) + "'");
      }
      const auto [it, inserted] = first.emplace(name, i);
      if (!inserted) {
        fail(node.at("name"), "duplicate body name '" + name + "' (first defined at " +
                                  pos_text(body_node(it->second).at("name")) + ")");
      }
      scene_.world.bodies.push_back(load_body(i));
      scene_.shapes.push_back(scene_.world.bodies.back().shape);
    }
    if (msg_.body_size() == 0) warn(TextPos{1, 1}, "the scene has no bodies");
  }

  physics::BodySpec load_body(int i) {
    const msgs::Body& b = msg_.body(i);
    const TextNode node = body_node(i);
    const std::string label = body_label(i);
    physics::BodySpec s;
    s.name = b.name();

    if (b.has_mass() && b.has_density()) {
      fail(node.at("density"), label + ": give mass or density, not both (mass " + num(b.mass()) +
                                   ", density " + num(b.density()) + ")");
    }
    std::optional<physics::Shape> shape;
    if (b.has_shape()) shape = load_shape(b.shape(), node.child("shape"), label);
    if (b.has_density()) {
      if (!shape) {
        fail(node.at("density"), label + ": density " + num(b.density()) +
                                     " needs a shape to give a volume; give mass instead");
      }
      if (!(b.density() > 0.0)) {
        fail(node.at("density"), label + ": density must be > 0, got " + num(b.density()));
      }
      const double volume = physics::shape_volume(*shape);
      s.mass = b.density() * volume;
      if (!std::isfinite(s.mass) || s.mass == 0.0) {
        fail(node.at("density"), label + ": mass = density * volume = " + num(b.density()) + " * " +
                                     num(volume) + " = " + num(s.mass) + " is not a usable mass");
      }
    } else if (b.has_mass()) {
      s.mass = b.mass();  // > 0 is checked by physics::World
    } else if (!b.kinematic()) {
      fail(node.pos(), label + ": needs a mass (or a shape and a density)");
    }

    switch (b.inertia_source_case()) {
      case msgs::Body::kInertia:
        s.I_B = vec(b.inertia()).asDiagonal();
        break;
      case msgs::Body::kInertiaTensor: {
        const msgs::InertiaTensor& t = b.inertia_tensor();
        s.I_B << t.xx(), t.xy(), t.xz(), t.xy(), t.yy(), t.yz(), t.xz(), t.yz(), t.zz();
        break;
      }
      case msgs::Body::kShape:
        // With a bad mass the tensor would be meaningless; World then reports the mass.
        if (s.mass > 0.0) s.I_B = physics::shape_inertia(*shape, s.mass);
        break;
      case msgs::Body::INERTIA_SOURCE_NOT_SET:
        s.has_inertia = false;
        break;
    }

    if (b.has_position()) s.p_WBo = vec(b.position());
    if (b.has_orientation()) s.q_WB = load_orientation(b.orientation(), node, label);
    if (b.has_velocity()) s.v_WBo = vec(b.velocity());
    if (b.has_angular_velocity()) s.w_WB = vec(b.angular_velocity());
    s.linear_drag = b.linear_drag();
    s.angular_drag = b.angular_drag();
    s.use_gravity = b.has_use_gravity() ? b.use_gravity() : true;
    s.kinematic = b.kinematic();
    s.freeze_translation = axes(b.freeze_translation());
    s.freeze_rotation = axes(b.freeze_rotation());
    s.shape = shape;
    s.surface = load_material(b.material(), node.child("material"), label, scene_.world_surface);
    if (b.collision().has_group()) s.collision_group = b.collision().group();
    if (b.collision().has_mask()) s.collision_mask = b.collision().mask();
    return s;
  }

  physics::Shape load_shape(const msgs::Shape& m, const TextNode& node, const std::string& label) {
    physics::Shape s;
    // Each size must be > 0; a missing one reads as 0 and points at its enclosing block.
    const auto positive = [&](const TextNode& n, const char* field, double v,
                              const std::string& path) {
      if (!(v > 0.0)) {
        fail(n.at(field), label + ": shape." + path + "." + field + " must be > 0, got " + num(v));
      }
    };
    const auto box_like = [&](const msgs::Vector3& v, const char* kind) {
      const TextNode n = node.child(kind);
      positive(n, "x", v.x(), kind);
      positive(n, "y", v.y(), kind);
      positive(n, "z", v.z(), kind);
      return vec(v);
    };
    switch (m.kind_case()) {
      case msgs::Shape::kBox:
        s.kind = physics::ShapeKind::kBox;
        s.size = box_like(m.box(), "box");
        break;
      case msgs::Shape::kEllipsoid:
        s.kind = physics::ShapeKind::kEllipsoid;
        s.size = box_like(m.ellipsoid(), "ellipsoid");
        break;
      case msgs::Shape::kSphere:
        s.kind = physics::ShapeKind::kSphere;
        positive(node.child("sphere"), "radius", m.sphere().radius(), "sphere");
        s.size = Vec3(m.sphere().radius(), 0.0, 0.0);
        break;
      case msgs::Shape::kCylinder:
        s.kind = physics::ShapeKind::kCylinder;
        positive(node.child("cylinder"), "radius", m.cylinder().radius(), "cylinder");
        positive(node.child("cylinder"), "length", m.cylinder().length(), "cylinder");
        s.size = Vec3(m.cylinder().radius(), 0.0, m.cylinder().length());
        break;
      case msgs::Shape::kCapsule:
        s.kind = physics::ShapeKind::kCapsule;
        positive(node.child("capsule"), "radius", m.capsule().radius(), "capsule");
        positive(node.child("capsule"), "length", m.capsule().length(), "capsule");
        s.size = Vec3(m.capsule().radius(), 0.0, m.capsule().length());
        break;
      case msgs::Shape::KIND_NOT_SET:
        fail(node.pos(),
             label + ": shape is empty; give one of box, sphere, cylinder, capsule, ellipsoid");
    }
    return s;
  }

  physics::Quat load_orientation(const msgs::Quaternion& m, const TextNode& body,
                                 const std::string& label) {
    const physics::Quat q(m.w(), m.x(), m.y(), m.z());
    const std::string text =
        "(" + num(m.w()) + ", " + num(m.x()) + ", " + num(m.y()) + ", " + num(m.z()) + ")";
    // stableNorm: components near 1e200 are finite and normalisable, but their squares are not.
    const double n = q.coeffs().stableNorm();
    if (!(n > 0.0) || !std::isfinite(n)) {
      fail(body.at("orientation"),
           label + ": orientation " + text + " has norm " + num(n) + " and cannot be normalised");
    }
    if (std::abs(n - 1.0) > 1e-9) {
      warn(body.at("orientation"), label + ": orientation " + text + " has norm " + num(n) +
                                       "; normalised to a unit quaternion");
    }
    return physics::Quat(q.coeffs() / n);
  }

  void load_forces() {
    for (int i = 0; i < msg_.force_size(); ++i) {
      const msgs::Force& f = msg_.force(i);
      const TextNode node = force_node(i);
      const std::string label = force_label(i);
      // By name, from the index load_bodies built (names are unique): a scan of every body per
      // force made a scene of 10^5 bodies and 3 x 10^4 forces take 44 s to load.
      const auto found = body_index_.find(f.body());
      const int body = found == body_index_.end() ? -1 : found->second;
      if (f.body().empty()) fail(node.at("body"), label + ": body must name the body it acts on");
      if (body < 0) fail(node.at("body"), label + ": no body named '" + printable(f.body()) + "'");
      // proto3 enums are open: the parser accepts any number for them.
      if (!msgs::Force::Frame_IsValid(f.frame())) {
        fail(node.at("frame"),
             label + ": frame must be WORLD or BODY, got " + std::to_string(f.frame()));
      }
      if (!msgs::Force::Frame_IsValid(f.torque_frame())) {
        fail(node.at("torque_frame"), label + ": torque_frame must be WORLD or BODY, got " +
                                          std::to_string(f.torque_frame()));
      }

      physics::LoadSpec load;
      load.body = body;
      load.force = vec(f.force());
      load.p_BoQ_B = vec(f.point());
      load.frame = frame(f.frame());
      load.torque = vec(f.torque());
      load.torque_frame = frame(f.torque_frame());
      const physics::BodySpec& target = scene_.world.bodies[body];
      if (target.kinematic) {
        warn(node.pos(), label + ": body '" + f.body() + "' is kinematic and ignores forces");
      } else if (!target.has_inertia &&
                 (load.p_BoQ_B != Vec3::Zero() || load.torque != Vec3::Zero())) {
        warn(node.pos(), label + ": body '" + f.body() +
                             "' is a point mass (no inertia); the point and torque have no effect");
      }
      scene_.world.loads.push_back(load);
    }
  }

  // The World constructor does the physics-level checks (mass, inertia, drags, frozen axes, ...);
  // its SpecError names a body index and a field, which are mapped back to the text here.
  void check_physics() {
    try {
      const physics::World world(scene_.world);
    } catch (const physics::SpecError& e) {
      fail(locate(e), e.what());
    }
  }

  TextPos locate(const physics::SpecError& e) const {
    const std::string& field = e.field();
    // A load's errors also name its body; the load's own entry is the better place.
    if (e.load() >= 0 && e.load() < msg_.force_size()) return at_path(force_node(e.load()), field);
    if (e.body() >= 0 && e.body() < msg_.body_size()) {
      const msgs::Body& b = msg_.body(e.body());
      const TextNode node = body_node(e.body());
      if (field == "inertia" || field == "inertia_tensor" || field == "shape") {
        switch (b.inertia_source_case()) {
          case msgs::Body::kInertia:
            return node.at("inertia");
          case msgs::Body::kInertiaTensor:
            return node.at("inertia_tensor");
          case msgs::Body::kShape:
            return node.at("shape");
          case msgs::Body::INERTIA_SOURCE_NOT_SET:
            return node.pos();
        }
      }
      if (field == "mass" && b.has_density()) return node.at("density");
      return at_path(node, field);
    }
    // The world's fields; its time step comes from rate_hz and substeps.
    if (field == "dt") return world_node().at("rate_hz");
    return at_path(world_node(), field);
  }

  // The position of a dotted field path ("freeze_rotation.x") under node, or of the deepest part
  // of it that exists.
  static TextPos at_path(TextNode node, std::string_view path) {
    while (true) {
      const std::size_t dot = path.find('.');
      const std::string head(path.substr(0, dot));
      const pb::FieldDescriptor* f = node.type()->FindFieldByName(head);
      if (f == nullptr) return node.pos();
      if (dot == std::string_view::npos || f->message_type() == nullptr || f->is_repeated()) {
        return node.at(f);
      }
      node = node.child(f);
      path.remove_prefix(dot + 1);
    }
  }

  const msgs::Scene& msg_;
  TextNode root_;
  Scene scene_;
  std::map<std::string, int, std::less<>> body_index_;      // name -> body index (load_bodies)
  std::map<std::string, TextPos, std::less<>> part_names_;  // static parts' names (load_statics)
};

// The text into msg, with the parser's warnings in `errors` and, unless `tree` is null, where
// each field was written. Throws SceneError on a syntax error (the parser's own position).
void parse_text(std::string_view text, std::string_view name, msgs::Scene& msg,
                CollectErrors& errors, TextNode::Tree* tree) {
  pb::TextFormat::Parser parser;
  parser.RecordErrorsTo(&errors);
  if (tree != nullptr) parser.WriteLocationsTo(tree);
  // The tokenizer takes an int size.
  if (text.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    throw SceneError(std::string(name), 0, 0, "file too large for a scene");
  }
  pb::io::ArrayInputStream input(text.data(), static_cast<int>(text.size()));
  if (parser.Parse(&input, &msg)) return;
  if (errors.error()) {
    // The parser quotes the offending token, which may hold any byte (a line break, too).
    std::string message = printable(errors.error()->message);
    // At the end of the text the parser's "Expected X, got: " names no token.
    if (message.ends_with("got: ")) message += "the end of the file";
    throw SceneError(std::string(name), errors.error()->pos.line, errors.error()->pos.column,
                     message);
  }
  throw SceneError(std::string(name), 0, 0, "not a valid scene (text format)");
}

// The parser's warnings, one line each as Scene::warnings has them.
std::vector<std::string> parser_warnings(const CollectErrors& errors, std::string_view name) {
  std::vector<std::string> lines;
  for (const CollectErrors::Entry& w : errors.warnings()) {
    lines.push_back(std::string(name) + ":" + pos_text(w.pos) +
                    ": warning: " + printable(w.message));
  }
  return lines;
}

}  // namespace

// The parser can record where it saw every field (a ParseInfoTree), which the loader's errors and
// warnings point at; but the tree takes ~1.6 KB a body (a scene of 10^6 bodies: 1.6 GB while it
// loads, three times what the world it describes keeps). So the text is parsed and loaded without
// it first, and again with it only when the loader has something to say: it refuses the scene or
// warns. Both loads read the same message and decide the same, so the second says what the first
// would have, with positions.
Scene parse_scene(std::string_view text, std::string_view name) {
  {
    msgs::Scene msg;
    CollectErrors errors;
    parse_text(text, name, msg, errors, nullptr);
    try {
      Scene scene = Loader(name, msg, nullptr).load();
      if (scene.warnings.empty()) {
        scene.warnings = parser_warnings(errors, name);
        return scene;
      }
    } catch (const SceneError&) {
      // Said below, with its position.
    }
  }
  msgs::Scene msg;
  CollectErrors errors;
  TextNode::Tree tree;
  parse_text(text, name, msg, errors, &tree);
  Scene scene = Loader(name, msg, &tree).load();
  const std::vector<std::string> warnings = parser_warnings(errors, name);
  scene.warnings.insert(scene.warnings.begin(), warnings.begin(), warnings.end());
  return scene;
}

Scene load_scene(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw SceneError(path, 0, 0, "is a directory, not a scene file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path, 0, 0, std::string("cannot open: ") + std::strerror(errno));
  // Read into one string sized by the file (a stream's buffer and its copy held the text of a
  // large scene twice at once).
  std::string text;
  const auto size = std::filesystem::file_size(path, ec);
  if (!ec && size > static_cast<std::uintmax_t>(std::numeric_limits<int>::max())) {
    throw SceneError(path, 0, 0, "file too large for a scene");
  }
  if (!ec) text.reserve(static_cast<std::size_t>(size));
  std::array<char, 1 << 16> chunk;
  while (in.read(chunk.data(), chunk.size()) || in.gcount() > 0) {
    text.append(chunk.data(), static_cast<std::size_t>(in.gcount()));
    // What the tokenizer could never take is not read on (a device or a pipe may never end).
    if (text.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
      throw SceneError(path, 0, 0, "file too large for a scene");
    }
  }
  if (in.bad()) throw SceneError(path, 0, 0, std::string("cannot read: ") + std::strerror(errno));
  return parse_scene(text, path);
}

}  // namespace rigid::scene
