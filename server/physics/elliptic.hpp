// Jacobi elliptic functions sn, cn, dn of real argument, parameter m = k^2 in [0, 1].
//
// Two evaluation paths, both accurate to a few ulp in absolute terms (what the free rotor needs:
// its momentum components are amplitude * function):
//  - |u| <= kJacobiSeriesMax: the Maclaurin series in u with coefficients polynomial in m
//    (Abramowitz & Stegun 16.22.1-3, extended to u^13 / u^14 and checked by
//    tests/physics/elliptic_test.cpp against the ODE sn' = cn dn, cn' = -sn dn, dn' = -m sn cn);
//  - otherwise the descending Landen transformation / arithmetic-geometric mean
//    (DLMF 22.20.ii, eqs. 22.20.4-22.20.5), valid for every real u.
#pragma once

namespace rigid::physics {

struct Jacobi {
  double sn = 0.0;
  double cn = 1.0;
  double dn = 1.0;
};

inline constexpr double kJacobiSeriesMax = 1.0 / 16.0;

// The series coefficients for one m, so that several arguments with the same m (the nodes of one
// free-rotor step) pay for the polynomials in m once. Only as many terms as arguments up to
// u_max need are formed: a free-rotor step at dt = 1 ms has |u| ~ 1e-3 and needs terms to u^5.
class JacobiSeries {
 public:
  explicit JacobiSeries(double m, double u_max = kJacobiSeriesMax);
  // Valid for |u| <= u_max (<= kJacobiSeriesMax); truncation error < 1e-19 (absolute).
  Jacobi operator()(double u) const;
  // sn, cn - 1, dn - 1: the departures from 1 to full relative accuracy, for updates of the form
  // x + (increment) whose round-off must stay relative to the increment.
  Jacobi departures(double u) const;

 private:
  int ns_ = 7, nc_ = 8;  // terms used
  double s_[7];          // sn: coefficient of u^(2i+1)
  double c_[8];          // cn: coefficient of u^(2i)
  double d_[8];          // dn: coefficient of u^(2i)
};

// sn, cn, dn(u | m) for any real u and m in [0, 1].
Jacobi jacobi(double u, double m);
// The same with the complementary parameter mc = k'^2 = 1 - m given separately: near m = 1 the
// functions at large u depend on k' to first order, and 1 - m rounded from m would lose it
// (m = 1 - 2.5e-7 carries k'^2 to only 9 digits). Pass mc when it is known more accurately.
Jacobi jacobi(double u, double m, double mc);

// Complete elliptic integral of the first kind K(m) (DLMF 19.8.5, by the AGM). +inf at m = 1.
double elliptic_k(double m);

// Carlson's symmetric integral R_F(x, y, z) (DLMF 19.16.1) by duplication (DLMF 19.36.i), for
// x, y, z >= 0 with at most one of them zero.
double carlson_rf(double x, double y, double z);

// Carlson's symmetric integral of the third kind R_J(x, y, z, p) (DLMF 19.16.2) for x, y, z >= 0
// with at most one of them zero and p > 0, by duplication (DLMF 19.36.ii; B. C. Carlson,
// "Numerical computation of real or complex elliptic integrals", Numer. Algorithms 10, 1995).
// Used with p > 0 only: the Cauchy principal value for p < 0 is not needed.
double carlson_rj(double x, double y, double z, double p);

// The incomplete integral of the first kind F(phi | m) for any real phi (DLMF 19.2.4), with the
// complement mc = 1 - m given separately (see jacobi): the inverse of the amplitude, so that
// sn(F(phi | m) | m) = sin(phi). Uses F = sin(phi) R_F(cos^2 phi, mc + m cos^2 phi, 1) (DLMF
// 19.25.5) and F(phi + n pi) = F(phi) + 2 n K.
double elliptic_f(double phi, double m, double mc);

}  // namespace rigid::physics
