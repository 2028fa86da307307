// Ours behind the peers' interface, so that peer_work_precision can time our integrators in the
// same process as the peers, interleaved with them, through the same accuracy and cost runs: the
// cost ratios of the report's headline then come from one run on one machine state. The world is
// exactly bench/work_precision's (hard_cases' world_spec); the only difference is one virtual
// call per step for the whole world, which is not per body.
#include <memory>
#include <stdexcept>

#include "peer_engine.hpp"

namespace rigid::bench::peers {

namespace {

class RigidWorld final : public PeerWorld {
 public:
  explicit RigidWorld(const physics::WorldSpec& spec) : world_(spec) {}
  void step() override { world_.step(); }
  // A body the World's guard froze (it diverged) reads as NaN: a blow-up, as for the peers.
  BodyState state(int i) const override {
    return world_.is_frozen(i) ? nan_state() : world_.state(i);
  }

 private:
  physics::World world_;
};

class RigidEngine final : public PeerEngine {
 public:
  std::string name() const override { return "rigid"; }
  std::string version() const override { return "rigid (this tree)"; }
  // Every integrator of ours; peer_work_precision --ours picks among them.
  std::vector<std::string> modes(const Case&) const override {
    std::vector<std::string> names;
    for (const auto& info : physics::all_integrators())
      names.emplace_back(info.name);
    return names;
  }
  std::unique_ptr<PeerWorld> make_world(const Case& c, const std::string& mode, double dt,
                                        int copies) const override {
    if (!physics::find_integrator(mode)) throw std::runtime_error("rigid: unknown mode " + mode);
    return std::make_unique<RigidWorld>(world_spec(c, mode, dt, copies));
  }
};

}  // namespace

std::unique_ptr<PeerEngine> make_rigid_engine() {
  return std::make_unique<RigidEngine>();
}

}  // namespace rigid::bench::peers
