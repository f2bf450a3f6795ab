#pragma once
/// The hitting DS (thesis eq. 2.10): xdot = s(|x - x*|) R(theta) g(R(theta)^T (x - x*)), with
/// g = v E, R(theta) the rotation about the vertical through the ball, s a speed modulator.
///
/// Real-time contract: `hitting_ds_velocity`, `speed_modulator`, `ball_reached` and
/// `hitting_velocity` allocate nothing and never throw (given a HittingDsData made for the model
/// and a command set with `set_command`). Everything that can fail happens in `set_command`.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ds/hitting_model.hpp"

namespace mg::ds {

enum class Modulator {
  kConstant,  ///< s = s^d everywhere
  kSine,      ///< s(r) = s^d + (1 - s^d) sin^2(pi r / (2 d0)) for r < d0, 1 beyond (eqs. 2.6a-d)
};
Modulator parse_modulator(const std::string& name);  ///< "constant" | "sine"; InputError otherwise
std::string to_string(Modulator modulator);

/// What to hit: angle theta [rad] about +z from psi0, speed v^d [m/s] at the ball, the modulator,
/// and the start position (for d0 = |x0 - x*| of the sine modulator) [m, world].
struct HittingCommand {
  double angle = 0.0;
  double speed = 1.5;
  Modulator modulator = Modulator::kConstant;
  Eigen::Vector3d start = Eigen::Vector3d::Zero();
};

/// Speed modulator value at distance r [m] from x*; s^d = v^d / v(x*), d0 > 0 [m].
double speed_modulator(Modulator modulator, double s_d, double d0, double r);

/// R(theta): counter-clockwise rotation by theta [rad] about +z (eq. 2.9).
Eigen::Matrix3d rotation_about_z(double theta);

/// Per-run workspace (preallocated GMR scratch) and the resolved command. One per thread.
class HittingDsData {
 public:
  explicit HittingDsData(const HittingModel& model);
  /// Validates and resolves the command (InputError naming the field on bad values).
  void set_command(const HittingModel& model, const HittingCommand& command);

  const HittingCommand& command() const { return command_; }
  double s_d() const { return s_d_; }                        ///< v^d / v(x*)
  double d0() const { return d0_; }                          ///< [m]
  const Eigen::Matrix3d& rotation() const { return rot_; }   ///< R(theta)
  const Eigen::Vector3d& direction() const { return psi_; }  ///< R(theta) psi0, world

 private:
  friend Eigen::Vector3d hitting_ds_velocity(const HittingModel&, HittingDsData&,
                                             const Eigen::Vector3d&);
  friend Eigen::Vector3d target_field(const HittingModel&, HittingDsData&, const Eigen::Vector3d&);
  friend double strength_factor(const HittingModel&, HittingDsData&, const Eigen::Vector3d&);
  HittingCommand command_;
  double s_d_ = 1.0;
  double d0_ = 1.0;
  Eigen::Matrix3d rot_ = Eigen::Matrix3d::Identity();
  Eigen::Vector3d psi_ = Eigen::Vector3d::UnitX();
  stats::GmrConditioner::Workspace seds_ws_;
  stats::GmrConditioner::Workspace strength_ws_;
  Eigen::VectorXd in3_;   // (3) GMR input
  Eigen::VectorXd out3_;  // (3) GMR output of the SEDS model
  Eigen::VectorXd out1_;  // (1) GMR output of the strength model
};

/// Target field E(y) in the DEFAULT frame (y = x - x* before rotation), unit vector, with the
/// guidance blend near the ball (see HittingDsSettings). Real-time safe.
Eigen::Vector3d target_field(const HittingModel& model, HittingDsData& data,
                             const Eigen::Vector3d& y);
/// Strength factor v(y) [m/s] in the default frame, clamped to the model's [min, max] and blended
/// to v(x*) over the same radii as the direction (so the impact speed is exact). Real-time safe.
double strength_factor(const HittingModel& model, HittingDsData& data, const Eigen::Vector3d& y);

/// The DS: commanded club-head velocity [m/s, world] at position x [m, world]. Real-time safe.
Eigen::Vector3d hitting_ds_velocity(const HittingModel& model, HittingDsData& data,
                                    const Eigen::Vector3d& x);

/// The velocity the DS reaches at the ball, v^d R(theta) psi0 [m/s, world]: what the control
/// module keeps commanding once `ball_reached` (then it switches to braking). Real-time safe.
Eigen::Vector3d hitting_velocity(const HittingModel& model, const HittingDsData& data);

/// True once x has crossed the hitting plane through x* (normal R(theta) psi0) within
/// `capture_radius` [m] of x*. Real-time safe.
bool ball_reached(const HittingModel& model, const HittingDsData& data, const Eigen::Vector3d& x,
                  double capture_radius = 0.01);

struct RolloutOptions {
  double dt = 0.002;               ///< [s] integration step (RK4), the 500 Hz control period
  double max_duration = 20.0;      ///< [s] give up (stall) after this
  double max_distance = 20.0;      ///< [m] give up (divergence) beyond this from x*
  double reach_tolerance = 0.005;  ///< [m] position error that still counts as reaching the ball
  double capture_radius = 0.03;  ///< [m] a hitting-plane crossing closer than this ends the rollout
  bool record = true;            ///< keep the trajectory samples
  void validate() const;
};

struct RolloutResult {
  bool reached = false;         ///< ball reached within reach_tolerance
  std::string stop_reason;      ///< "reached", "missed", "timeout", "diverged"
  double position_error = 0.0;  ///< [m] |x_hit - x*|
  Eigen::Vector3d hit_position = Eigen::Vector3d::Zero();  ///< [m, world] where the event happened
  Eigen::Vector3d velocity =
      Eigen::Vector3d::Zero();  ///< [m/s, world] DS velocity at the last tick before impact
  double duration = 0.0;        ///< [s] time to the event (interpolated)
  int steps = 0;
  std::vector<double> t;              ///< samples [s] (if recorded)
  std::vector<Eigen::Vector3d> x;     ///< [m, world]
  std::vector<Eigen::Vector3d> xdot;  ///< [m/s, world]
};

/// Integrates the DS from `command.start` until the ball is reached (the hitting plane is crossed
/// or the distance to x* stops decreasing), it times out or diverges.
/// Rollout starts at most this far from x* [m] (the arm reaches about 1 m).
inline constexpr double kMaxRolloutStartDistance = 5.0;
/// Throws InputError for a start that is not finite or farther than kMaxRolloutStartDistance from
/// x*.
RolloutResult rollout(const HittingModel& model, const HittingCommand& command,
                      const RolloutOptions& options = {});

/// Trajectory CSV: header `t,x,y,z,vx,vy,vz`.
std::string format_rollout(const RolloutResult& result);

/// How well the default DS (theta = 0, v = v(x*)) reproduces the demonstrations.
struct ReproductionError {
  double velocity_rmse =
      0.0;  ///< [m/s] |xdot_DS(x_n) - xdot_n| over samples faster than 5% of v(x*), > 2 cm from x*
  double direction_rmse = 0.0;  ///< [rad] angle between E(x_n) and xdot_n over the same samples
  double seds_direction_rmse =
      0.0;                  ///< [rad] the same for the bare SEDS field f (no guidance blend)
  double speed_rmse = 0.0;  ///< [m/s] | |xdot_DS(x_n)| - |xdot_n| | over the same samples
  double mean_path_distance =
      0.0;  ///< [m] mean over samples of the distance to the rollout from the demo start
  double max_path_distance = 0.0;  ///< [m] the largest such distance
  int all_reached = 0;             ///< rollouts from the demo starts that reached the ball
};
ReproductionError reproduction_error(const HittingModel& model,
                                     const std::vector<Demonstration>& demos);

}  // namespace mg::ds
