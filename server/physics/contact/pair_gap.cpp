#include "physics/contact/pair_gap.hpp"

#include <algorithm>
#include <cmath>

#include "physics/contact/gjk.hpp"

namespace rigid::physics::contact {

namespace {

bool round_point(const Convex& c) {
  return c.kind == Convex::Kind::kPoint || c.kind == Convex::Kind::kSphere;
}

// Two unit tangents completing n (Duff et al., JCGT 6(1), 2017).
void plane_basis(const Vec3& n, Vec3& t1, Vec3& t2) {
  const double sign = std::copysign(1.0, n.z());
  const double a = -1.0 / (sign + n.z());
  const double b = n.x() * n.y() * a;
  t1 = Vec3(1.0 + sign * n.x() * n.x() * a, sign * b, -sign * n.x());
  t2 = Vec3(b, sign + n.y() * n.y() * a, -n.y());
}

using P2 = Eigen::Vector2d;

// The points in counter-clockwise order about their centroid (a convex feature's corners).
int order_ccw(P2* p, int n) {
  if (n < 3) return n;
  P2 c = P2::Zero();
  for (int i = 0; i < n; ++i)
    c += p[i] / n;
  std::sort(p, p + n, [&](const P2& u, const P2& v) {
    return std::atan2(u.y() - c.y(), u.x() - c.x()) < std::atan2(v.y() - c.y(), v.x() - c.x());
  });
  return n;
}

double cross2(const P2& a, const P2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// Sutherland-Hodgman: the part of polygon (or segment) `in` inside the convex CCW polygon `clip`.
int clip_polygon(const P2* in, int n, const P2* clip, int m, P2* out, int cap) {
  P2 buf[2][32];
  int count = std::min(n, 32);
  std::copy(in, in + count, buf[0]);
  int cur = 0;
  for (int e = 0; e < m && count > 0; ++e) {
    const P2 a = clip[e], b = clip[(e + 1) % m];
    const auto inside = [&](const P2& p) { return cross2(b - a, p - a) >= 0.0; };
    const P2* src = buf[cur];
    P2* dst = buf[1 - cur];
    int k = 0;
    const bool closed = count >= 3;
    const int edges = closed ? count : count - 1;
    if (!closed && count == 2) {
      // A segment: keep its part inside.
      const P2 p = src[0], q = src[1];
      const bool ip = inside(p), iq = inside(q);
      if (ip && iq) {
        dst[k++] = p, dst[k++] = q;
      } else if (ip != iq) {
        const double dp = cross2(b - a, p - a), dq = cross2(b - a, q - a);
        const P2 x = p + (q - p) * (dp / (dp - dq));
        dst[k++] = ip ? p : x;
        dst[k++] = ip ? x : q;
      }
    } else if (!closed) {
      if (inside(src[0])) dst[k++] = src[0];
    } else {
      for (int i = 0; i < edges && k < 30; ++i) {
        const P2 p = src[i], q = src[(i + 1) % count];
        const bool ip = inside(p), iq = inside(q);
        if (ip) dst[k++] = p;
        if (ip != iq) {
          const double dp = cross2(b - a, p - a), dq = cross2(b - a, q - a);
          dst[k++] = p + (q - p) * (dp / (dp - dq));
        }
      }
    }
    count = k;
    cur = 1 - cur;
  }
  // Keep at most cap points: drop the one that adds the least area until it fits.
  P2* res = buf[cur];
  while (count > cap) {
    int worst = 0;
    double least = INFINITY;
    for (int i = 0; i < count; ++i) {
      const P2 p = res[(i + count - 1) % count], q = res[i], r = res[(i + 1) % count];
      const double area = std::abs(cross2(q - p, r - p));
      if (area < least) least = area, worst = i;
    }
    std::copy(res + worst + 1, res + count, res + worst);
    --count;
  }
  std::copy(res, res + count, out);
  return count;
}

}  // namespace

PairGap pair_gap(const Convex& a, const Pose& pa, const Convex& b, const Pose& pb) {
  PairGap g;
  if (round_point(a) && round_point(b)) {
    const Vec3 d = pa.p_WBo - pb.p_WBo;
    const double len = d.norm();
    g.n_W = len > 0.0 ? Vec3(d / len) : Vec3::UnitZ();
    g.distance = len - a.radius - b.radius;
    g.p_a_W = pa.p_WBo - a.radius * g.n_W;
    g.p_b_W = pb.p_WBo + b.radius * g.n_W;
    return g;
  }
  const Placed A{&a, pa.p_WBo, pa.q_WB};
  const Placed B{&b, pb.p_WBo, pb.q_WB};
  CoreDistance d = core_distance(A, B);
  Vec3 n;
  constexpr double kWellApart = 1e-7;
  if (d.distance > kWellApart * (1.0 + pa.p_WBo.norm() + pb.p_WBo.norm())) {
    n = (d.p_A - d.p_B) / d.distance;
  } else {
    // Touching cores: the normal from the pair backed off along the centres' line (shape_gap).
    Vec3 away = d.distance > 0.0 ? Vec3(d.p_A - d.p_B) : Vec3(pa.p_WBo - pb.p_WBo);
    if (away.squaredNorm() == 0.0) away = Vec3::UnitZ();
    away.normalize();
    const double step = 1e-5 * (1.0 + a.bounding_radius() + b.bounding_radius());
    const Placed backed{&a, pa.p_WBo + step * away, pa.q_WB};
    const CoreDistance e = core_distance(backed, B);
    n = e.distance > 0.0 ? Vec3((e.p_A - e.p_B) / e.distance) : away;
    if (d.distance == 0.0) d.p_A = e.p_A - step * away, d.p_B = e.p_B;
  }
  g.n_W = n;
  g.distance = d.distance - a.radius - b.radius;
  g.p_a_W = d.p_A - a.radius * n;
  g.p_b_W = d.p_B + b.radius * n;
  return g;
}

int pair_manifold(const Convex& a, const Pose& pa, const Convex& b, const Pose& pb,
                  const PairGap& g, double tol, std::array<Vec3, kMaxFeature>& out) {
  const Vec3& n = g.n_W;
  std::array<Vec3, kMaxFeature> fa, fb;
  const int na = touching_points(a, pa.q_WB.conjugate() * (-n), tol, fa);
  const int nb = touching_points(b, pb.q_WB.conjugate() * n, tol, fb);
  const Vec3 mid_shift = 0.5 * g.distance * n;  // from a's surface halfway to b's
  if (na <= 1 || nb <= 1) {
    out[0] = 0.5 * (g.p_a_W + g.p_b_W);
    return 1;
  }
  Vec3 t1, t2;
  plane_basis(n, t1, t2);
  P2 A[kMaxFeature], B[kMaxFeature], C[kMaxFeature];
  double level = 0.0;
  for (int i = 0; i < na; ++i) {
    const Vec3 p = pa.p_WBo + pa.q_WB * fa[i];
    A[i] = P2(t1.dot(p), t2.dot(p));
    level += n.dot(p) / na;
  }
  for (int i = 0; i < nb; ++i) {
    const Vec3 p = pb.p_WBo + pb.q_WB * fb[i];
    B[i] = P2(t1.dot(p), t2.dot(p));
  }
  order_ccw(A, na);
  order_ccw(B, nb);
  int k;
  if (nb >= 3) {
    k = clip_polygon(A, na, B, nb, C, kMaxFeature);
  } else if (na >= 3) {
    k = clip_polygon(B, nb, A, na, C, kMaxFeature);
  } else {
    // Two segments: their overlap along the first's direction (parallel lines), else the
    // closest points.
    const P2 d = A[1] - A[0];
    const double len2 = d.squaredNorm();
    double lo = 0.0, hi = 1.0;
    if (len2 > 0.0) {
      const double u0 = (B[0] - A[0]).dot(d) / len2, u1 = (B[1] - A[0]).dot(d) / len2;
      lo = std::max(0.0, std::min(u0, u1));
      hi = std::min(1.0, std::max(u0, u1));
    }
    if (lo <= hi && std::abs(cross2(d, B[1] - B[0])) <= 1e-9 * (d.norm() * (B[1] - B[0]).norm())) {
      C[0] = A[0] + lo * d;
      C[1] = A[0] + hi * d;
      k = lo < hi ? 2 : 1;
    } else {
      k = 0;
    }
  }
  if (k == 0) {
    out[0] = 0.5 * (g.p_a_W + g.p_b_W);
    return 1;
  }
  // Corners the clip repeats (two equal faces share theirs) kept once.
  int m = 0;
  const double same = 1e-9 * (1.0 + a.bounding_radius() + b.bounding_radius());
  for (int i = 0; i < k; ++i) {
    bool repeat = false;
    for (int j = 0; j < m && !repeat; ++j)
      repeat = (C[i] - C[j]).norm() <= same;
    if (!repeat) C[m++] = C[i];
  }
  for (int i = 0; i < m; ++i)
    out[i] = C[i].x() * t1 + C[i].y() * t2 + level * n - mid_shift;
  return m;
}

}  // namespace rigid::physics::contact
