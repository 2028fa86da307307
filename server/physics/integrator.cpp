#include "physics/integrator.hpp"

#include <array>

namespace rigid::physics {

namespace {

constexpr std::array<IntegratorInfo, 10> kIntegrators{{
    {IntegratorId::kHybrid4, "hybrid4", 4, true, true,
     "default: per body and per step, the exact free rotor for a body nothing turns, a cheap "
     "fourth-order composition (triple jump, closed-form or split drifts) for a loaded one"},
    {IntegratorId::kExactRotor4, "exact_rotor4", 4, true, true,
     "fourth-order composition of the exact-rotor splitting; exact for torque-free bodies at "
     "any step"},
    {IntegratorId::kExactRotor, "exact_rotor", 2, true, true,
     "kick-drift-kick with the exact free rotor (Jacobi elliptic functions) as drift"},
    {IntegratorId::kRk4, "rk4", 4, false, true,
     "classical Runge-Kutta on (x, v, q, w), loads re-evaluated at every stage"},
    {IntegratorId::kDlm, "dlm", 2, true, true,
     "kick-drift-kick, free rotor split into exact axis rotations (Dullweber-Leimkuhler-"
     "McLachlan 1997)"},
    {IntegratorId::kImplicitGyro, "implicit_gyro", 1, false, true,
     "explicit torque, implicit gyroscopic term by one Newton step (Catto, GDC 2015)"},
    {IntegratorId::kNotesSemiImplicitEuler, "games103", 1, false, false,
     "the course notes' scheme: semi-implicit Euler, w += dt I^-1 tau, q += [0, dt/2 w] q"},
    {IntegratorId::kNotesExplicitEuler, "notes_explicit_euler", 1, false, false,
     "course notes: explicit Euler translation, notes' rotation update"},
    {IntegratorId::kNotesMidpoint, "notes_midpoint", 2, false, false,
     "course notes: midpoint translation, notes' rotation update (no gyroscopic term)"},
    {IntegratorId::kNotesLeapfrog, "notes_leapfrog", 2, false, false,
     "course notes: leapfrog translation, notes' rotation update (no gyroscopic term)"},
}};

// Candidates measured against the listed ones (bench/forced_bench), reachable by name only.
constexpr std::array<IntegratorInfo, 1> kCandidates{{
    {IntegratorId::kHybrid4Suzuki, "hybrid4_suzuki", 4, true, true,
     "candidate: hybrid4 with Suzuki's five-stage composition"},
}};

}  // namespace

std::span<const IntegratorInfo> all_integrators() {
  return kIntegrators;
}

const IntegratorInfo* find_integrator(std::string_view name) {
  if (name == "notes_semi_implicit_euler") name = "games103";
  for (const auto& i : kIntegrators) {
    if (i.name == name) return &i;
  }
  for (const auto& i : kCandidates) {
    if (i.name == name) return &i;
  }
  return nullptr;
}

const IntegratorInfo& default_integrator() {
  return kIntegrators[0];
}

}  // namespace rigid::physics
