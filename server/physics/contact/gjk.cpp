#include "physics/contact/gjk.hpp"

#include <algorithm>
#include <cmath>

namespace rigid::physics::contact {

namespace {

// A vertex of the simplex: a point of A - B and the support points of A and B it came from.
struct Vertex {
  Vec3 w, a, b;
};

// The simplex and the barycentric weights of its point closest to the origin.
struct Simplex {
  Vertex v[4];
  double lambda[4] = {1.0, 0.0, 0.0, 0.0};
  int n = 0;

  Vec3 point() const {
    Vec3 p = Vec3::Zero();
    for (int i = 0; i < n; ++i)
      p += lambda[i] * v[i].w;
    return p;
  }
  void witnesses(Vec3& pa, Vec3& pb) const {
    pa.setZero();
    pb.setZero();
    for (int i = 0; i < n; ++i) {
      pa += lambda[i] * v[i].a;
      pb += lambda[i] * v[i].b;
    }
  }
  // Keeps the listed vertices with their weights.
  void keep(std::initializer_list<std::pair<int, double>> kept) {
    Vertex nv[4];
    double nl[4];
    int k = 0;
    for (const auto& [i, l] : kept) {
      nv[k] = v[i];
      nl[k] = l;
      ++k;
    }
    for (int i = 0; i < k; ++i) {
      v[i] = nv[i];
      lambda[i] = nl[i];
    }
    n = k;
  }
};

// Closest point of segment (v0, v1) to the origin.
void closest_segment(Simplex& s) {
  const Vec3 a = s.v[0].w, b = s.v[1].w;
  const Vec3 ab = b - a;
  const double t = -a.dot(ab), d = ab.squaredNorm();
  if (t <= 0.0 || d == 0.0) return s.keep({{0, 1.0}});
  if (t >= d) return s.keep({{1, 1.0}});
  const double u = t / d;
  s.keep({{0, 1.0 - u}, {1, u}});
}

// Closest point of triangle (v0, v1, v2) to the origin (Ericson 5.1.5).
void closest_triangle(Simplex& s) {
  const Vec3 a = s.v[0].w, b = s.v[1].w, c = s.v[2].w;
  const Vec3 ab = b - a, ac = c - a, ap = -a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return s.keep({{0, 1.0}});
  const Vec3 bp = -b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return s.keep({{1, 1.0}});
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);
    return s.keep({{0, 1.0 - v}, {1, v}});
  }
  const Vec3 cp = -c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return s.keep({{2, 1.0}});
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);
    return s.keep({{0, 1.0 - w}, {2, w}});
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return s.keep({{1, 1.0 - w}, {2, w}});
  }
  const double denom = va + vb + vc;
  if (denom == 0.0) return closest_segment(s);  // degenerate: a line
  const double v = vb / denom, w = vc / denom;
  s.keep({{0, 1.0 - v - w}, {1, v}, {2, w}});
}

// Closest point of tetrahedron (v0..v3) to the origin (Ericson 5.1.6): the best of the faces the
// origin lies outside of; inside all of them, the origin itself (the cores touch). A flat
// tetrahedron (four coplanar points: two faces meeting face to face give them) has no inside: the
// best of its faces.
bool closest_tetrahedron(Simplex& s) {
  const int faces[4][4] = {{0, 1, 2, 3}, {0, 2, 3, 1}, {0, 3, 1, 2}, {1, 3, 2, 0}};
  const Vec3 a = s.v[0].w;
  const Vec3 ab = s.v[1].w - a, ac = s.v[2].w - a, ad = s.v[3].w - a;
  const double volume = ab.cross(ac).dot(ad);
  const double scale = ab.norm() * ac.norm() * ad.norm();
  const bool flat = std::abs(volume) <= 1e-12 * scale;
  double best = INFINITY;
  Simplex best_s;
  bool outside = false;
  for (const auto& f : faces) {
    const Vec3 p = s.v[f[0]].w;
    const Vec3 n = (s.v[f[1]].w - p).cross(s.v[f[2]].w - p);
    const double so = -p.dot(n), sd = (s.v[f[3]].w - p).dot(n);
    if (!flat && so * sd >= 0.0) continue;  // the origin is on the tetrahedron's side
    outside = true;
    Simplex t;
    t.v[0] = s.v[f[0]], t.v[1] = s.v[f[1]], t.v[2] = s.v[f[2]];
    t.n = 3;
    closest_triangle(t);
    const double d = t.point().squaredNorm();
    if (d < best) best = d, best_s = t;
  }
  if (!outside) return false;
  s = best_s;
  return true;
}

}  // namespace

CoreDistance core_distance(const Placed& a, const Placed& b, double rel_tol) {
  const auto support = [&](const Vec3& u) {
    Vertex v;
    v.a = a.support_W(u);
    v.b = b.support_W(-u);
    v.w = v.a - v.b;
    return v;
  };
  Simplex s;
  s.v[0] = support(b.p_W - a.p_W);
  s.n = 1;
  CoreDistance out;
  Vec3 v = s.v[0].w;
  constexpr int kMaxIterations = 128;
  for (int it = 0; it < kMaxIterations; ++it) {
    out.iterations = it + 1;
    const double vv = v.squaredNorm();
    if (vv == 0.0) break;  // touching cores
    const Vertex w = support(-v);
    // |v|^2 - v.w bounds |v|^2 - distance |v| from above: v.w / |v| is a lower bound of the
    // distance, |v| an upper one.
    if (vv - v.dot(w.w) <= rel_tol * vv) break;
    // A vertex already in the simplex: no progress is possible (round-off).
    bool repeated = false;
    for (int i = 0; i < s.n; ++i)
      repeated = repeated || s.v[i].w == w.w;
    if (repeated) break;
    const Simplex before = s;
    s.v[s.n++] = w;
    if (s.n == 2) {
      closest_segment(s);
    } else if (s.n == 3) {
      closest_triangle(s);
    } else if (!closest_tetrahedron(s)) {
      v.setZero();
      break;
    }
    const Vec3 nv = s.point();
    if (nv.squaredNorm() >= vv) {  // no longer decreasing: converged to round-off
      s = before;
      break;
    }
    v = nv;
  }
  s.witnesses(out.p_A, out.p_B);
  out.distance = v.norm();
  return out;
}

}  // namespace rigid::physics::contact
