// MuJoCo 2.2.2 driven on the hard cases (see bench/peers/README.md for what each mode does and
// why).
//
// The copies are laid out the cheapest way for each mode, as a user who measured would: one model
// of N free bodies with one mjData when MuJoCo's step is linear in N (Euler or RK4, nothing
// written to xfrc_applied, no actuators, no force callback), else one mjData per copy of a
// one-body model, because xfrc_applied, site actuators, applied forces and the implicit
// integrator cost O(N^2) per step in one model (bench/notes/peers.md; at N = 32 the shared model is
// ~1.4x cheaper than separate data under Euler and RK4, and 1.2x to 7x dearer in the other cases).
#include <mujoco/mujoco.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "peer_body.hpp"
#include "peer_engine.hpp"

namespace rigid::bench::peers {

namespace {

static_assert(sizeof(mjtNum) == sizeof(double), "MuJoCo's mjtNum must be double");

// mjtNums of mjData's stack per body: a one-body model uses ~500 at most (implicit), a 32-body
// one ~100 per body (RK4). MuJoCo's default is ~10 MB per mjData, which slows many small models
// 2-3x (bench/notes/peers.md).
constexpr int kStackPerBody = 4000;

enum class Integrator { kEuler, kRk4, kImplicit };

struct Mode {
  Integrator integrator = Integrator::kEuler;
  bool site = false;      // body-frame loads as site actuators (re-evaluated at every RK4 stage)
  bool damping = false;   // drag as the free joint's own damping instead of a user force
  bool callback = false;  // loads and drag from mjcb_passive, at every RK4 stage
};

Mode parse_mode(const std::string& name) {
  Mode m;
  std::string base = name;
  const auto strip = [&](const std::string& suffix) {
    if (base.size() > suffix.size() &&
        base.compare(base.size() - suffix.size(), suffix.size(), suffix) == 0) {
      base.resize(base.size() - suffix.size());
      return true;
    }
    return false;
  };
  m.site = strip("_site");
  m.damping = strip("_damping");
  m.callback = strip("_callback");
  if (base == "euler") {
    m.integrator = Integrator::kEuler;
  } else if (base == "rk4") {
    m.integrator = Integrator::kRk4;
  } else if (base == "implicit") {
    m.integrator = Integrator::kImplicit;
  } else {
    throw std::runtime_error("mujoco: unknown mode '" + name + "'");
  }
  return m;
}

const char* xml_name(Integrator i) {
  switch (i) {
    case Integrator::kEuler:
      return "Euler";
    case Integrator::kRk4:
      return "RK4";
    case Integrator::kImplicit:
      return "implicit";
  }
  return "";
}

// The loads of a world in callback mode, which mjcb_passive (global in MuJoCo) finds through the
// first mjtNum of each mjData's userdata.
struct StageLoads {
  std::vector<LoadSpec> loads;
  double c = 0, k = 0;
};
static_assert(sizeof(StageLoads*) <= sizeof(mjtNum));

// MuJoCo calls this from mj_passive, i.e. in every mj_forward and so at each of RK4's four
// stages, with that stage's kinematics: the loads are then evaluated where RK4 needs them, which
// xfrc_applied (held over the step) cannot do for a force whose lever arm turns with the body.
void stage_forces(const mjModel* m, mjData* d) {
  if (m->nuserdata < 1) return;
  const StageLoads* s = nullptr;
  std::memcpy(&s, d->userdata, sizeof s);
  if (!s) return;      // not a callback world, or MuJoCo reset the data after a divergence
  const int body = 1;  // callback worlds are one-body models (see MujocoWorld's layout)
  const Quat q = Quat(d->xquat[4], d->xquat[5], d->xquat[6], d->xquat[7]).normalized();
  const Vec3 x(d->xpos[3], d->xpos[4], d->xpos[5]);  // the centre of mass: body origin here
  for (const LoadSpec& l : s->loads) {
    const Vec3 f = l.frame == Frame::kWorld ? l.force : Vec3(q * l.force);
    const Vec3 t = l.torque_frame == Frame::kWorld ? l.torque : Vec3(q * l.torque);
    const Vec3 p = x + q * l.p_BoQ_B;
    mj_applyFT(m, d, f.data(), t.data(), p.data(), body, d->qfrc_passive);
  }
  // The free joint's dofs: v in the world frame, then w in the body frame.
  for (int i = 0; i < 3; ++i) {
    d->qfrc_passive[i] -= s->c * d->qvel[i];
    d->qfrc_passive[3 + i] -= s->k * d->qvel[3 + i];
  }
}

// MuJoCo prints warnings (and resets the body) when a state goes bad; the driver reads the
// warning counters instead, so the console stays readable during a sweep.
void quiet_warning(const char*) {}

// `bodies` free bodies, each the case's body (with sites for its body-frame loads in site mode).
std::string model_xml(const Case& c, const Mode& mode, double dt, int bodies) {
  const Vec3 I = principal_moments(c);
  const Vec3 g = gravity_of(c);
  std::ostringstream x, act;
  x.precision(17);  // every number (the step included) round-trips exactly
  act.precision(17);
  x << "<mujoco model=\"rigid_peer\">\n"
    << "  <size nstack=\"" << kStackPerBody * bodies << "\" nuserdata=\"" << (mode.callback ? 1 : 0)
    << "\"/>\n"
    << "  <option timestep=\"" << dt << "\" integrator=\"" << xml_name(mode.integrator)
    << "\" gravity=\"" << g.x() << ' ' << g.y() << ' ' << g.z() << "\"/>\n"
    << "  <worldbody>\n";
  for (int b = 0; b < bodies; ++b) {
    x << "    <body name=\"b" << b << "\">\n"
      << "      <joint type=\"free\"/>\n"
      << "      <inertial pos=\"0 0 0\" mass=\"" << c.body.mass << "\" diaginertia=\"" << I.x()
      << ' ' << I.y() << ' ' << I.z() << "\"/>\n";
    if (mode.site) {
      int k = 0;
      for (const LoadSpec& l : c.loads) {
        const Vec3 f = l.frame == Frame::kBody ? l.force : Vec3::Zero();
        const Vec3 t = l.torque_frame == Frame::kBody ? l.torque : Vec3::Zero();
        if (f.isZero() && t.isZero()) continue;
        // A site at the point, its frame the body frame: a motor's gear is the wrench it applies
        // there in that frame, times ctrl = 1. MuJoCo recomputes it at every RK4 stage.
        const std::string site = "s" + std::to_string(b) + "_" + std::to_string(k++);
        x << "      <site name=\"" << site << "\" pos=\"" << l.p_BoQ_B.x() << ' ' << l.p_BoQ_B.y()
          << ' ' << l.p_BoQ_B.z() << "\"/>\n";
        act << "    <motor site=\"" << site
            << "\" ctrllimited=\"false\" forcelimited=\"false\" gear=\"" << f.x() << ' ' << f.y()
            << ' ' << f.z() << ' ' << t.x() << ' ' << t.y() << ' ' << t.z() << "\"/>\n";
      }
    }
    x << "    </body>\n";
  }
  x << "  </worldbody>\n";
  if (!act.str().empty()) x << "  <actuator>\n" << act.str() << "  </actuator>\n";
  x << "</mujoco>\n";
  return x.str();
}

mjModel* compile(const std::string& xml) {
  // mjVFS holds fixed arrays of file names (megabytes): on the heap, not the stack.
  const auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  const char* file = "rigid_peer.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), file, static_cast<int>(xml.size())) != 0) {
    throw std::runtime_error("mujoco: cannot create the model in a VFS");
  }
  const int i = mj_findFileVFS(vfs.get(), file);
  std::memcpy(vfs->filedata[i], xml.data(), xml.size());
  char error[1000] = "";
  mjModel* m = mj_loadXML(file, vfs.get(), error, sizeof error);
  mj_deleteVFS(vfs.get());
  if (!m) throw std::runtime_error(std::string("mujoco: model rejected: ") + error + "\n" + xml);
  return m;
}

Quat quat_of(const mjtNum* q) {
  return Quat(q[0], q[1], q[2], q[3]).normalized();
}

class MujocoWorld final : public PeerWorld {
 public:
  MujocoWorld(const Case& c, const Mode& mode, double dt, int copies) {
    if (mode.callback) {
      stage_ = std::make_unique<StageLoads>(
          StageLoads{c.loads, c.body.linear_drag, c.body.angular_drag});
    }
    for (const LoadSpec& l : mode.callback ? std::vector<LoadSpec>{} : c.loads) {
      // In site mode the body-frame parts ride on actuators; the rest goes through xfrc_applied.
      LoadSpec x = l;
      if (mode.site && l.frame == Frame::kBody) x.force = Vec3::Zero();
      if (mode.site && l.torque_frame == Frame::kBody) x.torque = Vec3::Zero();
      if (!x.force.isZero() || !x.torque.isZero()) xfrc_loads_.push_back(x);
    }
    if (!mode.damping && !mode.callback) {
      c_ = c.body.linear_drag;
      k_ = c.body.angular_drag;
    }
    const bool xfrc = !xfrc_loads_.empty() || c_ > 0 || k_ > 0;
    const bool shared =
        mode.integrator != Integrator::kImplicit && !mode.site && !mode.callback && !xfrc;
    const int bodies = shared ? copies : 1;
    model_ = compile(model_xml(c, mode, dt, bodies));
    if (mode.damping) {
      // Translational dofs get c, rotational ones k: qfrc = -c v (v in the world frame) and
      // -k w_B, which is -k w in any frame. Per dof after compiling, since the XML gives one
      // damping for all six.
      for (int b = 0; b < bodies; ++b) {
        for (int i = 0; i < 3; ++i) {
          model_->dof_damping[6 * b + i] = c.body.linear_drag;
          model_->dof_damping[6 * b + 3 + i] = c.body.angular_drag;
        }
      }
    }
    const Quat q = c.body.q_WB.normalized();
    const Vec3 w_B = q.conjugate() * c.body.w_WB;
    for (int n = 0; n < copies; ++n) {
      if (n % bodies == 0) {
        mjData* d = mj_makeData(model_);
        if (!d) throw std::runtime_error("mujoco: mj_makeData failed");
        for (int a = 0; a < model_->nu; ++a) {
          d->ctrl[a] = 1.0;
        }
        if (stage_) {
          const StageLoads* p = stage_.get();
          std::memcpy(d->userdata, &p, sizeof p);
        }
        data_.push_back(d);
      }
      Copy copy;
      copy.data = static_cast<int>(data_.size()) - 1;
      copy.body = 1 + n % bodies;  // body 0 is the world
      const int joint = model_->body_jntadr[copy.body];
      copy.qpos = model_->jnt_qposadr[joint];
      copy.qvel = model_->jnt_dofadr[joint];
      // The free joint: qpos = (p, q as w x y z); qvel = (v in the world frame, w in the body
      // frame).
      mjData* d = data_.back();
      for (int i = 0; i < 3; ++i) {
        d->qpos[copy.qpos + i] = c.body.p_WBo[i];
        d->qvel[copy.qvel + i] = c.body.v_WBo[i];
        d->qvel[copy.qvel + 3 + i] = w_B[i];
      }
      d->qpos[copy.qpos + 3] = q.w();
      d->qpos[copy.qpos + 4] = q.x();
      d->qpos[copy.qpos + 5] = q.y();
      d->qpos[copy.qpos + 6] = q.z();
      copies_.push_back(copy);
    }
    diverged_.assign(data_.size(), false);
  }

  ~MujocoWorld() override {
    for (mjData* d : data_)
      mj_deleteData(d);
    mj_deleteModel(model_);
  }
  MujocoWorld(const MujocoWorld&) = delete;
  MujocoWorld& operator=(const MujocoWorld&) = delete;

  void step() override {
    if (!xfrc_loads_.empty() || c_ > 0 || k_ > 0) {
      for (const Copy& copy : copies_)
        apply_xfrc(copy);
    }
    for (std::size_t k = 0; k < data_.size(); ++k) {
      mj_step(model_, data_[k]);
      if (!diverged_[k]) diverged_[k] = diverged(data_[k]);
    }
  }

  BodyState state(int i) const override {
    const Copy& copy = copies_[i];
    BodyState s;
    if (diverged_[copy.data]) {
      const double nan = std::numeric_limits<double>::quiet_NaN();
      s.p_WBo.setConstant(nan);
      s.q_WB.coeffs().setConstant(nan);
      s.v_WBo.setConstant(nan);
      s.w_WB.setConstant(nan);
      return s;
    }
    const mjtNum* x = data_[copy.data]->qpos + copy.qpos;
    const mjtNum* v = data_[copy.data]->qvel + copy.qvel;
    s.p_WBo = Vec3(x[0], x[1], x[2]);
    s.q_WB = quat_of(x + 3);
    s.v_WBo = Vec3(v[0], v[1], v[2]);
    s.w_WB = s.q_WB * Vec3(v[3], v[4], v[5]);
    return s;
  }

 private:
  struct Copy {
    int data = 0;  // index into data_
    int body = 1;  // body id in the model
    int qpos = 0, qvel = 0;
  };

  // xfrc_applied is a world-frame force at the centre of mass plus a world-frame torque: a force
  // f at body point r becomes (f, (R r) x f), from the orientation at the start of the step
  // (MuJoCo holds it over the step, including the four RK4 stages).
  void apply_xfrc(const Copy& copy) const {
    mjData* d = data_[copy.data];
    const Quat q = quat_of(d->qpos + copy.qpos + 3);
    const mjtNum* v = d->qvel + copy.qvel;
    Vec3 f = Vec3::Zero(), t = Vec3::Zero();
    for (const LoadSpec& l : xfrc_loads_) {
      const Vec3 f_W = l.frame == Frame::kWorld ? l.force : Vec3(q * l.force);
      f += f_W;
      t += (q * l.p_BoQ_B).cross(f_W);
      t += l.torque_frame == Frame::kWorld ? l.torque : Vec3(q * l.torque);
    }
    f -= c_ * Vec3(v[0], v[1], v[2]);
    t -= k_ * (q * Vec3(v[3], v[4], v[5]));
    mjtNum* x = d->xfrc_applied + 6 * copy.body;
    for (int i = 0; i < 3; ++i) {
      x[i] = f[i];
      x[3 + i] = t[i];
    }
  }

  // MuJoCo resets a model whose qpos, qvel or qacc goes bad (non-finite or > 1e10) to its start
  // pose and counts a warning: either shows here as a divergence of every copy in that mjData.
  bool diverged(const mjData* d) const {
    if (d->warning[mjWARN_BADQPOS].number > 0 || d->warning[mjWARN_BADQVEL].number > 0 ||
        d->warning[mjWARN_BADQACC].number > 0) {
      return true;
    }
    for (int i = 0; i < model_->nq; ++i) {
      if (!std::isfinite(d->qpos[i])) return true;
    }
    for (int i = 0; i < model_->nv; ++i) {
      if (!std::isfinite(d->qvel[i])) return true;
    }
    return false;
  }

  mjModel* model_ = nullptr;
  std::vector<mjData*> data_;
  std::vector<Copy> copies_;
  std::vector<bool> diverged_;  // per mjData
  std::vector<LoadSpec> xfrc_loads_;
  double c_ = 0, k_ = 0;               // drag applied as a user force
  std::unique_ptr<StageLoads> stage_;  // callback mode
};

class MujocoEngine final : public PeerEngine {
 public:
  MujocoEngine() {
    mju_user_warning = quiet_warning;
    mjcb_passive = stage_forces;  // acts only on the models of callback worlds
  }

  std::string name() const override { return "mujoco"; }

  std::string version() const override {
    return std::string("MuJoCo ") + mj_versionString() + " (mjtNum double)";
  }

  std::vector<std::string> modes(const Case& c) const override {
    std::vector<std::string> m = {"euler", "rk4", "implicit"};
    if (has_body_frame_load(c)) {
      for (const char* i : {"euler", "rk4", "implicit"})
        m.push_back(std::string(i) + "_site");
    }
    if (has_drag(c)) {
      for (const char* i : {"euler", "rk4", "implicit"})
        m.push_back(std::string(i) + "_damping");
    }
    // Only RK4 evaluates forces inside the step: under Euler and implicit a callback would give
    // exactly what xfrc_applied gives.
    if (!c.loads.empty()) m.push_back("rk4_callback");
    return m;
  }

  std::unique_ptr<PeerWorld> make_world(const Case& c, const std::string& mode, double dt,
                                        int copies) const override {
    return std::make_unique<MujocoWorld>(c, parse_mode(mode), dt, copies);
  }
};

}  // namespace

std::unique_ptr<PeerEngine> make_mujoco_engine() {
  return std::make_unique<MujocoEngine>();
}

}  // namespace rigid::bench::peers
