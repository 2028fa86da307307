// The C++ side of tests/python/test_world.py's bit-for-bit comparison: runs a scene through
// rigid::physics::World (linked as rigidd and rigid-sim link it, not the Python module's copy)
// applying the operations given on the command line, and prints the state with 17 significant
// digits whenever asked, so that every double survives the trip through text.
//
//   python_world_dump SCENE [--integrator NAME] [--dt S] OP...
//   OP: step:N | clear | print
//       force:BODY:FX,FY,FZ:PX,PY,PZ:world|body    torque:BODY:TX,TY,TZ:world|body
//       impulse:BODY:JX,JY,JZ:PX,PY,PZ:world|body
// Output per print: one line per body, "STEP,NAME,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz".
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "physics/world.hpp"
#include "scene/scene.hpp"

namespace {

using rigid::physics::Frame;
using rigid::physics::Vec3;
using rigid::physics::World;

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> parts;
  std::stringstream in(s);
  std::string part;
  while (std::getline(in, part, sep))
    parts.push_back(part);
  return parts;
}

Vec3 vec(const std::string& s) {
  const auto p = split(s, ',');
  if (p.size() != 3) throw std::invalid_argument("not a vector: " + s);
  return {std::stod(p[0]), std::stod(p[1]), std::stod(p[2])};
}

Frame frame(const std::string& s) {
  if (s == "world") return Frame::kWorld;
  if (s == "body") return Frame::kBody;
  throw std::invalid_argument("not a frame: " + s);
}

int body(const World& w, const std::string& name) {
  const int id = w.find_body(name);
  if (id < 0) throw std::invalid_argument("no body " + name);
  return id;
}

void print(const World& w) {
  for (int i = 0; i < w.body_count(); ++i) {
    const rigid::physics::BodyState s = w.state(i);
    std::printf(
        "%lld,%s,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n",
        static_cast<long long>(w.step_count()), std::string(w.body_name(i)).c_str(), s.p_WBo.x(),
        s.p_WBo.y(), s.p_WBo.z(), s.q_WB.w(), s.q_WB.x(), s.q_WB.y(), s.q_WB.z(), s.v_WBo.x(),
        s.v_WBo.y(), s.v_WBo.z(), s.w_WB.x(), s.w_WB.y(), s.w_WB.z());
  }
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc < 2) {
      std::fprintf(stderr, "usage: python_world_dump SCENE [--integrator NAME] [--dt S] OP...\n");
      return 2;
    }
    const rigid::scene::Scene scene = rigid::scene::load_scene(argv[1]);
    rigid::physics::WorldSpec spec = scene.world;
    int i = 2;
    for (; i + 1 < argc; i += 2) {
      const std::string opt = argv[i];
      if (opt == "--integrator") {
        spec.integrator = argv[i + 1];
      } else if (opt == "--dt") {
        spec.dt = std::stod(argv[i + 1]);
      } else {
        break;
      }
    }
    World w(spec);
    for (; i < argc; ++i) {
      const auto op = split(argv[i], ':');
      if (op[0] == "step" && op.size() == 2) {
        w.step(std::stoll(op[1]));
      } else if (op[0] == "clear") {
        w.clear_applied();
      } else if (op[0] == "print") {
        print(w);
      } else if (op[0] == "force" && op.size() == 5) {
        w.add_force(body(w, op[1]), vec(op[2]), vec(op[3]), frame(op[4]));
      } else if (op[0] == "torque" && op.size() == 4) {
        w.add_torque(body(w, op[1]), vec(op[2]), frame(op[3]));
      } else if (op[0] == "impulse" && op.size() == 5) {
        w.apply_impulse(body(w, op[1]), vec(op[2]), vec(op[3]), frame(op[4]));
      } else {
        std::fprintf(stderr, "python_world_dump: bad operation '%s'\n", argv[i]);
        return 2;
      }
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "python_world_dump: %s\n", e.what());
    return 1;
  }
}
