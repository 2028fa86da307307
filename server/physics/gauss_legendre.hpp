// Gauss-Legendre rules on [-1, 1] (Abramowitz & Stegun 25.4.29, Table 25.4): the exact free
// rotor's psi integral (free_rotor.cpp) on one panel (2, 3 or 4 nodes, by the step's phase
// increment) or on panels of the 6-point rule. Data only, no functions: the lanes kernels, built
// per instruction set, read the weights of the 2-, 3- and 4-node rules from here too (a cached
// plan keeps its phase increment X, not the n weights X w_i / 2: rotor_plans.hpp).
#pragma once

namespace rigid::physics::detail {

struct GaussLegendre {
  int n;
  double x[6];  // nodes, ascending
  double w[6];  // weights (0 past n)
};
constexpr GaussLegendre kGL2{2, {-0.57735026918962576, 0.57735026918962576}, {1.0, 1.0}};
constexpr GaussLegendre kGL3{3,
                             {-0.77459666924148338, 0.0, 0.77459666924148338},
                             {0.55555555555555556, 0.88888888888888889, 0.55555555555555556}};
constexpr GaussLegendre kGL4{
    4,
    {-0.86113631159405258, -0.33998104358485626, 0.33998104358485626, 0.86113631159405258},
    {0.34785484513745386, 0.65214515486254614, 0.65214515486254614, 0.34785484513745386}};
constexpr GaussLegendre kGL6{6,
                             {-0.93246951420315203, -0.66120938646626451, -0.23861918608319691,
                              0.23861918608319691, 0.66120938646626451, 0.93246951420315203},
                             {0.17132449237917035, 0.36076157304813861, 0.46791393457269105,
                              0.46791393457269105, 0.36076157304813861, 0.17132449237917035}};
// The single-panel rule of a cached plan by its node count n (2, 3 or 4; no rule for 0 and 1).
constexpr const GaussLegendre* kRotorRule[5] = {nullptr, nullptr, &kGL2, &kGL3, &kGL4};

}  // namespace rigid::physics::detail
