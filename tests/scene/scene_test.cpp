// Scene files: every error points at the right line:col and names the field and value; a valid
// scene becomes the right WorldSpec.
#include "scene/scene.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <initializer_list>
#include <numbers>
#include <string>

#include "physics/inertia.hpp"
#include "physics/integrator.hpp"

namespace rigid::scene {
namespace {

using physics::Mat3;
using physics::Vec3;

constexpr double kPi = std::numbers::pi;

// Parses text that must fail; checks the position and that the message mentions each fragment.
void expect_error(std::string_view text, int line, int column,
                  std::initializer_list<std::string_view> fragments) {
  try {
    parse_scene(text, "test.pbtxt");
    ADD_FAILURE() << "no error for:\n" << text;
  } catch (const SceneError& e) {
    EXPECT_EQ(e.file(), "test.pbtxt");
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.column(), column) << e.what();
    EXPECT_EQ(std::string(e.what()), "test.pbtxt:" + std::to_string(line) + ":" +
                                         std::to_string(column) + ": " + e.message());
    for (std::string_view f : fragments) {
      EXPECT_NE(e.message().find(f), std::string::npos) << "'" << f << "' not in: " << e.what();
    }
  }
}

Scene parse(std::string_view text) {
  return parse_scene(text, "test.pbtxt");
}

// ---- static geometry and materials --------------------------------------------------------------

TEST(SceneStatic, PlanesStaticsAndMaterialsLoadWithTheWorldsDefaults) {
  const Scene s = parse(R"(
world { material { restitution: 0.25 friction: 0.8 } }
body { name: "ball" mass: 1 shape { sphere { radius: 0.1 } } material { restitution: 0.9 } }
body { name: "dot" mass: 1 }
plane { name: "ground" normal { z: 2 } offset: 0.5 }
plane { name: "wall" normal { x: -1 } offset: 3 material { friction: 0 } }
static { name: "ramp" shape { box { x: 2 y: 1 z: 0.1 } } position { x: 1 z: 0.2 }
         orientation { w: 0.9238795325112867 y: 0.3826834323650898 } }
)");
  ASSERT_EQ(s.world.planes.size(), 2u);
  ASSERT_EQ(s.world.statics.size(), 1u);
  EXPECT_EQ(s.world.planes[0].name, "ground");
  EXPECT_EQ(s.world.planes[0].n_W, Vec3(0, 0, 1));
  EXPECT_EQ(s.world.planes[0].offset, 0.5);
  EXPECT_EQ(s.world.planes[0].surface.restitution, 0.25);
  EXPECT_EQ(s.world.planes[1].surface.friction, 0.0);
  EXPECT_EQ(s.world.planes[1].surface.restitution, 0.25);
  EXPECT_EQ(s.world.statics[0].shape.kind, physics::ShapeKind::kBox);
  EXPECT_EQ(s.world.statics[0].p_WS, Vec3(1, 0, 0.2));
  EXPECT_NEAR(s.world.statics[0].q_WS.angularDistance(
                  physics::Quat(Eigen::AngleAxisd(kPi / 4, Vec3::UnitY()))),
              0.0, 1e-12);
  EXPECT_EQ(s.world.statics[0].surface.friction, 0.8);
  // A body's material over the world's; its shape is its collision shape, none a point.
  EXPECT_EQ(s.world.bodies[0].surface.restitution, 0.9);
  EXPECT_EQ(s.world.bodies[0].surface.friction, 0.8);
  ASSERT_TRUE(s.world.bodies[0].shape.has_value());
  EXPECT_EQ(s.world.bodies[0].shape->kind, physics::ShapeKind::kSphere);
  EXPECT_FALSE(s.world.bodies[1].shape.has_value());
}

TEST(SceneStatic, WithoutAMaterialTheDefaultsAreInelasticAndHalfFriction) {
  const Scene s = parse("body { name: \"b\" mass: 1 }\nplane { name: \"g\" normal { z: 1 } }\n");
  EXPECT_EQ(s.world.planes[0].surface.restitution, 0.0);
  EXPECT_EQ(s.world.planes[0].surface.friction, 0.5);
  EXPECT_EQ(s.world.bodies[0].surface.restitution, 0.0);
}

TEST(SceneErrors, MaterialValuesOutsideTheirRanges) {
  expect_error("world {\n  material { restitution: 1.5 }\n}\n", 2, 14,
               {"world", "material.restitution", "[0, 1]", "1.5"});
  expect_error("body { name: \"b\" mass: 1\n  material { friction: -0.1 } }\n", 2, 14,
               {"body 'b'", "material.friction", ">= 0", "-0.1"});
  expect_error("plane { name: \"g\" normal { z: 1 }\n material { restitution: -1 } }\n", 2, 13,
               {"plane 'g'", "restitution", "-1"});
}

TEST(SceneErrors, StaticParts) {
  expect_error("plane { name: \"g\"\n  normal { x: 0 } }\n", 2, 3,
               {"plane 'g'", "normal", "non-zero"});
  expect_error("plane { name: \"g\" }\n", 1, 1, {"plane 'g'", "normal", "non-zero"});
  expect_error("plane { normal { z: 1 } }\n", 1, 1, {"plane #1", "name must not be empty"});
  expect_error(
      "plane { name: \"g\" normal { z: 1 } }\nstatic { name: \"g\" shape { sphere { radius: 1 } } "
      "}\n",
      2, 10, {"duplicate static part name 'g'", "1:9"});
  expect_error("body { name: \"b\" mass: 1 }\nplane { name: \"b\" normal { z: 1 } }\n", 2, 9,
               {"plane 'b'", "already a body's", "1:8"});
  expect_error("static { name: \"s\" }\n", 1, 1, {"static 's'", "needs a shape"});
  expect_error("static { name: \"s\" shape { box { x: 1 y: 0 z: 1 } } }\n", 1, 39,
               {"static 's'", "shape.box.y", "> 0"});
  expect_error("static { name: \"s\" shape { ellipsoid { x: 1 y: 1 z: 1 } } }\n", 1, 28,
               {"static 's'", "box, sphere, capsule or cylinder"});
  expect_error("plane { name: \"g\" normal { z: inf } }\n", 1, 28,
               {"plane 'g'", "normal.z", "finite"});
}

TEST(SceneWarnings, NonUnitPlaneNormalIsNormalised) {
  const Scene s = parse("plane { name: \"g\" normal { z: 3 } offset: 1 }\n");
  EXPECT_EQ(s.world.planes[0].n_W, Vec3(0, 0, 1));
  ASSERT_FALSE(s.warnings.empty());
  EXPECT_NE(s.warnings.back().find("normalised"), std::string::npos) << s.warnings.back();
}

// ---- parser errors ------------------------------------------------------------------------------
// The text-format parser reports a problem at the token where it noticed it: the ':' or '{' right
// after a bad field name, or the token after a bad value.

TEST(SceneErrors, UnknownFieldIsLocated) {
  expect_error("body {\n  name: \"a\"\n  mas: 1\n}\n", 3, 6, {"mas"});
}

TEST(SceneErrors, SyntaxErrorIsLocated) {
  expect_error("world {\n  rate_hz: fast\n}\n", 2, 12, {"fast"});
  expect_error("body { name: \"a\" mass: 1\n", 2, 1, {"end of the file"});
}

TEST(SceneErrors, FieldGivenTwice) {
  expect_error("body { name: \"a\" mass: 1 mass: 2 }", 1, 30, {"mass"});
}

TEST(SceneErrors, TwoInertiaSourcesAreRejected) {
  expect_error(
      "body {\n  name: \"a\" mass: 1\n  inertia { x: 1 y: 1 z: 1 }\n"
      "  shape { sphere { radius: 1 } }\n}\n",
      4, 9, {"shape", "inertia"});
}

TEST(SceneErrors, UnknownFrameName) {
  expect_error("body { name: \"a\" mass: 1 }\nforce { body: \"a\" frame: LOCAL }", 2, 32,
               {"LOCAL"});
}

// ---- numbers
// --------------------------------------------------------------------------------------

TEST(SceneErrors, NonFiniteNumbersAnywhere) {
  expect_error("body {\n  name: \"a\" mass: 1\n  velocity { x: 1 y: inf }\n}\n", 3, 19,
               {"body 'a'", "velocity.y", "inf"});
  expect_error("body { name: \"a\" mass: nan }", 1, 18, {"mass", "nan"});
  expect_error("world { gravity { z: -inf } }", 1, 19, {"world", "gravity.z", "-inf"});
  expect_error("body { name: \"a\" mass: 1 }\nforce { body: \"a\" point { x: nan } }", 2, 27,
               {"force #1", "point.x", "nan"});
}

// ---- world
// ----------------------------------------------------------------------------------------

TEST(SceneErrors, RateHz) {
  expect_error("world {\n  rate_hz: 0\n}", 2, 3, {"rate_hz", "0"});
  expect_error("world { rate_hz: -5 }", 1, 9, {"rate_hz", "-5"});
  expect_error("world { rate_hz: 2e6 }", 1, 9, {"rate_hz", "2e+06"});
}

TEST(SceneErrors, Substeps) {
  expect_error("world { substeps: 0 }", 1, 9, {"substeps", "0"});
  expect_error("world { rate_hz: 10 substeps: 10001 }", 1, 21, {"substeps", "10001"});
}

TEST(SceneErrors, PublishEvery) {
  expect_error("world {\n    publish_every: -2 }", 2, 5, {"publish_every", "-2"});
}

TEST(SceneErrors, UnknownIntegratorListsTheValidOnes) {
  const std::string name(physics::default_integrator().name);
  expect_error("world {\n  integrator: \"magic\"\n}", 2, 3, {"integrator", "'magic'", name});
}

TEST(SceneErrors, Limits) {
  expect_error("world { limits { max_force: 0 } }", 1, 18, {"limits.max_force", "0"});
  expect_error("world { limits {\n max_ttl: -1 } }", 2, 2, {"limits.max_ttl", "-1"});
}

// ---- bodies
// ---------------------------------------------------------------------------------------

TEST(SceneErrors, BodyNames) {
  expect_error("body { mass: 1 }", 1, 1, {"body #1", "name"});
  expect_error("body { name: \"\" mass: 1 }", 1, 8, {"body #1", "name"});
  expect_error("body { name: \"a b\" mass: 1 }", 1, 8, {"name", "'a b'"});
  expect_error("body { name: \"a,b\" mass: 1 }", 1, 8, {"name", "'a,b'"});
  expect_error(
      "body { name: \"x\" mass: 1 }\n"
      "body { name: \"y\" mass: 1 }\n"
      "body {\n  name: \"x\" mass: 1 }\n",
      4, 3, {"duplicate body name 'x'", "first defined at 1:8"});
}

TEST(SceneErrors, MassAndDensity) {
  expect_error("body { name: \"a\" mass: 1 density: 2 shape { sphere { radius: 1 } } }", 1, 26,
               {"body 'a'", "mass", "density", "1", "2"});
  expect_error("body { name: \"a\"\n  density: 1000 inertia { x: 1 y: 1 z: 1 } }", 2, 3,
               {"density", "1000", "shape"});
  expect_error("body { name: \"a\" density: -3 shape { sphere { radius: 1 } } }", 1, 18,
               {"density", "-3"});
  expect_error("\nbody { name: \"a\" inertia { x: 1 y: 1 z: 1 } }", 2, 1, {"body 'a'", "mass"});
  // A kinematic body needs neither.
  EXPECT_NO_THROW(parse("body { name: \"a\" kinematic: true velocity { x: 1 } }"));
}

TEST(SceneErrors, DensityTimesVolumeMustBeAUsableMass) {
  expect_error("body { name: \"a\" density: 1e300 shape { box { x: 1e10 y: 1e10 z: 1e10 } } }", 1,
               18, {"density", "inf"});
}

TEST(SceneErrors, ShapeSizes) {
  expect_error("body { name: \"a\" mass: 1\n  shape { box { x: 1 y: 2 } } }", 2, 11,
               {"shape.box.z", "0"});
  expect_error("body { name: \"a\" mass: 1 shape { sphere { radius: -1 } } }", 1, 43,
               {"shape.sphere.radius", "-1"});
  expect_error("body { name: \"a\" mass: 1 shape { cylinder { radius: 1 length: 0 } } }", 1, 55,
               {"shape.cylinder.length", "0"});
  expect_error("body { name: \"a\" mass: 1 shape { capsule { length: 1 } } }", 1, 34,
               {"shape.capsule.radius", "0"});
  expect_error("body { name: \"a\" mass: 1 shape { ellipsoid { x: 1 y: -2 z: 1 } } }", 1, 51,
               {"shape.ellipsoid.y", "-2"});
  expect_error("body { name: \"a\" mass: 1\n shape { } }", 2, 2, {"shape", "box"});
}

TEST(SceneErrors, OrientationThatCannotBeNormalised) {
  expect_error("body { name: \"a\" mass: 1\n  orientation { x: 0 } }", 2, 3,
               {"body 'a'", "orientation", "(0, 0, 0, 0)"});
}

TEST(SceneErrors, FrameNumbersOutsideTheEnum) {
  expect_error("body { name: \"a\" mass: 1 }\nforce { body: \"a\" frame: 5 }", 2, 19,
               {"force #1", "frame", "5"});
  expect_error("body { name: \"a\" mass: 1 }\nforce { body: \"a\" torque_frame: -3 }", 2, 19,
               {"force #1", "torque_frame", "-3"});
  // The numbers of the enum's own values are accepted.
  const Scene s = parse("body { name: \"a\" mass: 1 }\nforce { body: \"a\" frame: 1 }");
  EXPECT_EQ(s.world.loads[0].frame, physics::Frame::kBody);
}

TEST(SceneErrors, NonPrintableNameIsEscaped) {
  expect_error("body { name: \"a\\xff\" mass: 1 }", 1, 8, {"'a\\xff'"});
}

TEST(SceneErrors, ForceOnUnknownBody) {
  expect_error("body { name: \"a\" mass: 1 }\nforce {\n  body: \"b\" force { x: 1 } }", 3, 3,
               {"force #1", "'b'"});
  expect_error("body { name: \"a\" mass: 1 }\nforce { force { x: 1 } }", 2, 1,
               {"force #1", "body"});
}

// ---- errors found by physics::World, located in the file
// ------------------------------------------

TEST(SceneErrors, NegativeMass) {
  expect_error("body {\n  name: \"a\"\n  mass: -2\n}", 3, 3, {"mass", "-2"});
  expect_error("body { name: \"a\" mass: 0 }", 1, 18, {"mass", "0"});
}

TEST(SceneErrors, InertiaNotPositiveDefinite) {
  expect_error("body { name: \"a\" mass: 1\n  inertia { x: 1 y: -2 z: 3 } }", 2, 3,
               {"inertia", "-2"});
}

TEST(SceneErrors, InertiaTriangleInequality) {
  expect_error("body { name: \"a\" mass: 1\n  inertia { x: 1 y: 1 z: 3 } }", 2, 3,
               {"inertia", "triangle"});
  expect_error("body { name: \"a\" mass: 1\n   inertia_tensor { xx: 1 yy: 1 zz: 3 } }", 2, 4,
               {"inertia", "triangle"});
}

TEST(SceneErrors, NegativeDrag) {
  expect_error("body { name: \"a\" mass: 1\n linear_drag: -0.5 }", 2, 2, {"linear_drag", "-0.5"});
  expect_error("body { name: \"a\" mass: 1\n angular_drag: -1 inertia { x: 1 y: 1 z: 1 } }", 2, 2,
               {"angular_drag", "-1"});
}

TEST(SceneErrors, FreezingExactlyOneRotationAxis) {
  expect_error(
      "body { name: \"a\" mass: 1 inertia { x: 1 y: 1 z: 1 }\n  freeze_rotation { y: true } }", 2,
      3, {"freeze_rotation"});
}

TEST(SceneErrors, PhysicsErrorsPointAtTheRightBody) {
  expect_error(
      "body { name: \"a\" mass: 1 }\nbody { name: \"b\" mass: 1 }\n"
      "body { name: \"c\"\n  mass: -1 }",
      4, 3, {"mass", "-1"});
}

// ---- warnings
// -------------------------------------------------------------------------------------

TEST(SceneWarnings, NonUnitOrientationIsNormalisedWithAWarning) {
  const Scene s =
      parse("body { name: \"a\" mass: 1 inertia { x: 1 y: 1 z: 1 }\n  orientation { w: 2 } }");
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_EQ(s.warnings[0].rfind("test.pbtxt:2:3: warning: ", 0), 0u) << s.warnings[0];
  EXPECT_NE(s.warnings[0].find("(2, 0, 0, 0)"), std::string::npos) << s.warnings[0];
  EXPECT_EQ(s.world.bodies[0].q_WB.coeffs(), physics::Quat::Identity().coeffs());
}

TEST(SceneWarnings, NearlyUnitOrientationIsNormalisedQuietly) {
  const Scene s = parse("body { name: \"a\" mass: 1 orientation { w: 1.0000000001 } }");
  EXPECT_TRUE(s.warnings.empty());
  EXPECT_NEAR(s.world.bodies[0].q_WB.norm(), 1.0, 1e-16);
}

TEST(SceneWarnings, ForceOnKinematicBody) {
  const Scene s =
      parse("body { name: \"k\" kinematic: true }\nforce { body: \"k\" force { x: 1 } }");
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_EQ(s.warnings[0].rfind("test.pbtxt:2:1: warning: ", 0), 0u) << s.warnings[0];
  EXPECT_NE(s.warnings[0].find("kinematic"), std::string::npos);
}

TEST(SceneWarnings, EmptyScene) {
  const Scene s = parse("");
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("no bodies"), std::string::npos);
}

// ---- valid scenes
// ---------------------------------------------------------------------------------

TEST(SceneLoad, Defaults) {
  const Scene s = parse("body { name: \"p\" mass: 2 }");
  EXPECT_EQ(s.path, "test.pbtxt");
  EXPECT_EQ(s.rate_hz, 1000.0);
  EXPECT_EQ(s.substeps, 1);
  EXPECT_EQ(s.publish_every, 1);
  EXPECT_EQ(s.world.dt, 1e-3);
  EXPECT_EQ(s.world.g_W, Vec3(0, 0, -9.81));
  EXPECT_EQ(s.world.integrator, "");
  EXPECT_EQ(s.limits.max_force, 1e6);
  EXPECT_EQ(s.limits.max_torque, 1e6);
  EXPECT_EQ(s.limits.max_ttl, 60.0);
  ASSERT_EQ(s.world.bodies.size(), 1u);
  const physics::BodySpec& b = s.world.bodies[0];
  EXPECT_EQ(b.name, "p");
  EXPECT_EQ(b.mass, 2.0);
  EXPECT_FALSE(b.has_inertia);  // no inertia given: a point mass
  EXPECT_EQ(b.q_WB.coeffs(), physics::Quat::Identity().coeffs());
  EXPECT_EQ(b.p_WBo, Vec3::Zero());
  EXPECT_TRUE(b.use_gravity);
  EXPECT_FALSE(b.kinematic);
  EXPECT_EQ(b.linear_drag, 0.0);
  EXPECT_TRUE(s.warnings.empty());
}

TEST(SceneLoad, FullSceneRoundTrips) {
  const Scene s = parse(R"pb(
    world {
      rate_hz: 400
      substeps: 4
      publish_every: 8
      gravity { x: 0.5 y: -1 z: -3.7 }
      integrator: "rk4"
      limits { max_force: 100 max_torque: 20 max_ttl: 2.5 }
    }
    body {
      name: "tensor"
      mass: 3
      inertia_tensor { xx: 2 yy: 3 zz: 4 xy: 0.1 xz: -0.2 yz: 0.3 }
      position { x: 1 y: 2 z: 3 }
      orientation { w: 0.5 x: 0.5 y: 0.5 z: 0.5 }
      velocity { x: -1 y: -2 z: -3 }
      angular_velocity { x: 0.1 y: 0.2 z: 0.3 }
      linear_drag: 0.25
      angular_drag: 0.125
      use_gravity: false
      freeze_translation { z: true }
      freeze_rotation { x: true y: true }
    }
    body {
      name: "moments"
      mass: 1.5
      inertia { x: 1 y: 2 z: 2.5 }
      kinematic: true
    }
    force {
      body: "moments"
      force { x: 1 y: 2 z: 3 }
      point { x: 0.1 }
      frame: BODY
      torque { z: 4 }
      torque_frame: BODY
    }
    force {
      body: "tensor"
      force { z: 9 }
    }
  )pb");
  EXPECT_EQ(s.rate_hz, 400.0);
  EXPECT_EQ(s.substeps, 4);
  EXPECT_EQ(s.publish_every, 8);
  EXPECT_EQ(s.world.dt, 1.0 / 1600.0);
  EXPECT_EQ(s.world.g_W, Vec3(0.5, -1, -3.7));
  EXPECT_EQ(s.world.integrator, "rk4");
  EXPECT_EQ(s.limits.max_force, 100.0);
  EXPECT_EQ(s.limits.max_torque, 20.0);
  EXPECT_EQ(s.limits.max_ttl, 2.5);

  ASSERT_EQ(s.world.bodies.size(), 2u);
  const physics::BodySpec& a = s.world.bodies[0];
  EXPECT_EQ(a.name, "tensor");
  EXPECT_EQ(a.mass, 3.0);
  Mat3 I;
  I << 2, 0.1, -0.2, 0.1, 3, 0.3, -0.2, 0.3, 4;
  EXPECT_EQ(a.I_B, I);
  EXPECT_TRUE(a.has_inertia);
  EXPECT_EQ(a.p_WBo, Vec3(1, 2, 3));
  EXPECT_EQ(a.q_WB.coeffs(), physics::Quat(0.5, 0.5, 0.5, 0.5).coeffs());
  EXPECT_EQ(a.v_WBo, Vec3(-1, -2, -3));
  EXPECT_EQ(a.w_WB, Vec3(0.1, 0.2, 0.3));
  EXPECT_EQ(a.linear_drag, 0.25);
  EXPECT_EQ(a.angular_drag, 0.125);
  EXPECT_FALSE(a.use_gravity);
  EXPECT_FALSE(a.kinematic);
  EXPECT_EQ(a.freeze_translation, (std::array<bool, 3>{false, false, true}));
  EXPECT_EQ(a.freeze_rotation, (std::array<bool, 3>{true, true, false}));

  const physics::BodySpec& b = s.world.bodies[1];
  EXPECT_EQ(b.name, "moments");
  EXPECT_EQ(b.I_B, Mat3(Vec3(1, 2, 2.5).asDiagonal()));
  EXPECT_TRUE(b.kinematic);
  EXPECT_TRUE(b.use_gravity);

  ASSERT_EQ(s.world.loads.size(), 2u);
  const physics::LoadSpec& l = s.world.loads[0];
  EXPECT_EQ(l.body, 1);
  EXPECT_EQ(l.force, Vec3(1, 2, 3));
  EXPECT_EQ(l.p_BoQ_B, Vec3(0.1, 0, 0));
  EXPECT_EQ(l.frame, physics::Frame::kBody);
  EXPECT_EQ(l.torque, Vec3(0, 0, 4));
  EXPECT_EQ(l.torque_frame, physics::Frame::kBody);
  const physics::LoadSpec& m = s.world.loads[1];
  EXPECT_EQ(m.body, 0);
  EXPECT_EQ(m.force, Vec3(0, 0, 9));
  EXPECT_EQ(m.p_BoQ_B, Vec3::Zero());
  EXPECT_EQ(m.frame, physics::Frame::kWorld);
  EXPECT_EQ(m.torque_frame, physics::Frame::kWorld);
  // The kinematic body's force draws a warning, nothing else does.
  EXPECT_EQ(s.warnings.size(), 1u);
}

TEST(SceneLoad, DensityGivesMassFromVolume) {
  struct Case {
    const char* shape;
    physics::Shape expected;
    double volume;
  };
  const Case cases[] = {
      {"box { x: 1 y: 2 z: 3 }", {physics::ShapeKind::kBox, Vec3(1, 2, 3)}, 6.0},
      {"sphere { radius: 0.5 }", {physics::ShapeKind::kSphere, Vec3(0.5, 0, 0)}, kPi / 6.0},
      {"cylinder { radius: 1 length: 2 }",
       {physics::ShapeKind::kCylinder, Vec3(1, 0, 2)},
       2.0 * kPi},
      {"capsule { radius: 1 length: 2 }",
       {physics::ShapeKind::kCapsule, Vec3(1, 0, 2)},
       2.0 * kPi + 4.0 / 3.0 * kPi},
      {"ellipsoid { x: 1 y: 2 z: 3 }", {physics::ShapeKind::kEllipsoid, Vec3(1, 2, 3)}, 8.0 * kPi},
  };
  for (const Case& c : cases) {
    const Scene s =
        parse(std::string("body { name: \"a\" density: 250 shape { ") + c.shape + " } }");
    const physics::BodySpec& b = s.world.bodies[0];
    EXPECT_NEAR(b.mass, 250.0 * c.volume, 1e-12 * b.mass) << c.shape;
    EXPECT_TRUE(b.has_inertia);
    EXPECT_EQ(b.I_B, physics::shape_inertia(c.expected, b.mass)) << c.shape;
  }
}

TEST(SceneLoad, ShapeWithMass) {
  const Scene s = parse("body { name: \"a\" mass: 5 shape { sphere { radius: 2 } } }");
  EXPECT_EQ(s.world.bodies[0].mass, 5.0);
  EXPECT_EQ(s.world.bodies[0].I_B, Mat3(Vec3::Constant(8.0).asDiagonal()));
}

TEST(SceneLoad, ListSyntaxAndComments) {
  const Scene s =
      parse("# a comment\nbody [{ name: \"a\" mass: 1 }, { name: \"b\" mass: 2 }]  # another\n");
  ASSERT_EQ(s.world.bodies.size(), 2u);
  EXPECT_EQ(s.world.bodies[1].name, "b");
}

// ---- files
// ----------------------------------------------------------------------------------------

TEST(SceneFiles, MissingFile) {
  try {
    load_scene("/nonexistent/scene.pbtxt");
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()),
              "/nonexistent/scene.pbtxt: cannot open: No such file or directory");
  }
}

TEST(SceneFiles, Directory) {
  EXPECT_THROW(load_scene(std::filesystem::temp_directory_path().string()), SceneError);
}

TEST(SceneFiles, ErrorsNameTheFile) {
  const std::filesystem::path p = std::filesystem::temp_directory_path() /
                                  ("rigid_scene_test_" + std::to_string(::getpid()) + ".pbtxt");
  {
    std::FILE* f = std::fopen(p.c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs("body {\n  name: \"a\"\n  mass: 1\n  linear_drag: inf\n}\n", f);
    std::fclose(f);
  }
  try {
    load_scene(p.string());
    ADD_FAILURE() << "no error";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.file(), p.string());
    EXPECT_EQ(std::string(e.what()).rfind(p.string() + ":4:3: ", 0), 0u) << e.what();
  }
  std::filesystem::remove(p);
}

TEST(SceneFiles, ShippedScenesLoadCleanly) {
  int n = 0;
  for (const auto& entry : std::filesystem::directory_iterator(RIGID_SCENES_DIR)) {
    if (entry.path().extension() != ".pbtxt") continue;
    ++n;
    const Scene s = load_scene(entry.path().string());
    EXPECT_TRUE(s.warnings.empty()) << entry.path() << ": " << s.warnings.front();
    EXPECT_FALSE(s.world.bodies.empty()) << entry.path();
  }
  EXPECT_GE(n, 3);
}

TEST(SceneFiles, RacketScene) {
  const Scene s = load_scene(std::string(RIGID_SCENES_DIR) + "/racket.pbtxt");
  ASSERT_EQ(s.world.bodies.size(), 1u);
  const physics::BodySpec& b = s.world.bodies[0];
  EXPECT_EQ(b.I_B, Mat3(Vec3(1, 2, 3).asDiagonal()));
  EXPECT_EQ(b.w_WB, Vec3(1e-3, 5, 1e-3));
  EXPECT_EQ(s.world.dt, 1e-3);
  EXPECT_TRUE(s.world.g_W == Vec3::Zero() || !b.use_gravity);
}

}  // namespace
}  // namespace rigid::scene
