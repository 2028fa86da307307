// The five classic contact cases (one body over a static plane z = 0, gravity 9.81 along -z) and
// their closed forms: what every engine's contact driver is built from and scored against
// (peer_contacts, bench/peers/README.md "Contacts").
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "hard_cases.hpp"  // BodyState, Vec3, Quat

namespace rigid::bench::peers {

enum class ContactShape { kSphere, kCube };

// What a case measures (and so which closed forms it has).
enum class ContactKind {
  kElastic,   // a sphere dropped with e = 1: impact times, apex and energy after 12 bounces
  kBouncing,  // a sphere dropped with e < 1: impact times, apexes, rest time
  kResting,   // a cube put down with a small gap: nothing may move
  kSliding,   // a cube sliding on its face: stop time and distance
  kTumbling,  // a cube dropped turning: its energy never rises, it comes to rest flat
};

struct ContactCase {
  std::string name;
  std::string description;  // one line, for the .meta and the report
  ContactKind kind = ContactKind::kElastic;
  ContactShape shape = ContactShape::kSphere;
  double size = 0.1;  // the sphere's radius or the cube's edge (m)
  double mass = 1.0;  // kg; uniform density
  // The pair's restitution e and Coulomb friction mu (each driver gives its engine what makes the
  // body-plane pair use exactly these: README.md).
  double restitution = 0.0;
  double friction = 0.5;
  BodyState start;  // centre of mass, orientation, world-frame velocities at t = 0
  double g = 9.81;  // along -z
  double duration = 10.0;
  bool plane = true;  // false: the same body falling freely (the cost of a free body of its model)
};

// The five cases, in report order.
std::vector<ContactCase> contact_cases();
// The same body and start without the plane: a free body of the same model.
ContactCase without_plane(const ContactCase& c);

// Speeds below this (m/s) count as rest for an engine whose states are only known at step ends
// (the rest-time rule), and reversals whose approach was slower than it are not impacts but
// jitter at rest (the impact rule).
inline constexpr double kRestSpeed = 0.01;
// The resting cube's drift is measured from this time on: each engine may settle first (land from
// its gap, sink to its soft contact's equilibrium).
inline constexpr double kSettleTime = 1.0;
// How many impacts and apexes are compared with the closed form.
inline constexpr int kImpactsScored = 12;
inline constexpr int kApexesScored = 3;  // the bouncing sphere's first apexes

// The body's collision shape in our terms, and its principal moments (the shape's uniform-density
// inertia; the body frame is principal).
physics::Shape shape_of(const ContactCase& c);
Vec3 principal_moments(const ContactCase& c);
// The height of the centre when the body rests on the plane (flat, for the cube).
double rest_height(const ContactCase& c);
// The largest distance of a point of the body from its centre: |v| + |w| times this bounds every
// point's speed.
double bounding_radius(const ContactCase& c);
// The height of the body's lowest point above the plane (negative: it penetrates).
double lowest_point(const ContactCase& c, const BodyState& s);
// Energy relative to rest on the plane: m g (z - rest_height) plus kinetic (J).
double energy(const ContactCase& c, const BodyState& s);
// The largest speed of any point of the body, bounded as |v| + |w| bounding_radius (m/s).
double speed_bound(const ContactCase& c, const BodyState& s);
// The cube's corners in the world frame (8), for its displacement.
std::vector<Vec3> corners(const ContactCase& c, const BodyState& s);
// The angle between the world's z and the body axis nearest it (rad): 0 when a cube lies flat.
double tilt(const BodyState& s);

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// What the exact motion does (NaN or empty where a case has no closed form for it).
struct ClosedForm {
  // Impact times whose approach speed is at least kRestSpeed, and the apex heights (of the
  // centre) after each: the first at sqrt(2 (h - r) / g), then every 2 e^k sqrt(2 (h - r) / g).
  std::vector<double> impacts;
  std::vector<double> apexes;
  // When the body stops for good: t1 (1 + e) / (1 - e) (bouncing), v0 / (mu g) (sliding).
  double rest_time = kNaN;
  // When its speed is last at least kRestSpeed: the last impact approached at that speed
  // (bouncing), (v0 - kRestSpeed) / (mu g) (sliding).
  double rest_threshold_time = kNaN;
  // The sliding cube's stop distance v0^2 / (2 mu g).
  double stop_distance = kNaN;
};
ClosedForm closed_form(const ContactCase& c);

// Whether the case's exact motion is known in closed form at every instant (every case but the
// tumbling cube), and that motion: piecewise parabolas between the impacts, the slide's constant
// deceleration, the resting cube's 1 um fall onto the plane (e = 0).
bool has_exact_motion(const ContactCase& c);
BodyState exact_state(const ContactCase& c, double t);
// What the speed rule (contact_score.hpp) finds on the exact motion sampled every dt: the time
// the rule should give. Within dt after rest_threshold_time, or earlier where the samples miss
// the short spells above kRestSpeed around the last impacts.
double exact_speed_rule_rest(const ContactCase& c, double dt);

}  // namespace rigid::bench::peers
