#include "transport/ros/markers.hpp"

#include <array>
#include <string_view>

#include "transport/ros/cdr.hpp"

namespace rigid::transport::ros {
namespace {

// visualization_msgs/Marker type constants.
constexpr std::int32_t kCube = 1;
constexpr std::int32_t kSphere = 2;
constexpr std::int32_t kCylinder = 3;
constexpr std::int32_t kAdd = 0;

// rigid-view's palette (clients/view/web/app.js), by the body's place in the scene.
constexpr std::array<std::uint32_t, 7> kPalette = {0x4fc3f7, 0xffb74d, 0x81c784, 0xe57373,
                                                   0xba68c8, 0xfff176, 0x90a4ae};
// Static parts: a neutral grey, apart from the bodies' colours.
constexpr std::uint32_t kStaticColour = 0x9e9e9e;

struct Shape {
  std::int32_t type;
  Vec3 scale;
  double z = 0.0;  // the marker's offset along the body's z
};

void marker(CdrWriter& w, std::string_view frame, std::string_view ns, std::int32_t id,
            const Shape& s, std::uint32_t rgb) {
  // header: stamp zero (tf2's "latest"), frame_id
  w.i32(0);
  w.u32(0);
  w.string(frame);
  w.string(ns);
  w.i32(id);
  w.i32(s.type);
  w.i32(kAdd);
  // pose: position, orientation (x, y, z, w)
  w.f64(0.0);
  w.f64(0.0);
  w.f64(s.z);
  w.f64(0.0);
  w.f64(0.0);
  w.f64(0.0);
  w.f64(1.0);
  for (const double v : s.scale)
    w.f64(v);
  // color: std_msgs/ColorRGBA (float32 r, g, b, a)
  w.f32(static_cast<float>((rgb >> 16) & 0xff) / 255.0f);
  w.f32(static_cast<float>((rgb >> 8) & 0xff) / 255.0f);
  w.f32(static_cast<float>(rgb & 0xff) / 255.0f);
  w.f32(1.0f);
  // lifetime: builtin_interfaces/Duration, zero: forever
  w.i32(0);
  w.u32(0);
  w.boolean(true);  // frame_locked
  w.count(0);       // points
  w.count(0);       // colors
  w.string("");     // texture_resource
  // texture: sensor_msgs/CompressedImage (header, format, data)
  w.i32(0);
  w.u32(0);
  w.string("");
  w.string("");
  w.count(0);
  w.count(0);        // uv_coordinates
  w.string("");      // text
  w.string("");      // mesh_resource
  w.string("");      // mesh_file.filename
  w.count(0);        // mesh_file.data
  w.boolean(false);  // mesh_use_embedded_materials
}

Shape shape_of(ShapeKind kind, const double* d) {
  switch (kind) {
    case ShapeKind::kSphere:
      return {kSphere, {2 * d[0], 2 * d[0], 2 * d[0]}};
    case ShapeKind::kEllipsoid:
      return {kSphere, {2 * d[0], 2 * d[1], 2 * d[2]}};
    case ShapeKind::kBox:
      return {kCube, {d[0], d[1], d[2]}};
    case ShapeKind::kCylinder:
    case ShapeKind::kCapsule:
      return {kCylinder, {2 * d[0], 2 * d[0], d[1]}};
    case ShapeKind::kPlane:  // a static part's kind: planes are drawn by their own case
    case ShapeKind::kNone:
      break;
  }
  return {kSphere, {kPointMarkerDiameter, kPointMarkerDiameter, kPointMarkerDiameter}};
}

}  // namespace

void encode_markers(const SceneDescription& scene, std::span<const StaticFrame> statics,
                    std::vector<std::uint8_t>& out) {
  CdrWriter w(out);
  const std::size_t n = scene.lengths_agree() ? scene.body_count() : 0;
  std::size_t capsules = 0;
  for (std::size_t i = 0; i < n; ++i)
    capsules += scene.shape_kinds[i] == ShapeKind::kCapsule ? 1 : 0;
  for (const StaticFrame& s : statics)
    capsules += !s.plane && s.shape == ShapeKind::kCapsule ? 1 : 0;
  w.count(n + statics.size() + 2 * capsules);
  // A capsule: its cylinder, then its two round ends.
  const auto shape = [&](std::string_view frame, std::string_view ns, std::string_view ends_ns,
                         std::int32_t id, ShapeKind kind, const double* d, std::uint32_t rgb) {
    marker(w, frame, ns, id, shape_of(kind, d), rgb);
    if (kind != ShapeKind::kCapsule) return;
    const Vec3 ball{2 * d[0], 2 * d[0], 2 * d[0]};
    for (int end = 0; end < 2; ++end)
      marker(w, frame, ends_ns, 2 * id + end, Shape{kSphere, ball, end == 0 ? d[1] / 2 : -d[1] / 2},
             rgb);
  };
  for (std::size_t i = 0; i < n; ++i) {
    shape(scene.names[i], "rigid", "rigid_capsule_ends", scene.ids[i], scene.shape_kinds[i],
          &scene.shape_dims[3 * i], kPalette[i % kPalette.size()]);
  }
  for (std::size_t k = 0; k < statics.size(); ++k) {
    const StaticFrame& s = statics[k];
    const auto id = static_cast<std::int32_t>(k);
    if (s.plane) {
      marker(w, s.name, "rigid_static", id,
             Shape{kCube,
                   {kPlaneMarkerSide, kPlaneMarkerSide, kPlaneMarkerThickness},
                   -kPlaneMarkerThickness / 2},
             kStaticColour);
    } else {
      shape(s.name, "rigid_static", "rigid_static_capsule_ends", id, s.shape, s.dims.data(),
            kStaticColour);
    }
  }
}

}  // namespace rigid::transport::ros
