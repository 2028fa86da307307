// rigid-sim: runs a scene in batch (no real time, no network) and reports drift and cost, or
// replays a journal. Wiring only: the work is in sim_options (command line), sim_run (run and
// report) and the replay (common/replay.hpp, --replay).
#include <exception>
#include <iostream>
#include <string_view>
#include <vector>

#include "common/replay.hpp"
#include "scene/scene.hpp"
#include "sim/sim_options.hpp"
#include "sim/sim_run.hpp"

int main(int argc, char** argv) {
  using namespace rigid;
  const std::vector<std::string_view> args(argv + 1, argv + argc);
  try {
    const sim::SimOptions options = sim::parse_options(args);
    if (options.help) {
      std::cout << sim::usage();
      return 0;
    }
    if (options.list_integrators) {
      sim::print_integrators(std::cout);
      return 0;
    }
    if (options.replay) {
      const common::ReplayReport report =
          common::replay({*options.replay, options.scene, options.csv, options.contacts_csv});
      for (const std::string& w : report.warnings)
        std::cerr << "rigid-sim: warning: " << w << '\n';
      common::print_replay(std::cout, report);
      return report.exit_status();
    }
    const scene::Scene scene = scene::load_scene(options.scene);
    for (const std::string& w : scene.warnings)
      std::cerr << w << '\n';
    const sim::RunSummary summary = sim::run(scene, options);
    sim::print_summary(std::cout, summary);
    return 0;
  } catch (const sim::UsageError& e) {
    std::cerr << "rigid-sim: " << e.what() << '\n';
    return 2;
  } catch (const common::SceneMismatch& e) {
    std::cerr << "rigid-sim: " << e.what() << '\n';
    return 2;
  } catch (const scene::SceneError& e) {
    std::cerr << e.what() << '\n';
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "rigid-sim: " << e.what() << '\n';
    return 1;
  }
}
