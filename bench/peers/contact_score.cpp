#include "contact_score.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <ostream>

namespace rigid::bench::peers {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// A state whose lowest point is less than this below the plane counts as not penetrating (the
// target's bound on penetration): the apex and the energy rise are read on such states only, so
// that a soft contact's stored energy is not read as lost and then regained.
constexpr double kNoPenetration = 1e-9;

bool finite(const BodyState& s) {
  return s.p_WBo.allFinite() && s.q_WB.coeffs().allFinite() && s.v_WBo.allFinite() &&
         s.w_WB.allFinite();
}

bool drops(const ContactCase& c) {
  return c.plane && (c.kind == ContactKind::kElastic || c.kind == ContactKind::kBouncing);
}

}  // namespace

ContactScorer::ContactScorer(const ContactCase& c, double dt, bool events)
    : c_(c), exact_(closed_form(c)), dt_(dt), events_(events) {
  prev_ = last_ = c.start;
  E0_ = E_min_ = energy(c, c.start);
  row_.max_penetration = std::max(0.0, -lowest_point(c, c.start));
  row_.max_energy_rise = 0;
  last_fast_ = speed_bound(c, c.start) >= kRestSpeed ? 0.0 : -dt;
  if (c.plane && has_exact_motion(c) && !events) speed_rule_rest_ = exact_speed_rule_rest(c, dt);
}

void ContactScorer::impact(double t) {
  close_flight();
  impacts_.push_back(t);
  have_apex_ = false;
}

void ContactScorer::close_flight() {
  if (impacts_.empty()) return;
  if (have_apex_) {
    const double vz = apex_state_.v_WBo.z();
    apex_heights_.push_back(apex_state_.p_WBo.z() + vz * vz / (2.0 * c_.g));
    apex_energies_.push_back(energy(c_, apex_state_) / E0_ - 1.0);
  } else {
    apex_heights_.push_back(kNaN);
    apex_energies_.push_back(kNaN);
  }
}

void ContactScorer::observe(long n, const BodyState& s, const StepContact& contact,
                            std::span<const LocatedEvent> events) {
  if (failed_) return;
  const double t = static_cast<double>(n) * dt_;
  if (!finite(s) || blown_up(s, prev_, dt_)) {
    failed_ = true;
    return;
  }
  row_.max_points = std::max(row_.max_points, contact.points);
  const double pen = std::max(0.0, -lowest_point(c_, s));
  row_.max_penetration = std::max(row_.max_penetration, pen);

  // Impacts: located by the engine, or the step over which the centre's vertical velocity turns
  // from down to up (its middle), once the descent before it reached kRestSpeed.
  if (drops(c_)) {
    if (events_) {
      for (const LocatedEvent& e : events) {
        if (e.kind != LocatedEvent::Kind::kImpact) continue;
        const double approach = e.normal_impulse / (c_.mass * (1.0 + c_.restitution));
        if (approach >= kRestSpeed) impact(e.time);
      }
    } else {
      const double v0 = prev_.v_WBo.z(), v1 = s.v_WBo.z();
      if (v0 < 0) approach_ = std::max(approach_, -v0);
      if (v0 < 0 && v1 >= 0) {
        if (approach_ >= kRestSpeed) impact(t - 0.5 * dt_);
        approach_ = 0;
      }
    }
    // The state of the current flight nearest its apex.
    if (!impacts_.empty() && pen <= kNoPenetration &&
        (!have_apex_ || std::abs(s.v_WBo.z()) < std::abs(apex_state_.v_WBo.z()))) {
      apex_state_ = s;
      have_apex_ = true;
    }
  }

  if (pen <= kNoPenetration) {
    const double E = energy(c_, s);
    row_.max_energy_rise = std::max(row_.max_energy_rise, (E - E_min_) / E0_);
    E_min_ = std::min(E_min_, E);
  }

  if (speed_bound(c_, s) >= kRestSpeed) last_fast_ = t;
  for (const LocatedEvent& e : events) {
    rest_event_ = e.kind == LocatedEvent::Kind::kResting ? e.time : kNaN;
  }

  if (c_.kind == ContactKind::kResting && t >= kSettleTime - 0.5 * dt_) {
    const std::vector<Vec3> now = corners(c_, s);
    if (settled_corners_.empty()) {
      settled_corners_ = now;
      row_.drift = 0;
    }
    for (std::size_t i = 0; i < now.size(); ++i) {
      row_.drift = std::max(row_.drift, (now[i] - settled_corners_[i]).norm());
    }
  }
  prev_ = last_ = s;
}

ContactRow ContactScorer::result() const {
  ContactRow r = row_;
  if (failed_) {
    r.blown_up = true;
    for (double* x : {&r.first_impact_error, &r.later_impact_error, &r.max_penetration,
                      &r.apex_error, &r.energy_error, &r.max_energy_rise, &r.rest_time,
                      &r.rest_time_error, &r.stop_distance_error, &r.drift, &r.final_tilt}) {
      *x = kInf;
    }
    return r;
  }
  if (drops(c_)) {
    // The flight still open at the end of the run counts as well.
    ContactScorer open = *this;
    open.close_flight();
    const std::vector<double>& run = impacts_;
    const std::vector<double>& exact = exact_.impacts;
    r.impacts = static_cast<int>(run.size());
    r.exact_impacts = static_cast<int>(exact.size());
    r.first_impact_error = run.empty() ? kInf : run[0] - exact[0];
    const std::size_t both = std::min({run.size(), exact.size(), std::size_t(kImpactsScored)});
    for (std::size_t k = 1; k < both; ++k) {
      const double e = std::abs(run[k] - exact[k]);
      r.later_impact_error =
          std::isnan(r.later_impact_error) ? e : std::max(r.later_impact_error, e);
    }
    const std::vector<double>& apexes = open.apex_heights_;
    if (c_.kind == ContactKind::kElastic) {
      const std::size_t k = kImpactsScored - 1;  // the apex after the 12th impact
      if (k < apexes.size() && k < exact_.apexes.size()) {
        r.apex_error = apexes[k] - exact_.apexes[k];
        r.energy_error = open.apex_energies_[k];
      } else {
        r.apex_error = r.energy_error = kInf;  // fewer than 12 bounces
      }
    } else {
      const std::size_t n =
          std::min({apexes.size(), exact_.apexes.size(), std::size_t(kApexesScored)});
      for (std::size_t k = 0; k < n; ++k) {
        const double e = std::abs(apexes[k] - exact_.apexes[k]);
        if (!std::isnan(e)) r.apex_error = std::isnan(r.apex_error) ? e : std::max(r.apex_error, e);
      }
    }
  }
  if (c_.plane && (c_.kind == ContactKind::kBouncing || c_.kind == ContactKind::kSliding ||
                   c_.kind == ContactKind::kTumbling)) {
    const double end = c_.duration;
    if (events_) {
      r.rest_rule = "event";
      r.rest_time = std::isnan(rest_event_) ? kInf : rest_event_;
      r.rest_time_error = r.rest_time - exact_.rest_time;
    } else {
      r.rest_rule = "speed";
      // The first state after the last one at kRestSpeed or more; never if that is the last.
      r.rest_time = last_fast_ >= end - 0.5 * dt_ ? kInf : last_fast_ + dt_;
      r.rest_time_error = r.rest_time - speed_rule_rest_;
    }
  }
  if (c_.plane && c_.kind == ContactKind::kSliding) {
    const Vec3 along = c_.start.v_WBo.normalized();
    r.stop_distance_error = (last_.p_WBo - c_.start.p_WBo).dot(along) - exact_.stop_distance;
  }
  if (c_.shape == ContactShape::kCube) r.final_tilt = tilt(last_);
  return r;
}

void write_contact_csv_header(std::ostream& os) {
  os << "case,engine_mode,dt,steps,impacts,exact_impacts,first_impact_error_s,"
        "later_impact_error_s,max_penetration_m,apex_error_m,energy_error_rel,"
        "max_energy_rise_rel,rest_rule,rest_time_s,rest_time_error_s,stop_distance_error_m,"
        "drift_m,final_tilt_rad,max_contact_points,blown_up,ns_per_body_step,"
        "settled_ns_per_body_step,free_ns_per_body_step\n";
}

void write_contact_csv_row(std::ostream& os, const ContactCase& c, const std::string& engine_mode,
                           double dt, long steps, const ContactRow& r, double ns_per_body_step,
                           double settled_ns_per_body_step, double free_ns_per_body_step) {
  const auto old = os.precision(9);
  os << c.name << ',' << engine_mode << ',' << dt << ',' << steps << ',' << r.impacts << ','
     << r.exact_impacts << ',' << r.first_impact_error << ',' << r.later_impact_error << ','
     << r.max_penetration << ',' << r.apex_error << ',' << r.energy_error << ','
     << r.max_energy_rise << ',' << r.rest_rule << ',' << r.rest_time << ',' << r.rest_time_error
     << ',' << r.stop_distance_error << ',' << r.drift << ',' << r.final_tilt << ',' << r.max_points
     << ',' << (r.blown_up ? 1 : 0) << ',' << ns_per_body_step << ',' << settled_ns_per_body_step
     << ',' << free_ns_per_body_step << '\n';
  os.precision(old);
}

}  // namespace rigid::bench::peers
