// The integrators a scene can choose by name, and what each promises.
#pragma once

#include <span>
#include <string_view>

namespace rigid::physics {

enum class IntegratorId {
  kNotesExplicitEuler,
  kNotesSemiImplicitEuler,  // the course notes' full scheme ("games103")
  kNotesMidpoint,
  kNotesLeapfrog,
  kImplicitGyro,
  kRk4,
  kDlm,
  kExactRotor,
  kExactRotor4,
  kHybrid4,
  kHybrid4Suzuki,  // a candidate, not listed: hybrid4 with Suzuki's five stages
};

struct IntegratorInfo {
  IntegratorId id;
  std::string_view name;
  int order;        // global order of accuracy on smooth problems
  bool symplectic;  // for conservative loads
  bool gyroscopic;  // models the w x Iw term (false: right only for equal principal moments)
  std::string_view summary;
};

// Every integrator, in the order --list-integrators prints them.
std::span<const IntegratorInfo> all_integrators();
// nullptr when unknown. Accepts the aliases listed in docs/physics.md ("games103").
const IntegratorInfo* find_integrator(std::string_view name);
const IntegratorInfo& default_integrator();

}  // namespace rigid::physics
