#pragma once
/// The automated teacher (thesis 5.1): for a situation (a hole position), find hitting parameters
/// (theta, v) that sink the ball on the full system, following a named strategy, with a verified
/// neighbourhood (the simulator is deterministic, so a window's edge would be a fragile example).
///
/// Search, in the ball's terms (what a person watching the putt corrects by):
///   residual r(theta, v) = (lateral miss at the closest approach [m],
///                           e - v_t^2 [m^2/s^2]),  e = v_c^2 - 2 a_roll along,
/// where v_c is the ball's speed at its closest approach, `along` how far short it stopped and
/// a_roll = (5/7) rho g the rolling deceleration, so e is the squared speed the ball would have
/// had at the hole. The target arrival speed v_t names the strategy:
///   min-speed  the ball reaches the hole slowly (v_t = kMinSpeedArrival): the slowest speed
///              whose neighbourhood still sinks;
///   min-angle  the ball reaches the hole as fast as the cup holds it (v_t = kMinAngleArrival
///              scaled by the hole's capture speed): the straightest line.
/// 1. Proposal on the ball-only path (launch angle, launch speed): Broyden's method from a
///    physics-free prior (aim at the hole; the launch speed that rolls the distance plus the
///    climb, Penner's law); a coarse grid around the aim if that does not converge. When an
///    obstacle blocks the straight line, bank shots instead (bank_shots.hpp): the path folded at
///    one border or obstacle face (mirror images, legs clear of obstacles), shortest first, then
///    at two; the first that converges is the window the teacher takes (each bounce mirrors the
///    path, so the miss's slope in the angle flips sign per bounce). Hits beyond the fixed arm's
///    envelope are made with the base turned (system::hit_pose): angles are world angles.
/// 2. The proposal is mapped to the club through the launch relation measured by the putts
///    themselves (launch angle - theta, launch speed / club speed) and solved again on the full
///    system with the same residual. Every recorded example is a full-system putt that sank.
/// 3. Margin: the putts at theta +- margin_angle and v +- margin_speed (angle only: theta +-)
///    must sink too; otherwise the point moves away from the failing side (twice at most), then
///    the margin is halved (recorded).
/// The solution is a smooth function of the hole where the sinking window is, so neighbouring
/// situations get neighbouring parameters (thesis 3.2). Deterministic: the same system and hole
/// give the same example.
#include <array>
#include <string>

#include "belief/prior.hpp"
#include "system/system.hpp"

namespace mg::teacher {

enum class Strategy { kMinSpeed, kMinAngle };
std::string to_string(Strategy s);
Strategy parse_strategy(const std::string& name);  ///< "min-speed" | "min-angle"; InputError

constexpr double kMinSpeedArrival = 0.4;  ///< [m/s] min-speed target speed at the hole centre
constexpr double kMinAngleArrival = 0.8;  ///< [m/s] min-angle target for a 60 mm deep, 108 mm hole

struct TeacherOptions {
  Strategy strategy = Strategy::kMinSpeed;
  /// Angle only (thesis 6.2.1-6.2.2): the club speed is fixed at `fixed_speed` [m/s].
  bool learn_speed = true;
  double fixed_speed = 0.0;
  double margin_angle = 0.004;  ///< [rad] (0.23 deg; the launch std under noise is 0.07-0.1 deg)
  double margin_speed = 0.03;   ///< [m/s] club speed
  /// A starting club (theta [rad], v [m/s]) from neighbouring examples: the full-system search
  /// starts there and the ball-only proposal is skipped (continuity repair, thesis 3.2).
  bool use_hint = false;
  std::array<double, 2> hint{0.0, 0.0};
  int max_full_putts = 40;  ///< budget per situation
  int max_ball_putts = 600;
  void validate() const;  ///< InputError naming the field
};

/// The teacher's options for `region`: what it learns (angle and speed, or the angle at the
/// region's club speed) and `strategy` (empty: the region's default); the rest at their defaults.
TeacherOptions options_for(const field::Situations& region, const std::string& strategy = "");

/// One collected example (a row of the teacher's data set).
struct Example {
  std::array<double, 2> hole{0, 0};  ///< [m]
  std::array<double, 2> ball{0, 0};  ///< [m] where the ball lay (the tee unless a ball region)
  bool found = false;                ///< a sinking putt with a verified neighbourhood (or margin 0)
  double angle = 0.0;                ///< [rad] hitting angle theta
  double speed = 0.0;                ///< [m/s] club speed v
  double margin_angle = 0.0;         ///< [rad] verified: theta +- this sinks (0: not verified)
  double margin_speed = 0.0;         ///< [m/s] verified: v +- this sinks (0 for angle only)
  double launch_angle = 0.0;         ///< [rad] measured ball launch of the example's putt
  double launch_speed = 0.0;         ///< [m/s]
  double approach_speed = 0.0;       ///< [m/s] ball speed at the hole (closest approach)
  int full_putts = 0;                ///< full-system putts this example cost
  int ball_putts = 0;                ///< ball-only putts this example cost
};

/// Finds an example for `hole`, the ball on the tee (see the file comment).
Example teach(const system::System& system, system::SystemData& data, std::array<double, 2> hole,
              const TeacherOptions& options);
/// The same for the ball at situation.ball: the base stands beside it as beside the tee (the
/// stance rule for hits, system::hit_pose), so angles are world angles as from the tee.
Example teach(const system::System& system, system::SystemData& data,
              const field::Situation& situation, const TeacherOptions& options);

/// The target arrival speed [m/s] of `strategy` for the field's hole.
double arrival_speed(const field::Field& field, Strategy strategy);

}  // namespace mg::teacher
