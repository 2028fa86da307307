// Physics state -> StateFrame (flat per-body arrays in id order, quaternion w first, everything in
// W), and the scene -> SceneDescription.
#include "common/state_conversion.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "loop/triple_buffer.hpp"

namespace rigid::loop {
namespace {

scene::Scene test_scene() {
  return scene::parse_scene(R"(
world { rate_hz: 500 substeps: 2 publish_every: 5 gravity { z: -1 }
        limits { max_force: 50 max_torque: 5 max_ttl: 2 } }
body { name: "a" mass: 2 inertia { x: 1 y: 2 z: 3 } position { x: 1 y: 2 z: 3 }
       orientation { w: 0.8 x: 0.6 } velocity { x: -1 } angular_velocity { y: 0.5 } }
body { name: "p" mass: 0.5 position { z: -4 } velocity { x: 7 y: 8 z: 9 } }
)",
                            "test.pbtxt");
}

TEST(StateConversion, FrameHoldsEveryBodyInIdOrder) {
  const scene::Scene s = test_scene();
  physics::World world(s.world);
  world.step(3);
  rigid::StateFrame frame;
  common::shape_state_frame(world, frame);
  ASSERT_TRUE(frame.lengths_agree());
  EXPECT_EQ(frame.ids, (std::vector<std::int32_t>{0, 1}));
  common::fill_state_frame(world, 42, 0.042, frame);
  EXPECT_EQ(frame.tick, 42);
  EXPECT_EQ(frame.sim_time, 0.042);
  for (int i = 0; i < 2; ++i) {
    const physics::BodyState b = world.state(i);
    const auto k = static_cast<std::size_t>(i);
    EXPECT_EQ(frame.position[3 * k + 0], b.p_WBo.x());
    EXPECT_EQ(frame.position[3 * k + 2], b.p_WBo.z());
    EXPECT_EQ(frame.orientation[4 * k + 0], b.q_WB.w());
    EXPECT_EQ(frame.orientation[4 * k + 1], b.q_WB.x());
    EXPECT_EQ(frame.orientation[4 * k + 3], b.q_WB.z());
    EXPECT_EQ(frame.linear_velocity[3 * k + 0], b.v_WBo.x());
    EXPECT_EQ(frame.angular_velocity[3 * k + 1], b.w_WB.y());
  }
  // Body 0 starts at orientation (0.8, 0.6, 0, 0) and spins about y in W.
  EXPECT_NEAR(frame.orientation[0], 0.8, 1e-3);
  EXPECT_NEAR(frame.angular_velocity[1], 0.5, 1e-6);  // torque-free: L is constant, w nearly
  EXPECT_EQ(frame.linear_velocity[3], 7.0);
}

TEST(StateConversion, RefillingAFrameDoesNotReallocate) {
  const scene::Scene s = test_scene();
  physics::World world(s.world);
  rigid::StateFrame frame;
  common::shape_state_frame(world, frame);
  const double* data = frame.position.data();
  for (int k = 0; k < 10; ++k) {
    world.step();
    common::fill_state_frame(world, k, k * 1e-3, frame);
  }
  EXPECT_EQ(frame.position.data(), data);
}

TEST(StateConversion, SceneDescription) {
  const scene::Scene s = test_scene();
  physics::World world(s.world);
  const rigid::SceneDescription d = common::describe_scene(s, world);
  ASSERT_TRUE(d.lengths_agree());
  EXPECT_EQ(d.scene_name, "test.pbtxt");
  EXPECT_DOUBLE_EQ(d.dt, 1.0 / 500);
  EXPECT_EQ(d.substeps, 2);
  EXPECT_EQ(d.publish_every, 5);
  EXPECT_EQ(d.gravity, (rigid::Vec3{0, 0, -1}));
  EXPECT_EQ(d.integrator, std::string(world.integrator().name));
  EXPECT_EQ(d.max_force, 50);
  EXPECT_EQ(d.max_torque, 5);
  EXPECT_EQ(d.names, (std::vector<std::string>{"a", "p"}));
  EXPECT_EQ(d.masses, (std::vector<double>{2, 0.5}));
  EXPECT_EQ(d.inertia, (std::vector<double>{1, 2, 3, 0, 0, 0, 0, 0, 0, 0, 0, 0}));
}

// Shapes given in the file reach SceneInfo with their wire dims; an inertia given directly is
// SHAPE_NONE.
TEST(StateConversion, SceneDescriptionCarriesTheShapes) {
  const scene::Scene s = scene::parse_scene(R"(
body { name: "ball" density: 10 shape { sphere { radius: 0.5 } } }
body { name: "brick" mass: 1 shape { box { x: 1 y: 2 z: 3 } } }
body { name: "can" mass: 1 shape { cylinder { radius: 0.2 length: 0.7 } } }
body { name: "pill" mass: 1 shape { capsule { radius: 0.1 length: 0.4 } } }
body { name: "egg" mass: 1 shape { ellipsoid { x: 0.1 y: 0.2 z: 0.3 } } }
body { name: "plain" mass: 1 inertia { x: 1 y: 1 z: 1 } }
)",
                                            "shapes.pbtxt");
  physics::World world(s.world);
  const rigid::SceneDescription d = common::describe_scene(s, world);
  ASSERT_TRUE(d.lengths_agree());
  using K = rigid::ShapeKind;
  EXPECT_EQ(d.shape_kinds, (std::vector<K>{K::kSphere, K::kBox, K::kCylinder, K::kCapsule,
                                           K::kEllipsoid, K::kNone}));
  EXPECT_EQ(d.shape_dims, (std::vector<double>{0.5, 0, 0, 1, 2, 3, 0.2, 0.7, 0, 0.1, 0.4, 0, 0.1,
                                               0.2, 0.3, 0, 0, 0}));
}

// Static parts reach SceneInfo planes first, then shapes, each with its frame S: a plane's origin
// is its point nearest W's origin and its z axis its unit normal; a shape's pose, dims and material
// as given (the world's material where it gives none).
TEST(StateConversion, SceneDescriptionCarriesTheStaticParts) {
  const scene::Scene s = scene::parse_scene(R"(
world { material { restitution: 0.25 friction: 0.75 } }
body { name: "ball" mass: 1 shape { sphere { radius: 0.1 } } }
static { name: "ramp" shape { box { x: 2 y: 1 z: 0.1 } } position { x: 1 y: 2 z: 3 }
         orientation { w: 0.8 y: 0.6 } material { friction: 0.2 } }
static { name: "post" shape { cylinder { radius: 0.3 length: 2 } } }
plane { name: "ground" normal { z: 1 } offset: -0.5 material { restitution: 0.5 } }
plane { name: "wall" normal { x: -3 } offset: 2 }
plane { name: "ceiling" normal { z: -1 } offset: 10 }
)",
                                            "parts.pbtxt");
  physics::World world(s.world);
  const rigid::SceneDescription d = common::describe_scene(s, world);
  ASSERT_TRUE(d.lengths_agree());
  ASSERT_EQ(d.part_count(), 5u);
  EXPECT_EQ(d.part_names, (std::vector<std::string>{"ground", "wall", "ceiling", "ramp", "post"}));
  using K = rigid::ShapeKind;
  EXPECT_EQ(d.part_kinds, (std::vector<K>{K::kPlane, K::kPlane, K::kPlane, K::kBox, K::kCylinder}));
  EXPECT_EQ(d.part_restitution, (std::vector<double>{0.5, 0.25, 0.25, 0.25, 0.25}));
  EXPECT_EQ(d.part_friction, (std::vector<double>{0.75, 0.75, 0.75, 0.2, 0.75}));
  // Each plane: S's z axis (q_WS applied to z) is the unit normal, and S's origin is offset along
  // it; a point of the plane z = 0 of S satisfies n . x = offset.
  const std::vector<physics::Vec3> normals{{0, 0, 1}, {-1, 0, 0}, {0, 0, -1}};
  const std::vector<double> offsets{-0.5, 2, 10};
  for (std::size_t i = 0; i < 3; ++i) {
    SCOPED_TRACE(d.part_names[i]);
    const physics::Quat q(d.part_orientation[4 * i], d.part_orientation[4 * i + 1],
                          d.part_orientation[4 * i + 2], d.part_orientation[4 * i + 3]);
    EXPECT_NEAR(q.norm(), 1.0, 1e-15);
    EXPECT_LT((q * physics::Vec3::UnitZ() - normals[i]).norm(), 1e-15);
    const physics::Vec3 p(d.part_position[3 * i], d.part_position[3 * i + 1],
                          d.part_position[3 * i + 2]);
    EXPECT_LT((p - offsets[i] * normals[i]).norm(), 1e-15);
    const physics::Vec3 on_plane = p + q * physics::Vec3(0.3, -0.7, 0.0);
    EXPECT_NEAR(normals[i].dot(on_plane), offsets[i], 1e-14);
    EXPECT_EQ(d.part_dims[3 * i], 0.0);
  }
  // The shortest turn of z onto the normal, and for n = -z a half turn about x (/tf_static of
  // rigidd --ros carries the same frames).
  EXPECT_EQ(std::vector<double>(d.part_orientation.begin(), d.part_orientation.begin() + 4),
            (std::vector<double>{1, 0, 0, 0}));
  EXPECT_EQ(std::vector<double>(d.part_orientation.begin() + 8, d.part_orientation.begin() + 12),
            (std::vector<double>{0, 1, 0, 0}));
  // z onto -x: a quarter turn about y (to an ulp or two: the frame divides by a hypot)
  EXPECT_NEAR(d.part_orientation[4], std::sqrt(0.5), 3e-16);
  EXPECT_NEAR(d.part_orientation[6], -std::sqrt(0.5), 3e-16);
  EXPECT_EQ(std::vector<double>(d.part_position.begin() + 9, d.part_position.end()),
            (std::vector<double>{1, 2, 3, 0, 0, 0}));
  EXPECT_EQ(std::vector<double>(d.part_orientation.begin() + 12, d.part_orientation.end()),
            (std::vector<double>{0.8, 0, 0.6, 0, 1, 0, 0, 0}));
  EXPECT_EQ(std::vector<double>(d.part_dims.begin() + 9, d.part_dims.end()),
            (std::vector<double>{2, 1, 0.1, 0.3, 2, 0}));
}

TEST(TripleBuffer, TheReaderGetsTheNewestAndOverwritesAreReported) {
  TripleBuffer<int> b(0);
  EXPECT_EQ(b.take(), nullptr);
  b.back() = 1;
  EXPECT_FALSE(b.publish());
  b.back() = 2;
  EXPECT_TRUE(b.publish());  // 1 was never taken
  int* v = b.take();
  ASSERT_NE(v, nullptr);
  EXPECT_EQ(*v, 2);
  EXPECT_EQ(b.take(), nullptr);
  b.back() = 3;
  EXPECT_FALSE(b.publish());
  EXPECT_EQ(*v, 2);  // the reader's value is untouched until its next take
  EXPECT_EQ(*b.take(), 3);
}

}  // namespace
}  // namespace rigid::loop
