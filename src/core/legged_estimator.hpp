// The legged state estimator: the base's orientation, position and velocity and the feet's
// contacts from an IMU on the base, the joints' encoders and the applied efforts
// (virtual_actuators.estimation.LeggedEstimator; its equations: docs/estimation.md).
//
// One update, on the kinematics pass of the joints with the base at the world's origin (so that
// every frame is in the base's axes):
// 1. the IMU's readings into the base's axes; the orientation propagated with the gyro;
// 2. each foot's contact: its normal force from the efforts, quasi-static, through the leg's
//    Jacobian (J^T f = g(q) - tau on the leg's joints), and whether it moves in the world;
//    their product is the contact's probability, thresholded with hysteresis;
// 3. the orientation corrected by gravity and by pairs of stance feet (attitude_filter.hpp);
// 4. position and velocity predicted with the accelerometer and corrected by the feet
//    (leg_filter.hpp).
// The new state is computed on a copy and kept only when every number in it is finite.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "attitude_filter.hpp"
#include "gravity.hpp"
#include "kinematics.hpp"
#include "leg_filter.hpp"
#include "leg_force.hpp"
#include "so3.hpp"

namespace va {

// The time constant of the base's acceleration that the tilt update takes [s].
constexpr double ACCEL_TIME = 0.02;

struct ContactTuning {
  double force_low, force_high;      // fractions of the weight per foot: p_force 0 -> 1
  double still_speed, moving_speed;  // [m/s] the foot's speed: p_still 1 -> 0
  double on, off;                    // hysteresis on the probability
  double low_height, high_height;    // [m] on level ground, a foot this low may be in contact
};

struct EstimatorTuning {
  AttitudeNoise attitude;
  LegNoise leg;
  ContactTuning contact;
  double tilt_sigma, yaw_sigma, bias_sigma, accel_bias_sigma;  // at reset [rad, rad, rad/s, m/s^2]
  bool level_ground;
  double output_rate_time;  // [s] the low-pass of the rates the estimate gives (0: none)
};

// Static tables of one robot (fixed at construction).
struct EstimatorTables {
  std::shared_ptr<const Tree> tree;
  std::vector<std::int64_t> foot_rows;        // (nf) rows of the tree's frame table
  std::int64_t imu_row;                       // row of the IMU frame
  std::vector<std::int64_t> leg_offsets;      // (nf + 1) into leg_columns
  std::vector<std::int64_t> leg_columns;      // velocity indices of each foot's leg joints
  std::vector<std::int64_t> gravity_columns;  // every leg column once
  std::vector<double> masses, levers;         // (njoints), (njoints, 3)
  std::vector<double>
      spheres;             // (nf, 4) each foot's rounded sole: centre in the foot frame, radius
  double gravity[3];       // world [m/s^2]
  double weight_per_foot;  // [N]
};

struct EstimatorState {
  AttitudeFilter attitude;
  LegFilter leg;
  std::vector<double> probability;
  std::vector<char> in_contact;
  double time = 0.0;
  std::vector<double> rates;  // (nv) the estimate's base angular velocity (3:6), joint rates
  double accel[3] = {0.0, 0.0, 0.0}, velocity[3] = {0.0, 0.0, 0.0};  // world, for the tilt
  bool started = false;
};

class LeggedEstimatorCore {
 public:
  LeggedEstimatorCore(EstimatorTables tables, EstimatorTuning tuning)
      : t_(std::move(tables)), tuning_(tuning) {
    const auto nf = static_cast<std::int64_t>(t_.foot_rows.size());
    s_.leg.resize(nf);
    s_.probability.assign(static_cast<size_t>(nf), 1.0);
    s_.rates.assign(static_cast<size_t>(t_.tree->tables().nv), 0.0);
    s_.in_contact.assign(static_cast<size_t>(nf), 1);
    buffer_.resize(static_cast<size_t>(t_.tree->size(true)));
    subtree_.resize(static_cast<size_t>(4 * t_.tree->tables().njoints));
    gravity_tau_.resize(static_cast<size_t>(t_.tree->tables().nv));
    offsets_.resize(static_cast<size_t>(3 * nf));
    rates_.resize(static_cast<size_t>(3 * nf));
    leg_jjt_.resize(static_cast<size_t>(9 * nf));
  }

  std::int64_t feet() const { return static_cast<std::int64_t>(t_.foot_rows.size()); }
  const EstimatorState& state() const { return s_; }

  // Start from the base's placement (position p, rotation r world <- base), its velocity
  // (world axes) and the joints (q_local: the configuration with the base at the origin).
  void reset(const double* q_local, const double* p, const so3::Mat3 r, const double* v_world) {
    t_.tree->compute(q_local, nullptr, buffer_.data());
    const std::int64_t nf = feet();
    std::vector<double> feet_world(static_cast<size_t>(3 * nf));
    for (std::int64_t f = 0; f < nf; ++f) {
      double world[3];
      double point[3];
      const double* foot = frame(t_.foot_rows[f]);
      const so3::Mat3 foot_rotation = {
          {foot[0], foot[1], foot[2]}, {foot[3], foot[4], foot[5]}, {foot[6], foot[7], foot[8]}};
      double down[3], centre[3];
      const double minus_z[3] = {0.0, 0.0, -1.0};
      so3::apply_transposed(r, minus_z, down);
      so3::apply(foot_rotation, t_.spheres.data() + 4 * f, centre);
      for (int i = 0; i < 3; ++i)
        point[i] = foot[9 + i] + centre[i] + t_.spheres[4 * f + 3] * down[i];
      so3::apply(r, point, world);
      for (int i = 0; i < 3; ++i) feet_world[3 * f + i] = p[i] + world[i];
    }
    for (int i = 0; i < 3; ++i) s_.accel[i] = 0.0, s_.velocity[i] = v_world[i];
    s_.attitude.reset(r, tuning_.tilt_sigma, tuning_.yaw_sigma, tuning_.bias_sigma,
                      tuning_.accel_bias_sigma);
    s_.leg.reset(p, v_world, feet_world.data(), 1e-6, 1e-3, tuning_.leg.kinematics);
    for (std::int64_t f = 0; f < nf; ++f) s_.probability[f] = 1.0, s_.in_contact[f] = 1;
    s_.started = false;
  }

  // One reading: q_local (nq, the base at the origin), v_local (nv, the base at rest), gyro and
  // accelerometer in the IMU's axes, tau (nv) the applied efforts, time [s]. False (and the
  // state unchanged) when the result would not be finite.
  // switches: (nf) a contact switch per foot, 1 closed, 0 open, -1 none (the estimate's own
  // contact); nullptr: no switches.
  bool update(const double* q_local, const double* v_local, const double* gyro_imu,
              const double* accel_imu, const double* tau, double time,
              const double* switches = nullptr) {
    next_ = s_;  // copy-assigned into the same storage: no allocation after the first
    switches_ = switches;
    if (!step(next_, q_local, v_local, gyro_imu, accel_imu, tau, time)) return false;
    std::swap(s_, next_);
    return true;
  }

 private:
  const double* frame(std::int64_t row) const {
    return buffer_.data() + t_.tree->frames_offset() + 12 * row;
  }
  const double* frame_velocity(std::int64_t row) const {
    const TreeTables& tt = t_.tree->tables();
    return buffer_.data() + t_.tree->frames_offset() + 12 * tt.nf + 3 * row;
  }

  bool step(EstimatorState& s, const double* q_local, const double* v_local, const double* gyro_imu,
            const double* accel_imu, const double* tau, double time) {
    const TreeTables& tt = t_.tree->tables();
    const std::int64_t nf = feet(), nv = tt.nv;
    t_.tree->compute(q_local, v_local, buffer_.data());
    // 1. the IMU in the base's axes (the lever arm's centripetal term removed)
    const double* imu = frame(t_.imu_row);
    const so3::Mat3 r_bi = {
        {imu[0], imu[1], imu[2]}, {imu[3], imu[4], imu[5]}, {imu[6], imu[7], imu[8]}};
    double w_m[3], f_m[3], w[3], wr[3], wwr[3];
    so3::apply(r_bi, gyro_imu, w_m);
    so3::apply(r_bi, accel_imu, f_m);  // f_m's bias c^ comes off where it is used
    s.attitude.rate(w_m, w);
    so3::cross(w, imu + 9, wr);
    so3::cross(w, wr, wwr);
    for (int i = 0; i < 3; ++i) f_m[i] -= wwr[i];
    const double dt = s.started ? time - s.time : 0.0;
    if (s.started && !(dt > 0.0)) return false;
    if (dt > 0.0) s.attitude.propagate(w_m, dt, tuning_.attitude);
    s.attitude.rate(w_m, w);
    // 2. contacts
    const double* jacobian = buffer_.data() + t_.tree->jacobian_offset();
    double gravity_base[3];
    so3::apply_transposed(s.attitude.rotation, t_.gravity, gravity_base);
    generalized_gravity(tt, buffer_.data(), jacobian, t_.masses.data(), t_.levers.data(),
                        gravity_base, t_.gravity_columns.data(),
                        static_cast<std::int64_t>(t_.gravity_columns.size()), subtree_.data(),
                        gravity_tau_.data());
    std::vector<double>& offsets = offsets_;  // (nf, 3) each: contact points, rates, J J^T
    std::vector<double>& rates = rates_;
    std::vector<double>& leg_jjt = leg_jjt_;
    const ContactTuning& c = tuning_.contact;
    double down[3];  // the world's -z in base axes
    const double minus_z[3] = {0.0, 0.0, -1.0};
    so3::apply_transposed(s.attitude.rotation, minus_z, down);
    for (std::int64_t f = 0; f < nf; ++f) {
      contact_point(f, down, jacobian, nv, v_local, offsets.data() + 3 * f, rates.data() + 3 * f);
      const double* r = offsets.data() + 3 * f;
      const double* rr = rates.data() + 3 * f;
      double force[3];
      leg_force(t_.leg_columns.data() + t_.leg_offsets[f],
                t_.leg_offsets[f + 1] - t_.leg_offsets[f], r, jacobian, nv, gravity_tau_.data(),
                tau, force, leg_jjt.data() + 9 * f);
      double force_world[3];
      so3::apply(s.attitude.rotation, force, force_world);
      double moving[3], foot_velocity[3];
      so3::cross(w, r, moving);
      for (int i = 0; i < 3; ++i) moving[i] += rr[i];
      so3::apply(s.attitude.rotation, moving, foot_velocity);
      for (int i = 0; i < 3; ++i) foot_velocity[i] += s.leg.x[3 + i];
      const double low = c.force_low * t_.weight_per_foot, high = c.force_high * t_.weight_per_foot;
      const double p_force = ramp((force_world[2] - low) / (high - low));
      const double p_still =
          ramp((c.moving_speed - so3::norm(foot_velocity)) / (c.moving_speed - c.still_speed));
      // on level ground: a still foot at its level stands on it, one far above it does not
      // (a swing pushing its foot down looks like a ground pushing it up)
      double p_low = 0.0, p_near = 1.0;
      if (tuning_.level_ground) {
        double offset_world[3];
        so3::apply(s.attitude.rotation, r, offset_world);
        const double height = s.leg.x[2] + offset_world[2] - s.leg.level[f];
        const double span = c.high_height - c.low_height;
        p_low = ramp((c.high_height - height) / span);
        p_near = ramp((c.high_height + span - height) / span);
      }
      const double p_pushed = p_force * p_near;
      const double p = p_still * (p_pushed > p_low ? p_pushed : p_low);
      if (switches_ != nullptr && switches_[f] >= 0.0) {  // a switch says it: no hysteresis
        s.probability[f] = switches_[f] > 0.5 ? 1.0 : 0.0;
        s.in_contact[f] = switches_[f] > 0.5;
        continue;
      }
      s.probability[f] = p;
      if (s.in_contact[f] && p < c.off) s.in_contact[f] = 0;
      if (!s.in_contact[f] && p > c.on) s.in_contact[f] = 1;
    }
    // 3. orientation: gravity, then every stance foot against the first
    s.attitude.update_gravity(f_m, s.accel, t_.gravity, tuning_.attitude);
    std::int64_t first = -1;
    for (std::int64_t f = 0; f < nf; ++f) {
      if (!s.in_contact[f]) continue;
      if (first < 0) {
        first = f;
        continue;
      }
      double r[3], rr[3];
      for (int i = 0; i < 3; ++i) {
        r[i] = offsets[3 * f + i] - offsets[3 * first + i];
        rr[i] = rates[3 * f + i] - rates[3 * first + i];
      }
      s.attitude.update_stance(w_m, r, rr, tuning_.attitude);
      if (tuning_.level_ground)
        s.attitude.update_level(r, s.leg.level[f] - s.leg.level[first], tuning_.attitude);
    }
    s.attitude.rate(w_m, w);
    // 4. position and velocity
    bool stance[64];
    for (std::int64_t f = 0; f < nf && f < 64; ++f) stance[f] = s.in_contact[f] != 0;
    if (dt > 0.0) {
      double accel_world[3], f[3];
      s.attitude.force(f_m, f);
      so3::apply(s.attitude.rotation, f, accel_world);
      for (int i = 0; i < 3; ++i) accel_world[i] += t_.gravity[i];
      s.leg.predict(accel_world, dt, stance, tuning_.leg);
    }
    const so3::Mat3& rot = s.attitude.rotation;
    for (std::int64_t f = 0; f < nf; ++f) {
      const double* r = offsets.data() + 3 * f;
      const double* jjt = leg_jjt.data() + 9 * f;
      double offset_world[3], cov[9];
      so3::apply(rot, r, offset_world);
      // base-axes noise: encoders through J J^T, the attitude through [r]x P_theta [r]x^T
      so3::Mat3 rx;
      so3::skew(r, rx);
      double base[9];
      const LegNoise& n = tuning_.leg;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          double sum =
              n.encoder * n.encoder * jjt[3 * i + j] + (i == j ? n.kinematics * n.kinematics : 0.0);
          for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
              sum += rx[i][a] * s.attitude.P[ATTITUDE_STATES * a + b] * rx[j][b];
          base[3 * i + j] = sum;
        }
      rotate_covariance(rot, base, cov);
      if (!stance[f]) {
        if (!s.leg.update_foot(f, offset_world, cov, nullptr, nullptr, 0.0)) return false;
        continue;
      }
      double moving[3], velocity[3], velocity_cov[9];
      so3::cross(w, r, moving);
      for (int i = 0; i < 3; ++i) moving[i] += rates[3 * f + i];
      so3::apply(rot, moving, velocity);
      for (double& e : velocity) e = -e;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          double sum = n.encoder_rate * n.encoder_rate * jjt[3 * i + j] +
                       (i == j ? n.foot_velocity * n.foot_velocity : 0.0);
          for (int a = 0; a < 3; ++a) sum += n.gyro * n.gyro * rx[i][a] * rx[j][a];
          base[3 * i + j] = sum;
        }
      rotate_covariance(rot, base, velocity_cov);
      if (!s.leg.update_foot(f, offset_world, cov, velocity, velocity_cov,
                             tuning_.level_ground ? n.height : 0.0))
        return false;
    }
    if (dt > 0.0) {  // the base's acceleration for the next tilt update, low-passed
      const double blend = dt / (dt + ACCEL_TIME);
      for (int i = 0; i < 3; ++i) {
        const double a = (s.leg.x[3 + i] - s.velocity[i]) / dt;
        s.accel[i] += blend * (a - s.accel[i]);
      }
    }
    for (int i = 0; i < 3; ++i) s.velocity[i] = s.leg.x[3 + i];
    s.time = time;
    s.started = true;
    // what the controller reads of the rates: low-passed against the sensors' white noise
    // (the gyro's, the encoders'), but never more than three of its deviations from the
    // reading, so that the lag stays small where the rates jump (a leg's damping acting late on
    // a foot's impact bounces it)
    const double tau_f = tuning_.output_rate_time;
    const double blend = tau_f <= 0.0 || dt <= 0.0 ? 1.0 : dt / (dt + tau_f);  // first: 1
    for (std::int64_t k = 3; k < nv; ++k) {
      const double raw = k < 6 ? w[k - 3] : v_local[k];
      const double band = 3.0 * (k < 6 ? tuning_.leg.gyro : tuning_.leg.encoder_rate);
      const double lag = (1.0 - blend) * (s.rates[k] - raw);
      s.rates[k] = raw + (lag > band ? band : lag < -band ? -band : lag);
    }
    return finite(s);
  }

  // Foot f's contact point (base axes): for a sole rounded as a sphere (centre c in the foot
  // frame, radius rho) its lowest point r_f + R_f c + rho down, and the rate of the foot's
  // material point there, r_f' + w_f x (R_f c + rho down) (w_f the foot's angular velocity from
  // the leg's joints): zero in the world when the foot rolls without slipping.
  void contact_point(std::int64_t f, const double* down, const double* jacobian, std::int64_t nv,
                     const double* v, double* r, double* rate) const {
    const double* foot = frame(t_.foot_rows[f]);
    const double* origin = foot + 9;
    const double* origin_rate = frame_velocity(t_.foot_rows[f]);
    const double* sphere = t_.spheres.data() + 4 * f;
    const double rho = sphere[3];
    double w[3] = {0.0, 0.0, 0.0};
    for (std::int64_t k = t_.leg_offsets[f]; k < t_.leg_offsets[f + 1]; ++k) {
      const std::int64_t col = t_.leg_columns[k];
      for (int i = 0; i < 3; ++i) w[i] += jacobian[(3 + i) * nv + col] * v[col];
    }
    double lever[3];
    for (int i = 0; i < 3; ++i)
      lever[i] = foot[3 * i] * sphere[0] + foot[3 * i + 1] * sphere[1] +
                 foot[3 * i + 2] * sphere[2] + rho * down[i];
    double wl[3];
    so3::cross(w, lever, wl);
    for (int i = 0; i < 3; ++i) r[i] = origin[i] + lever[i], rate[i] = origin_rate[i] + wl[i];
  }

  static bool finite(const EstimatorState& s) {
    const auto count = [](const std::vector<double>& v) {
      return static_cast<std::int64_t>(v.size());
    };
    return all_finite(s.attitude.P, ATTITUDE_STATES * ATTITUDE_STATES) &&
           all_finite(s.attitude.bias, 3) && all_finite(s.attitude.accel_bias, 3) &&
           all_finite(s.leg.x.data(), count(s.leg.x)) &&
           all_finite(s.leg.P.data(), count(s.leg.P)) &&
           all_finite(s.rates.data(), count(s.rates)) &&
           all_finite(s.probability.data(), count(s.probability));
  }

  EstimatorTables t_;
  EstimatorTuning tuning_;
  EstimatorState s_, next_;
  const double* switches_ = nullptr;  // this update's contact switches, or nullptr
  std::vector<double> buffer_, subtree_, gravity_tau_, offsets_, rates_, leg_jjt_;
};

}  // namespace va
