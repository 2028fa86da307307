// MuJoCo 2.2.2 on the contact cases (README.md, "Contacts": the settings and why). Each copy is its
// own mjData of a one-body model (a free body over a plane geom): MuJoCo's constraint solver works
// on all of a model's contacts together, so one model of N bodies would make every step a problem
// N times the size, and no user with independent bodies would write it that way.
#include <mujoco/mujoco.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "contact_engine.hpp"

namespace rigid::bench::peers {

namespace {

static_assert(sizeof(mjtNum) == sizeof(double), "MuJoCo's mjtNum must be double");

// MuJoCo has no restitution coefficient: its contact is a damped spring on the penetration. In
// solref's direct form (-k, -b) the spring is k = w^2, b = 2 zeta w; a linear spring-damper
// returns e = exp(-zeta pi / sqrt(1 - zeta^2)) of the approach speed, so zeta =
// -ln e / sqrt(pi^2 + ln^2 e) (1 for e = 0: critical damping). w = 0.5 / dt: the stiffest
// spring MuJoCo resolves (its time constant 1 / w = 2 dt, the documented lower limit).
std::string solref(double e, double dt) {
  const double w = 0.5 / dt;
  double zeta = 1.0;
  if (e > 0) {
    const double l = std::log(e);
    zeta = -l / std::sqrt(std::numbers::pi * std::numbers::pi + l * l);
  }
  std::ostringstream s;
  s.precision(17);
  s << -(w * w) << ' ' << -(2 * zeta * w);
  return s.str();
}

// Contact parameters on both geoms (MuJoCo mixes the two sides' solref and solimp and takes the
// larger friction: equal sides give exactly these). solimp flat: the impedance does not vary with
// the penetration. margin 0, gap 0: a contact exists only once the shapes overlap.
std::string contact_params(const ContactCase& c, double dt) {
  std::ostringstream s;
  s.precision(17);
  s << "condim=\"3\" friction=\"" << c.friction << " 0.005 0.0001\" solref=\""
    << solref(c.restitution, dt) << "\" solimp=\"0.99 0.99 0.001\" margin=\"0\" gap=\"0\"";
  return s.str();
}

std::string model_xml(const ContactCase& c, bool rk4, double dt) {
  const Vec3 I = principal_moments(c);
  const Quat q = c.start.q_WB.normalized();
  const std::string params = contact_params(c, dt);
  std::ostringstream x;
  x.precision(17);
  x << "<mujoco model=\"rigid_contact\">\n"
    << "  <size nstack=\"20000\"/>\n"
    << "  <option timestep=\"" << dt << "\" integrator=\"" << (rk4 ? "RK4" : "Euler")
    << "\" gravity=\"0 0 " << -c.g
    << "\" solver=\"Newton\" cone=\"elliptic\" iterations=\"100\" tolerance=\"1e-10\"/>\n"
    << "  <worldbody>\n";
  if (c.plane) x << "    <geom name=\"ground\" type=\"plane\" size=\"0 0 1\" " << params << "/>\n";
  x << "    <body name=\"b\" pos=\"" << c.start.p_WBo.x() << ' ' << c.start.p_WBo.y() << ' '
    << c.start.p_WBo.z() << "\" quat=\"" << q.w() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z()
    << "\">\n"
    << "      <freejoint/>\n"
    << "      <inertial pos=\"0 0 0\" mass=\"" << c.mass << "\" diaginertia=\"" << I.x() << ' '
    << I.y() << ' ' << I.z() << "\"/>\n";
  if (c.shape == ContactShape::kSphere) {
    x << "      <geom type=\"sphere\" size=\"" << c.size << "\" " << params << "/>\n";
  } else {
    const double h = 0.5 * c.size;
    x << "      <geom type=\"box\" size=\"" << h << ' ' << h << ' ' << h << "\" " << params
      << "/>\n";
  }
  x << "    </body>\n  </worldbody>\n</mujoco>\n";
  return x.str();
}

mjModel* compile(const std::string& xml) {
  // mjVFS holds fixed arrays of file names (megabytes): on the heap, not the stack.
  const auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  const char* file = "rigid_contact.xml";
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

// MuJoCo prints warnings (and resets the body) when a state goes bad; the driver reads the
// warning counters instead.
void quiet_warning(const char*) {}

class MujocoContactWorld final : public ContactWorld {
 public:
  MujocoContactWorld(const ContactCase& c, bool rk4, double dt, int copies, bool record)
      : record_(record) {
    model_ = compile(model_xml(c, rk4, dt));
    const int dof = model_->jnt_dofadr[model_->body_jntadr[1]];
    for (int k = 0; k < copies; ++k) {
      mjData* d = mj_makeData(model_);
      if (!d) throw std::runtime_error("mujoco: mj_makeData failed");
      // The free joint's qvel: v in the world frame, then w in the body frame.
      const Vec3 w_B = c.start.q_WB.normalized().conjugate() * c.start.w_WB;
      for (int i = 0; i < 3; ++i) {
        d->qvel[dof + i] = c.start.v_WBo[i];
        d->qvel[dof + 3 + i] = w_B[i];
      }
      data_.push_back(d);
    }
    diverged_.assign(copies, false);
    contacts_.resize(copies);
  }

  ~MujocoContactWorld() override {
    for (mjData* d : data_)
      mj_deleteData(d);
    mj_deleteModel(model_);
  }
  MujocoContactWorld(const MujocoContactWorld&) = delete;
  MujocoContactWorld& operator=(const MujocoContactWorld&) = delete;

  void step() override {
    for (std::size_t k = 0; k < data_.size(); ++k) {
      mjData* d = data_[k];
      mj_step(model_, d);
      if (!diverged_[k]) diverged_[k] = diverged(d);
      if (record_) {
        // The contacts and forces of the step just taken (found at its start): the normal force
        // is the first component in the contact frame.
        StepContact& s = contacts_[k];
        s = {};
        s.points = d->ncon;
        for (int i = 0; i < d->ncon; ++i) {
          mjtNum f[6];
          mj_contactForce(model_, d, i, f);
          s.normal_impulse += f[0] * model_->opt.timestep;
        }
      }
    }
  }

  BodyState state(int i) const override {
    BodyState s;
    if (diverged_[i]) return nan_state();
    const mjData* d = data_[i];
    const mjtNum* x = d->qpos;  // one body: its free joint's qpos and qvel come first
    const mjtNum* v = d->qvel;
    s.p_WBo = Vec3(x[0], x[1], x[2]);
    s.q_WB = Quat(x[3], x[4], x[5], x[6]).normalized();
    s.v_WBo = Vec3(v[0], v[1], v[2]);
    s.w_WB = s.q_WB * Vec3(v[3], v[4], v[5]);
    return s;
  }

  StepContact contact(int i) const override { return contacts_[i]; }

 private:
  // MuJoCo resets a model whose qpos, qvel or qacc goes bad and counts a warning.
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

  bool record_;
  mjModel* model_ = nullptr;
  std::vector<mjData*> data_;
  std::vector<bool> diverged_;
  std::vector<StepContact> contacts_;
};

class MujocoContactEngine final : public ContactEngine {
 public:
  MujocoContactEngine() { mju_user_warning = quiet_warning; }
  std::string name() const override { return "mujoco"; }
  std::string version() const override {
    return std::string("MuJoCo ") + mj_versionString() + " (mjtNum double)";
  }
  std::vector<std::string> modes() const override { return {"euler", "rk4"}; }
  std::string settings(const std::string& mode) const override {
    return std::string(mode == "rk4" ? "RK4" : "Euler") +
           "; solref direct (-w^2, -2 zeta w), w = 0.5/dt, zeta = -ln e / sqrt(pi^2 + ln^2 e) "
           "(1 for e = 0), solimp 0.99 0.99 0.001, margin 0, condim 3, Newton, elliptic cones, "
           "100 iterations, tolerance 1e-10; one mjData per copy";
  }
  std::unique_ptr<ContactWorld> make_world(const ContactCase& c, const std::string& mode, double dt,
                                           int copies, bool record) const override {
    if (mode != "euler" && mode != "rk4") throw std::runtime_error("mujoco: unknown mode " + mode);
    return std::make_unique<MujocoContactWorld>(c, mode == "rk4", dt, copies, record);
  }
};

}  // namespace

std::unique_ptr<ContactEngine> make_mujoco_contact_engine() {
  return std::make_unique<MujocoContactEngine>();
}

}  // namespace rigid::bench::peers
