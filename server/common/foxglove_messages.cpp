#include "common/foxglove_messages.hpp"

#include <google/protobuf/descriptor.pb.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <set>
#include <string_view>

#include "foxglove/SceneUpdate.pb.h"
#include "rigid/names.hpp"

namespace rigid::common::foxglove {
namespace {

// Protobuf wire format, for the messages written by hand. The field numbers are those of
// msgs/foxglove/FrameTransform.proto, Vector3.proto, Quaternion.proto and
// msgs/live/body_states.proto; the tests decode the results with the schemas.
char* put_varint(char* p, std::uint64_t v) {
  while (v >= 0x80) {
    *p++ = static_cast<char>(v | 0x80);
    v >>= 7;
  }
  *p++ = static_cast<char>(v);
  return p;
}
std::size_t varint_size(std::uint64_t v) {
  std::size_t n = 1;
  for (; v >= 0x80; v >>= 7)
    ++n;
  return n;
}
// A double field (wire type 1, 64-bit), written even when zero so that every bit is kept.
char* put_double(char* p, int field, double v) {
  *p++ = static_cast<char>(field << 3 | 1);
  std::memcpy(p, &v, 8);
  return p + 8;
}
char* put_bytes(char* p, int field, std::string_view v) {
  *p++ = static_cast<char>(field << 3 | 2);
  p = put_varint(p, v.size());
  std::memcpy(p, v.data(), v.size());
  return p + v.size();
}
// A Vector3 (x, y, z) or a Quaternion (x, y, z, w) as a length-delimited field: k tagged doubles.
char* put_doubles(char* p, int field, const double* v, int k) {
  *p++ = static_cast<char>(field << 3 | 2);
  *p++ = static_cast<char>(9 * k);
  for (int j = 0; j < k; ++j)
    p = put_double(p, j + 1, v[j]);
  return p;
}

// google.protobuf.Timestamp of a time in ns since the epoch.
std::string timestamp_bytes(std::uint64_t ns) {
  char buf[32];
  char* p = buf;
  *p++ = static_cast<char>(1 << 3 | 0);
  p = put_varint(p, ns / 1'000'000'000);
  *p++ = static_cast<char>(2 << 3 | 0);
  p = put_varint(p, ns % 1'000'000'000);
  return std::string(buf, p);
}

void set_timestamp(google::protobuf::Timestamp* t, std::uint64_t ns) {
  t->set_seconds(static_cast<std::int64_t>(ns / 1'000'000'000));
  t->set_nanos(static_cast<std::int32_t>(ns % 1'000'000'000));
}

// A colour per body, spread around the hue circle (golden-ratio steps) so neighbours differ.
void set_color(::foxglove::Color* c, std::size_t i) {
  const double h = std::fmod(0.13 + 0.6180339887498949 * static_cast<double>(i), 1.0) * 6.0;
  const double x = 1.0 - std::abs(std::fmod(h, 2.0) - 1.0);
  double rgb[3] = {0, 0, 0};
  const int sector = static_cast<int>(h);
  const int hi[6] = {0, 1, 1, 2, 2, 0};
  const int lo[6] = {1, 0, 2, 1, 0, 2};
  rgb[hi[sector % 6]] = 1.0;
  rgb[lo[sector % 6]] = x;
  c->set_r(0.25 + 0.7 * rgb[0]);
  c->set_g(0.25 + 0.7 * rgb[1]);
  c->set_b(0.25 + 0.7 * rgb[2]);
  c->set_a(0.9);
}

void set_pose(::foxglove::Pose* pose, const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
  pose->mutable_position()->set_x(p.x());
  pose->mutable_position()->set_y(p.y());
  pose->mutable_position()->set_z(p.z());
  pose->mutable_orientation()->set_x(q.x());
  pose->mutable_orientation()->set_y(q.y());
  pose->mutable_orientation()->set_z(q.z());
  pose->mutable_orientation()->set_w(q.w());
}

void set_size(::foxglove::Vector3* v, double x, double y, double z) {
  v->set_x(x);
  v->set_y(y);
  v->set_z(z);
}

// The primitives drawing body i of `scene`, in the body's frame (B, origin at the centre of mass).
void add_shape(const SceneDescription& scene, std::size_t i, ::foxglove::SceneEntity& e) {
  const double* d = &scene.shape_dims[3 * i];
  const Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  const Eigen::Quaterniond identity = Eigen::Quaterniond::Identity();
  const auto sphere = [&](const Eigen::Vector3d& at, double dx, double dy, double dz) {
    ::foxglove::SpherePrimitive* s = e.add_spheres();
    set_pose(s->mutable_pose(), at, identity);
    set_size(s->mutable_size(), dx, dy, dz);
    set_color(s->mutable_color(), i);
  };
  switch (scene.shape_kinds[i]) {
    case ShapeKind::kBox: {
      ::foxglove::CubePrimitive* c = e.add_cubes();
      set_pose(c->mutable_pose(), origin, identity);
      set_size(c->mutable_size(), d[0], d[1], d[2]);
      set_color(c->mutable_color(), i);
      return;
    }
    case ShapeKind::kSphere:
      sphere(origin, 2 * d[0], 2 * d[0], 2 * d[0]);
      return;
    case ShapeKind::kEllipsoid:  // Foxglove's sphere takes a diameter per axis
      sphere(origin, 2 * d[0], 2 * d[1], 2 * d[2]);
      return;
    case ShapeKind::kCylinder:
    case ShapeKind::kCapsule: {
      ::foxglove::CylinderPrimitive* c = e.add_cylinders();
      set_pose(c->mutable_pose(), origin, identity);
      set_size(c->mutable_size(), 2 * d[0], 2 * d[0], d[1]);
      c->set_bottom_scale(1.0);
      c->set_top_scale(1.0);
      set_color(c->mutable_color(), i);
      if (scene.shape_kinds[i] == ShapeKind::kCapsule) {  // and its two hemispherical caps
        sphere(Eigen::Vector3d(0, 0, d[1] / 2), 2 * d[0], 2 * d[0], 2 * d[0]);
        sphere(Eigen::Vector3d(0, 0, -d[1] / 2), 2 * d[0], 2 * d[0], 2 * d[0]);
      }
      return;
    }
    case ShapeKind::kPlane:  // static parts only: no body has it
    case ShapeKind::kNone:
      break;
  }
  // No shape: the uniform box with the body's principal moments, along its principal axes. A box
  // of mass m and edges a, b, c has moments m (b^2 + c^2) / 12, ..., so a^2 = 6 (I2 + I3 - I1) / m.
  const double* t = &scene.inertia[6 * i];  // Ixx, Iyy, Izz, Ixy, Ixz, Iyz
  Eigen::Matrix3d inertia;
  inertia << t[0], t[3], t[4], t[3], t[1], t[5], t[4], t[5], t[2];
  const double m = scene.masses[i];
  if (!(m > 0) || !(inertia.cwiseAbs().maxCoeff() > 0)) {
    // A point mass (no inertia): a small marker sphere.
    sphere(origin, 0.05, 0.05, 0.05);
    return;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(inertia);
  const Eigen::Vector3d I = eig.eigenvalues();
  Eigen::Matrix3d axes = eig.eigenvectors();
  if (axes.determinant() < 0) axes.col(2) = -axes.col(2);  // a rotation, not a reflection
  const auto edge = [&](int k) {
    const double s = 6.0 * (I.sum() - 2.0 * I[k]) / m;
    return std::sqrt(std::max(s, 1e-6));
  };
  ::foxglove::CubePrimitive* c = e.add_cubes();
  set_pose(c->mutable_pose(), origin, Eigen::Quaterniond(axes).normalized());
  set_size(c->mutable_size(), edge(0), edge(1), edge(2));
  set_color(c->mutable_color(), i);
}

}  // namespace

std::string descriptor_set(const google::protobuf::Descriptor* message) {
  google::protobuf::FileDescriptorSet set;
  std::set<std::string> added;
  const std::function<void(const google::protobuf::FileDescriptor*)> add =
      [&](const google::protobuf::FileDescriptor* file) {
        if (!added.insert(std::string(file->name())).second) return;
        for (int i = 0; i < file->dependency_count(); ++i)
          add(file->dependency(i));
        file->CopyTo(set.add_file());
      };
  add(message->file());
  return set.SerializeAsString();
}

std::string scene_update(const SceneDescription& scene, std::uint64_t time_ns, bool replace_all) {
  ::foxglove::SceneUpdate update;
  if (replace_all) {
    ::foxglove::SceneEntityDeletion* d = update.add_deletions();
    set_timestamp(d->mutable_timestamp(), time_ns);
    d->set_type(::foxglove::SceneEntityDeletion::ALL);
  }
  const std::size_t n = scene.lengths_agree() ? scene.body_count() : 0;
  for (std::size_t i = 0; i < n; ++i) {
    ::foxglove::SceneEntity* e = update.add_entities();
    set_timestamp(e->mutable_timestamp(), time_ns);
    e->set_frame_id(scene.names[i]);
    e->set_id(scene.names[i]);
    e->set_frame_locked(true);
    const auto meta = [e](std::string key, std::string value) {
      ::foxglove::KeyValuePair* kv = e->add_metadata();
      kv->set_key(std::move(key));
      kv->set_value(std::move(value));
    };
    meta("id", std::to_string(scene.ids[i]));
    meta("mass", std::to_string(scene.masses[i]));
    const std::string_view shape = rigid::shape_name(scene.shape_kinds[i]);
    meta("shape",
         shape.empty() ? "none (drawn as the box of its principal moments)" : std::string(shape));
    add_shape(scene, i, *e);
  }
  return update.SerializeAsString();
}

void append_frame_transforms(std::string& out, const std::vector<std::string>& frame_names,
                             const double* pos, const double* q, std::uint64_t time_ns) {
  const std::string stamp = timestamp_bytes(time_ns);
  constexpr std::string_view kWorld = "world";
  constexpr std::size_t kTranslation = 3 * 9;  // three tagged doubles
  constexpr std::size_t kRotation = 4 * 9;
  std::size_t bound = 0;
  for (const std::string& name : frame_names)
    bound += 2 * 10 + stamp.size() + kWorld.size() + name.size() + 3 * 2 + 2 * 10 + kTranslation +
             kRotation + 8;
  const std::size_t start = out.size();
  out.resize(start + bound);
  char* p = out.data() + start;
  for (std::size_t i = 0; i < frame_names.size(); ++i) {
    const std::string& name = frame_names[i];
    const std::size_t inner = 1 + varint_size(stamp.size()) + stamp.size() + 2 + kWorld.size() + 1 +
                              varint_size(name.size()) + name.size() + 2 + kTranslation + 2 +
                              kRotation;
    *p++ = static_cast<char>(1 << 3 | 2);  // FrameTransforms.transforms
    p = put_varint(p, inner);
    p = put_bytes(p, 1, stamp);             // timestamp
    p = put_bytes(p, 2, kWorld);            // parent_frame_id
    p = put_bytes(p, 3, name);              // child_frame_id
    p = put_doubles(p, 4, &pos[3 * i], 3);  // translation
    const double xyzw[4] = {q[4 * i + 1], q[4 * i + 2], q[4 * i + 3], q[4 * i]};
    p = put_doubles(p, 5, xyzw, 4);  // rotation
  }
  out.resize(static_cast<std::size_t>(p - out.data()));
}

void append_body_states(std::string& out, const StateFrame& s,
                        const std::vector<std::string>& names) {
  const std::size_t n = std::min(s.body_count(), names.size());
  const std::string stamp =
      timestamp_bytes(s.stamp_ns > 0 ? static_cast<std::uint64_t>(s.stamp_ns) : 0);
  constexpr std::size_t kVector = 2 + 3 * 9, kQuaternion = 2 + 4 * 9;
  std::size_t bound = 2 + stamp.size() + 1 + 10 + 9;
  for (std::size_t i = 0; i < n; ++i)
    bound += 1 + 10 + 1 + 10 + names[i].size() + 1 + 10 + 3 * kVector + kQuaternion;
  const std::size_t start = out.size();
  out.resize(start + bound);
  char* p = out.data() + start;
  p = put_bytes(p, 1, stamp);            // timestamp
  *p++ = static_cast<char>(2 << 3 | 0);  // tick (int64: two's complement as a varint)
  p = put_varint(p, static_cast<std::uint64_t>(s.tick));
  p = put_double(p, 3, s.sim_time);
  for (std::size_t i = 0; i < n; ++i) {
    const std::string& name = names[i];
    const auto id = static_cast<std::uint64_t>(static_cast<std::int64_t>(s.ids[i]));
    const std::size_t inner = 1 + varint_size(name.size()) + name.size() + 1 + varint_size(id) +
                              3 * kVector + kQuaternion;
    *p++ = static_cast<char>(4 << 3 | 2);  // BodyStates.bodies
    p = put_varint(p, inner);
    p = put_bytes(p, 1, name);
    *p++ = static_cast<char>(2 << 3 | 0);  // id (int32: sign-extended to 64 bits as a varint)
    p = put_varint(p, id);
    p = put_doubles(p, 3, &s.position[3 * i], 3);
    const double* q = &s.orientation[4 * i];
    const double xyzw[4] = {q[1], q[2], q[3], q[0]};
    p = put_doubles(p, 4, xyzw, 4);
    p = put_doubles(p, 5, &s.linear_velocity[3 * i], 3);
    p = put_doubles(p, 6, &s.angular_velocity[3 * i], 3);
  }
  out.resize(static_cast<std::size_t>(p - out.data()));
}

}  // namespace rigid::common::foxglove
