#include "physics/contact/gap.hpp"

#include <cmath>

namespace rigid::physics::contact {

Gap plane_gap(const Convex& body, const Pose& pose, const StaticPart& plane) {
  const Vec3& n = plane.n_W;
  const Vec3 u_B = pose.q_WB.conjugate() * (-n);  // towards the plane, in B
  const Vec3 core_B = body.core_support(u_B);
  Gap g;
  g.n_W = n;
  g.p_W = pose.p_WBo + pose.q_WB * core_B - body.radius * n;
  g.distance = n.dot(pose.p_WBo) - body.core_height(u_B) - body.radius - plane.offset;
  return g;
}

Gap shape_gap(const Convex& body, const Pose& pose, const StaticPart& part) {
  const Placed a{&body, pose.p_WBo, pose.q_WB};
  const Placed b{&part.convex, part.p_WS, part.q_WS};
  const double radii = body.radius + part.convex.radius;
  CoreDistance d = core_distance(a, b);
  Vec3 n;
  // The cores' closest points give the normal while they are apart by more than round-off can
  // disturb; closer, the direction between them is noise, and the normal is taken from the same
  // query on the body backed off from the part by a small distance (the shapes do not turn in it,
  // so the closest features are the same ones).
  constexpr double kWellApart = 1e-7;
  if (d.distance > kWellApart * (1.0 + part.p_WS.norm() + pose.p_WBo.norm())) {
    n = (d.p_A - d.p_B) / d.distance;
  } else {
    Vec3 away = d.distance > 0.0 ? Vec3(d.p_A - d.p_B) : Vec3(pose.p_WBo - part.p_WS);
    if (away.squaredNorm() == 0.0) away = Vec3::UnitZ();
    away.normalize();
    const double step = 1e-5 * (1.0 + body.bounding_radius() + part.convex.bounding_radius());
    const Placed backed{&body, pose.p_WBo + step * away, pose.q_WB};
    const CoreDistance e = core_distance(backed, b);
    n = e.distance > 0.0 ? Vec3((e.p_A - e.p_B) / e.distance) : away;
    if (d.distance == 0.0) {
      // Touching cores: the closest points are where the backed-off ones came from.
      d.p_A = e.p_A - step * away;
    }
  }
  Gap g;
  g.n_W = n;
  g.distance = d.distance - radii;
  g.p_W = d.p_A - body.radius * n;
  return g;
}

int touching_points(const Convex& body, const Pose& pose, const StaticPart& part, const Gap& g,
                    double tol, std::array<Vec3, kMaxFeature>& out) {
  const Vec3 u_B = pose.q_WB.conjugate() * (-g.n_W);
  std::array<Vec3, kMaxFeature> local;
  const int n = touching_points(body, u_B, tol, local);
  int kept = 0;
  for (int k = 0; k < n; ++k) {
    const Vec3 p_W = pose.p_WBo + pose.q_WB * local[k];
    if (part.kind == StaticPart::Kind::kShape && n > 1) {
      // Of a face or an edge, only what lies on the part (a box's corner past the edge of a
      // static box does not touch it).
      const Convex point;
      const Placed a{&point, p_W, Quat::Identity()};
      const Placed b{&part.convex, part.p_WS, part.q_WS};
      if (core_distance(a, b).distance - part.convex.radius > g.distance + tol) continue;
    }
    out[kept++] = p_W;
  }
  if (kept == 0) out[kept++] = g.p_W;  // the closest point itself always touches
  return kept;
}

}  // namespace rigid::physics::contact
