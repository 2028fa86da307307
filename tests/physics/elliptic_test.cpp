// Jacobi elliptic functions: identities, the ODE they solve, limits and special values.
#include "physics/elliptic.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace rigid::physics {
namespace {

const double kParams[] = {0.0, 1e-12, 0.1, 0.5, 0.9, 0.999, 1.0 - 1e-12, 1.0};
const double kArgs[] = {-7.3,   -0.5,   -0.0625, -1e-3, 0.0, 1e-6, 0.01,
                        0.0625, 0.0626, 0.3,     1.0,   2.5, 10.0, 33.0};

TEST(Jacobi, SatisfiesTheQuadraticIdentities) {
  for (double m : kParams) {
    for (double u : kArgs) {
      const Jacobi e = jacobi(u, m);
      EXPECT_NEAR(e.sn * e.sn + e.cn * e.cn, 1.0, 4e-16) << "m=" << m << " u=" << u;
      EXPECT_NEAR(e.dn * e.dn + m * e.sn * e.sn, 1.0, 4e-16) << "m=" << m << " u=" << u;
    }
  }
}

// sn' = cn dn, cn' = -sn dn, dn' = -m sn cn, checked by a fourth-order central difference: this is
// what pins down the series coefficients and the Landen recursion.
TEST(Jacobi, SolvesItsDifferentialEquations) {
  const double d = 1e-3;
  for (double m : kParams) {
    for (double u : kArgs) {
      const auto diff = [&](auto f) {
        return (-f(jacobi(u + 2 * d, m)) + 8 * f(jacobi(u + d, m)) - 8 * f(jacobi(u - d, m)) +
                f(jacobi(u - 2 * d, m))) /
               (12 * d);
      };
      const Jacobi e = jacobi(u, m);
      EXPECT_NEAR(diff([](const Jacobi& j) { return j.sn; }), e.cn * e.dn, 1e-10) << m << " " << u;
      EXPECT_NEAR(diff([](const Jacobi& j) { return j.cn; }), -e.sn * e.dn, 1e-10) << m << " " << u;
      EXPECT_NEAR(diff([](const Jacobi& j) { return j.dn; }), -m * e.sn * e.cn, 1e-10)
          << m << " " << u;
    }
  }
}

TEST(Jacobi, SeriesAndLandenAgreeAtTheirBoundary) {
  const double below = kJacobiSeriesMax, above = std::nextafter(kJacobiSeriesMax, 1.0);
  for (double m : kParams) {
    const Jacobi a = jacobi(below, m), b = jacobi(above, m);
    EXPECT_NEAR(a.sn, b.sn, 3e-16) << m;
    EXPECT_NEAR(a.cn, b.cn, 3e-16) << m;
    EXPECT_NEAR(a.dn, b.dn, 3e-16) << m;
  }
}

TEST(Jacobi, ReducesToCircularAndHyperbolicFunctions) {
  for (double u : kArgs) {
    const Jacobi c = jacobi(u, 0.0);
    EXPECT_NEAR(c.sn, std::sin(u), 1e-15);
    EXPECT_NEAR(c.cn, std::cos(u), 1e-15);
    EXPECT_EQ(c.dn, 1.0);
    const Jacobi h = jacobi(u, 1.0);
    EXPECT_NEAR(h.sn, std::tanh(u), 1e-15);
    EXPECT_NEAR(h.cn, 1.0 / std::cosh(u), 1e-15);
    EXPECT_NEAR(h.dn, 1.0 / std::cosh(u), 1e-15);
  }
}

TEST(Jacobi, QuarterPeriodValues) {
  // The lemniscatic case: K(1/2) = Gamma(1/4)^2 / (4 sqrt(pi)) = 1.8540746773013719.
  EXPECT_NEAR(elliptic_k(0.5), 1.8540746773013719, 1e-15);
  EXPECT_NEAR(elliptic_k(0.0), std::numbers::pi / 2, 1e-15);
  for (double m : {0.1, 0.5, 0.9, 0.999999}) {
    const double K = elliptic_k(m);
    const Jacobi e = jacobi(K, m);
    EXPECT_NEAR(e.sn, 1.0, 1e-14) << m;
    EXPECT_NEAR(e.cn, 0.0, 1e-7) << m;  // cn ~ sqrt(1 - sn^2): a quadratic zero
    EXPECT_NEAR(e.dn, std::sqrt(1.0 - m), 1e-9) << m;
    const Jacobi p = jacobi(4 * K + 0.3, m), q = jacobi(0.3, m);  // period 4K
    EXPECT_NEAR(p.sn, q.sn, 1e-13) << m;
    EXPECT_NEAR(p.cn, q.cn, 1e-13) << m;
  }
}

TEST(Jacobi, SeriesEvaluatorMatchesTheFunction) {
  for (double m : kParams) {
    const JacobiSeries s(m);
    for (double u : {-0.0625, -0.01, 0.0, 0.003, 0.05}) {
      const Jacobi a = s(u), b = jacobi(u, m);
      EXPECT_EQ(a.sn, b.sn);
      EXPECT_EQ(a.cn, b.cn);
      EXPECT_EQ(a.dn, b.dn);
    }
  }
}

// R_J from its definition, (3/2) int_0^inf dt / ((t + p) sqrt((t + x)(t + y)(t + z))), with
// t = tau^2 (regular where an argument is zero) and tau = v / (1 - v), by composite 8-point
// Gauss-Legendre in long double: an oracle independent of the duplication algorithm.
double rj_by_quadrature(double x, double y, double z, double p) {
  static constexpr long double kX[4] = {0.18343464249564980494L, 0.52553240991632898582L,
                                        0.79666647741362673959L, 0.96028985649753623168L};
  static constexpr long double kW[4] = {0.36268378337836198297L, 0.31370664587788728734L,
                                        0.22238103445337447054L, 0.10122853629037625915L};
  const auto f = [&](long double v) {
    const long double tau = v / (1.0L - v), t = tau * tau;
    const long double dtau = 1.0L / ((1.0L - v) * (1.0L - v));
    return 2.0L * tau * dtau / ((t + p) * std::sqrt((t + x) * (t + y) * (t + z)));
  };
  const int panels = 4000;
  long double sum = 0.0L;
  for (int k = 0; k < panels; ++k) {
    const long double mid = (k + 0.5L) / panels, half = 0.5L / panels;
    for (int i = 0; i < 4; ++i)
      sum += half * kW[i] * (f(mid - half * kX[i]) + f(mid + half * kX[i]));
  }
  return static_cast<double>(1.5L * sum);
}

TEST(Carlson, RjAgreesWithItsDefiningIntegral) {
  const double args[][4] = {{0.0, 1.0, 2.0, 3.0}, {2.0, 3.0, 4.0, 5.0},  {1.0, 1.0, 1.0, 1.0},
                            {0.0, 0.3, 1.0, 7.5}, {0.49, 0.02, 1.0, 65}, {0.9, 0.1, 1.0, 1.01},
                            {4.0, 4.0, 4.0, 0.2}, {0.0, 1e-6, 1.0, 2.0}};
  for (const auto& a : args) {
    const double want = rj_by_quadrature(a[0], a[1], a[2], a[3]);
    EXPECT_NEAR(carlson_rj(a[0], a[1], a[2], a[3]), want, 1e-14 * want)
        << a[0] << ", " << a[1] << ", " << a[2] << ", " << a[3];
  }
}

TEST(Carlson, RjSpecialValues) {
  // R_J(x, x, x, x) = x^-3/2; homogeneity of degree -3/2; R_J(x, y, y, y) = R_D(x, y, y).
  EXPECT_NEAR(carlson_rj(2.0, 2.0, 2.0, 2.0), std::pow(2.0, -1.5), 1e-16);
  const double r = carlson_rj(0.3, 1.2, 2.0, 0.7);
  EXPECT_NEAR(carlson_rj(0.3 * 9, 1.2 * 9, 2.0 * 9, 0.7 * 9), r / 27.0, 1e-16 * r);
  // Pi(n; pi/2 | 0) = pi / (2 sqrt(1 - n)) for n < 1 (DLMF 19.6.3), with
  // Pi(n; pi/2 | m) = K(m) + (n / 3) R_J(0, 1 - m, 1, 1 - n) (DLMF 19.25.14).
  for (double n : {-50.0, -2.0, -0.3, 0.4}) {
    const double k = carlson_rf(0.0, 1.0, 1.0), t = n / 3.0 * carlson_rj(0.0, 1.0, 1.0, 1.0 - n);
    // For n << 0 the two terms cancel: the bound is relative to their sizes, not to the sum.
    EXPECT_NEAR(k + t, std::numbers::pi / (2.0 * std::sqrt(1.0 - n)), 2e-16 * (k + std::abs(t)))
        << n;
  }
}

}  // namespace
}  // namespace rigid::physics
