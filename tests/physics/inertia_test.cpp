// Principal decomposition, physical-validity check and solid-shape inertia.
#include "physics/inertia.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace rigid::physics {
namespace {

constexpr double kPi = std::numbers::pi;

Mat3 diag(double a, double b, double c) {
  return Vec3(a, b, c).asDiagonal();
}

// Relative difference of two tensors, in the max-entry norm.
double rel_diff(const Mat3& a, const Mat3& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

TEST(PrincipalInertia, DiagonalAscendingIsIdentity) {
  const PrincipalInertia p = principal_inertia(diag(1, 2, 3));
  EXPECT_EQ(p.moments, Vec3(1, 2, 3));
  EXPECT_EQ(p.q_BP.coeffs(), Quat::Identity().coeffs());
}

TEST(PrincipalInertia, DiagonalUnsortedIsSortedAndProper) {
  const Mat3 I = diag(3, 1, 2);
  const PrincipalInertia p = principal_inertia(I);
  EXPECT_EQ(p.moments, Vec3(1, 2, 3));
  const Mat3 R = p.q_BP.toRotationMatrix();
  EXPECT_NEAR(R.determinant(), 1.0, 1e-15);
  EXPECT_LT(rel_diff(R * p.moments.asDiagonal() * R.transpose(), I), 1e-15);
}

TEST(PrincipalInertia, RotatedTensorRecoversMomentsAndFrame) {
  const Vec3 moments(0.7, 1.9, 2.3);
  // A few rotations, including ones that make an eigen-solver return a reflected basis.
  const Quat rotations[] = {
      Quat(Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized())),
      Quat(Eigen::AngleAxisd(2.9, Vec3(-1, 0.5, 0.2).normalized())),
      Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ())),
      Quat(0.1, -0.7, 0.3, 0.64).normalized(),
  };
  for (const Quat& q : rotations) {
    const Mat3 R = q.toRotationMatrix();
    const Mat3 I_B = R * moments.asDiagonal() * R.transpose();
    const PrincipalInertia p = principal_inertia(I_B);
    EXPECT_LT((p.moments - moments).cwiseAbs().maxCoeff(), 1e-14);
    const Mat3 R_BP = p.q_BP.toRotationMatrix();
    EXPECT_NEAR(R_BP.determinant(), 1.0, 1e-14);
    EXPECT_LT(rel_diff(R_BP * p.moments.asDiagonal() * R_BP.transpose(), I_B), 1e-14);
    // Distinct moments fix each principal axis up to sign.
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(std::abs(R_BP.col(k).dot(R.col(k))), 1.0, 1e-13) << "axis " << k;
    }
    EXPECT_NEAR(p.q_BP.norm(), 1.0, 1e-15);
  }
}

TEST(PrincipalInertia, RepeatedMomentsGiveAValidFrame) {
  const Mat3 R = Quat(Eigen::AngleAxisd(1.1, Vec3(1, -1, 2).normalized())).toRotationMatrix();
  const Mat3 I_B = R * diag(2, 2, 3) * R.transpose();
  const PrincipalInertia p = principal_inertia(I_B);
  EXPECT_LT((p.moments - Vec3(2, 2, 3)).cwiseAbs().maxCoeff(), 1e-14);
  const Mat3 R_BP = p.q_BP.toRotationMatrix();
  EXPECT_NEAR(R_BP.determinant(), 1.0, 1e-14);
  EXPECT_LT(rel_diff(R_BP * p.moments.asDiagonal() * R_BP.transpose(), I_B), 1e-14);
}

TEST(InertiaProblem, AcceptsValidTensors) {
  EXPECT_EQ(inertia_problem(diag(1, 2, 3)), "");
  EXPECT_EQ(inertia_problem(diag(1, 1, 2)), "");  // the flat limit (a lamina): equality holds
  const Mat3 R = Quat(Eigen::AngleAxisd(0.4, Vec3(1, 1, 0).normalized())).toRotationMatrix();
  EXPECT_EQ(inertia_problem(R * diag(1, 2, 3) * R.transpose()), "");
}

TEST(InertiaProblem, RejectsNonFinite) {
  Mat3 I = diag(1, 2, 3);
  I(1, 2) = I(2, 1) = std::nan("");
  const std::string why = inertia_problem(I);
  EXPECT_NE(why.find("non-finite"), std::string::npos) << why;
  EXPECT_NE(why.find("nan"), std::string::npos) << why;
}

TEST(InertiaProblem, RejectsAsymmetric) {
  Mat3 I = diag(1, 2, 3);
  I(0, 1) = 0.1;
  const std::string why = inertia_problem(I);
  EXPECT_NE(why.find("not symmetric"), std::string::npos) << why;
  EXPECT_NE(why.find("0.1"), std::string::npos) << why;
  // Within 1e-12 relative it is accepted.
  I(0, 1) = 1e-13;
  EXPECT_EQ(inertia_problem(I), "");
}

TEST(InertiaProblem, RejectsNotPositiveDefinite) {
  EXPECT_NE(inertia_problem(diag(1, 2, -3)).find("not positive definite"), std::string::npos);
  EXPECT_NE(inertia_problem(diag(0, 1, 1)).find("not positive definite"), std::string::npos);
  EXPECT_NE(inertia_problem(Mat3::Zero()).find("not positive definite"), std::string::npos);
  // Positive diagonal, indefinite overall: eigenvalues 1 +- 2.
  Mat3 I = diag(1, 1, 1);
  I(0, 1) = I(1, 0) = 2;
  const std::string why = inertia_problem(I);
  EXPECT_NE(why.find("not positive definite"), std::string::npos) << why;
  EXPECT_NE(why.find("-1"), std::string::npos) << why;
}

TEST(InertiaProblem, RejectsTriangleInequality) {
  const std::string why = inertia_problem(diag(1, 1, 3));
  EXPECT_NE(why.find("triangle inequality"), std::string::npos) << why;
  EXPECT_NE(why.find("(1, 1, 3)"), std::string::npos) << why;
  // Just inside / outside the 1e-12 relative tolerance.
  EXPECT_EQ(inertia_problem(diag(1, 1, 2 * (1 + 0.5e-12))), "");
  EXPECT_NE(inertia_problem(diag(1, 1, 2 * (1 + 4e-12))), "");
}

TEST(Shape, Volumes) {
  EXPECT_DOUBLE_EQ(shape_volume({ShapeKind::kBox, Vec3(1, 2, 3)}), 6.0);
  EXPECT_DOUBLE_EQ(shape_volume({ShapeKind::kSphere, Vec3(2, 0, 0)}), 32.0 / 3.0 * kPi);
  EXPECT_DOUBLE_EQ(shape_volume({ShapeKind::kCylinder, Vec3(2, 0, 3)}), 12.0 * kPi);
  EXPECT_DOUBLE_EQ(shape_volume({ShapeKind::kCapsule, Vec3(1, 0, 3)}), 3.0 * kPi + 4.0 / 3 * kPi);
  EXPECT_DOUBLE_EQ(shape_volume({ShapeKind::kEllipsoid, Vec3(1, 2, 3)}), 8.0 * kPi);
}

TEST(Shape, ClosedFormInertia) {
  // Box 1 x 2 x 3, m = 12: I = (2^2 + 3^2, 1^2 + 3^2, 1^2 + 2^2).
  EXPECT_LT(rel_diff(shape_inertia({ShapeKind::kBox, Vec3(1, 2, 3)}, 12.0), diag(13, 10, 5)),
            1e-15);
  // Sphere r = 2, m = 5: 2/5 * 5 * 4 = 8.
  EXPECT_LT(rel_diff(shape_inertia({ShapeKind::kSphere, Vec3(2, 0, 0)}, 5.0), diag(8, 8, 8)),
            1e-15);
  // Cylinder r = 1, L = 2, m = 12: axial 6, transverse (3 + 4) = 7.
  EXPECT_LT(rel_diff(shape_inertia({ShapeKind::kCylinder, Vec3(1, 0, 2)}, 12.0), diag(7, 7, 6)),
            1e-15);
  // Ellipsoid (1, 2, 3), m = 5: (4 + 9, 1 + 9, 1 + 4).
  EXPECT_LT(rel_diff(shape_inertia({ShapeKind::kEllipsoid, Vec3(1, 2, 3)}, 5.0), diag(13, 10, 5)),
            1e-15);
}

TEST(Shape, CapsuleClosedForm) {
  // Independent form: with m_c, m_h the cylinder and total hemisphere masses,
  // I_zz = m_c r^2/2 + 2/5 m_h r^2, I_xx = m_c (3r^2 + L^2)/12 + m_h (2/5 r^2 + L^2/4 + 3 L r/8).
  const double r = 0.5, L = 2.0, m = 3.0;
  const double vc = kPi * r * r * L, vh = 4.0 / 3 * kPi * r * r * r;
  const double mc = m * vc / (vc + vh), mh = m - mc;
  const double zz = mc * r * r / 2 + 0.4 * mh * r * r;
  const double xx = mc * (3 * r * r + L * L) / 12 + mh * (0.4 * r * r + L * L / 4 + 3 * L * r / 8);
  EXPECT_LT(rel_diff(shape_inertia({ShapeKind::kCapsule, Vec3(r, 0, L)}, m), diag(xx, xx, zz)),
            1e-14);
}

TEST(Shape, CapsuleTendsToSphereAsLengthVanishes) {
  const Mat3 sphere = shape_inertia({ShapeKind::kSphere, Vec3(0.7, 0, 0)}, 2.0);
  EXPECT_LT(rel_diff(shape_inertia({ShapeKind::kCapsule, Vec3(0.7, 0, 0)}, 2.0), sphere), 1e-15);
  double previous = 1.0;
  for (double L : {1e-2, 1e-4, 1e-6}) {
    const double e = rel_diff(shape_inertia({ShapeKind::kCapsule, Vec3(0.7, 0, L)}, 2.0), sphere);
    EXPECT_LT(e, 2.0 * L / 0.7) << "L = " << L;  // first order in L / r
    EXPECT_LT(e, previous);
    previous = e;
  }
}

TEST(Shape, CapsuleTendsToCylinderAsRadiusVanishes) {
  double previous = 1.0;
  for (double r : {1e-2, 1e-4, 1e-6}) {
    const Mat3 cyl = shape_inertia({ShapeKind::kCylinder, Vec3(r, 0, 1.0)}, 2.0);
    const Mat3 cap = shape_inertia({ShapeKind::kCapsule, Vec3(r, 0, 1.0)}, 2.0);
    // Compare each moment relatively: the axial one is tiny next to the transverse ones.
    const double e =
        ((cap.diagonal() - cyl.diagonal()).array() / cyl.diagonal().array()).abs().maxCoeff();
    EXPECT_LT(e, 5.0 * r) << "r = " << r;  // first order in r / L
    EXPECT_LT(e, previous);
    previous = e;
  }
}

TEST(Shape, ShapesSatisfyTheTriangleInequality) {
  for (const Shape& s :
       {Shape{ShapeKind::kBox, Vec3(1e-3, 1, 2)}, Shape{ShapeKind::kCylinder, Vec3(1, 0, 1e-3)},
        Shape{ShapeKind::kCapsule, Vec3(1e-3, 0, 5)},
        Shape{ShapeKind::kEllipsoid, Vec3(3, 2, 1e-3)}}) {
    EXPECT_EQ(inertia_problem(shape_inertia(s, 1.0)), "");
  }
}

}  // namespace
}  // namespace rigid::physics
