#pragma once
/// Barrett WAM 7-DoF parameters from the published DH table and inertia (docs/robot.md) and our own
/// picks (armature, damping, velocity limits, golf club), in one place.
///
/// Frames: DH link frame i (Spong convention, i = 1..7) is attached to link i; joint i turns about
/// z of frame i-1. Frame 0 ("shoulder frame") sits at the J1/J2 axis intersection, z up, and is
/// fixed to the mounting plate `kShoulderHeight` above it. Units: SI, radians.
#include <array>

namespace mg::robot {

inline constexpr int kNumJoints = 7;
inline constexpr double kPi = 3.14159265358979323846;

/// One row of the DH table (Spong: A_i = Rz(theta) Tz(d) Tx(a) Rx(alpha)); all theta offsets 0.
struct DhRow {
  double a;      ///< [m] along x_i
  double alpha;  ///< [rad] about x_i
  double d;      ///< [m] along z_{i-1}
};

/// WAM manual D1001 Table 5 / libbarrett wam7w.conf. Zero pose = arm straight up.
inline constexpr std::array<DhRow, kNumJoints> kDhTable{{
    {0.0, -kPi / 2, 0.0},
    {0.0, +kPi / 2, 0.0},
    {0.045, -kPi / 2, 0.55},
    {-0.045, +kPi / 2, 0.0},
    {0.0, -kPi / 2, 0.30},
    {0.0, +kPi / 2, 0.0},
    {0.0, 0.0, 0.0609},
}};

/// [m] height of frame 0 (J1/J2 axes) above the base mounting plate.
inline constexpr double kShoulderHeight = 0.346;

/// [rad] joint position limits (manual Table 6), (7).
inline constexpr std::array<double, kNumJoints> kJointLower{-2.6,  -2.0, -2.8, -0.9,
                                                            -4.76, -1.6, -3.0};
inline constexpr std::array<double, kNumJoints> kJointUpper{2.6, 2.0, 2.8, 3.1, 1.24, 1.6, 3.0};

/// [N m] model torque limits used as actuator ctrlrange, (7).
inline constexpr std::array<double, kNumJoints> kTorqueLimit{60, 60, 45, 30, 10, 10, 10};

/// [rad/s] joint velocity limits, (7). Our pick: no joint-level figure is published with the
/// tables. Sized so the club face can reach the WAM's published 3 m/s end-point maximum along the
/// hitting direction with the face heading held (the putting task): at the impact postures for
/// theta in [0, 0.6] rad that needs about (5.4, 0.2, 0.3-1.3, 0.4-4.9, 4.5-6.4, 0.7-5.6, 0.4-1.3)
/// rad/s (limit-weighted least-norm J^+ v, notes/robot.md), and a measured 2.5 m/s putt uses up to
/// (5.0, 0.9, 0.8, 5.9, 4.7, 6.1, 2.2) rad/s. Through the published transmission ratios (about
/// 42, 28.25, 28.25, 18 at J1-J4, 10-15 at the wrist) these are motor speeds of roughly
/// 1100-2200 rpm, ordinary for the WAM's brushless motors. The previous (2.0, 2.0, 2.5, 2.5, 3,
/// 3, 3) capped the club at ~1.4 m/s (not enough for a 2 m putt).
inline constexpr std::array<double, kNumJoints> kVelocityLimit{5.5,  5.5,  7.0, 7.0,
                                                               10.0, 10.0, 10.0};

/// [m/s] end-point (club face) speed limits: the libbarrett safety rule, and the WAM maximum.
inline constexpr double kSafeEndpointSpeed = 1.5;
inline constexpr double kMaxEndpointSpeed = 3.0;

/// [kg m^2] reflected rotor inertia per joint (MJCF `armature`), (7). J1, J2 from PHYSICS.md
/// (0.205, 0.094). Our picks for the rest: they scale with the square of the transmission ratio,
/// libbarrett's base ratios are about 42 : 28.25 : 28.25 : 18 and the wrist ones about 9.5-15 with
/// smaller motors, so J3 ~ J2, J4 ~ 0.04, wrist 3.5e-3 / 3.5e-3 / 1e-3.
inline constexpr std::array<double, kNumJoints> kArmature{0.205,  0.094,  0.094, 0.040,
                                                          0.0035, 0.0035, 0.0010};

/// [N m s/rad] viscous joint damping (MJCF `damping`), (7). Small; our pick.
inline constexpr std::array<double, kNumJoints> kDamping{0.10, 0.10, 0.05, 0.05, 0.01, 0.01, 0.01};

/// Rigid-body parameters of one link in its DH frame. The inertia tensor is taken about the COM,
/// axes parallel to the DH frame (libbarrett convention); entries are tensor elements.
struct LinkInertial {
  double mass;                    ///< [kg]
  std::array<double, 3> com;      ///< [m] DH link frame
  std::array<double, 6> inertia;  ///< [kg m^2] Ixx Iyy Izz Ixy Ixz Iyz (MJCF fullinertia order)
};

/// libbarrett wam7w.conf "inertial specifications Sept 2008".
inline constexpr std::array<LinkInertial, kNumJoints> kLinkInertials{{
    {10.7677,
     {-0.00443, 0.12189, -0.00066},
     {0.13488, 0.11328, 0.09046, -0.00213, -0.000125, 0.000686}},
    {3.8749,
     {-0.00237, 0.03106, 0.01542},
     {0.02141, 0.01378, 0.01559, 0.000272, 0.0000246, -0.00182}},
    {1.8023,
     {-0.03826, 0.20751, 0.00003},
     {0.05911, 0.003246, 0.05927, -0.00250, 0.0000074, -0.0000177}},
    {2.17266,
     {0.00553, 0.0000682, 0.11928},
     {0.010675, 0.010587, 0.002820, 0.0000450, -0.00135557, -0.000110}},
    {0.35656, {0.0000548, 0.02886, 0.00148}, {0.000371, 0.000194, 0.000382, 0.0, 0.0, -0.0000161}},
    {0.40916,
     {-0.0000592, -0.01686, 0.02419},
     {0.000549, 0.000238, 0.000451, 0.0, 0.0, -0.0000443}},
    {0.07548, {0.000148, 0.0000725, -0.00335}, {0.0000391, 0.0000388, 0.0000761, 0.0, 0.0, 0.0}},
}};

/// The golf club (our design, after thesis figure 4.6): a straight shaft along +z of the flange
/// (link-7) frame, ending at the heel of a box putter head. The head's heel-to-toe axis makes the
/// lie angle with the shaft; the face normal is perpendicular to both (zero loft). With the face
/// vertical the shaft therefore leans (90 deg - lie) off vertical, towards the robot.
struct ClubGeometry {
  double shaft_length = 0.70;    ///< [m] flange to the head's heel
  double shaft_radius = 0.006;   ///< [m]
  double shaft_mass = 0.10;      ///< [kg]
  double lie_angle = 1.2217;     ///< [rad] between the shaft and the sole on the heel side (70 deg)
  double head_length = 0.10;     ///< [m] heel to toe
  double head_thickness = 0.03;  ///< [m] face to back
  double head_height = 0.025;    ///< [m] sole to top
  double head_mass = 0.30;       ///< [kg]
  /// Coefficient of restitution of face and ball (a putter and a golf ball: ~0.8; putters give
  /// ball speed / club speed 1.6-1.9, notes/robot.md).
  double face_restitution = 0.8;
  /// [s] natural period of the face-ball contact spring: 8 physics steps of 1 ms, so the impact
  /// is resolved (a stiffer contact would bounce numerically).
  double face_contact_period = 0.008;
};

}  // namespace mg::robot
