#include "robot/dynamics.hpp"

namespace mg::robot {
namespace {

struct Rigid {
  double mass;
  Eigen::Vector3d com;      // DH link frame
  Eigen::Matrix3d inertia;  // about the COM, link-frame axes
};

Rigid to_rigid(const LinkInertial& l) {
  const auto& i = l.inertia;
  Rigid r{l.mass, Eigen::Vector3d(l.com.data()), Eigen::Matrix3d()};
  r.inertia << i[0], i[3], i[4], i[3], i[1], i[5], i[4], i[5], i[2];
  return r;
}

// Plain RNEA in frame 0 (the shoulder frame). Joint i turns about z_{i-1} through p_{i-1}.
// Gravity enters as a base acceleration of -g.
void rnea(const ArmModel& arm, const Vector7& q, const Vector7& qd, const Vector7& qdd,
          bool gravity, Vector7& tau) {
  std::array<Eigen::Matrix3d, kNumJoints> rot;
  std::array<Eigen::Vector3d, kNumJoints + 1> origin, axis;  // index i: frame i (0..7)
  std::array<Eigen::Vector3d, kNumJoints> force, torque;     // per link: m a_c, I alpha + w x I w
  std::array<Eigen::Vector3d, kNumJoints> com;               // COM positions, frame 0

  origin[0].setZero();
  axis[0] = Eigen::Vector3d::UnitZ();
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  Eigen::Vector3d w = Eigen::Vector3d::Zero(), dw = Eigen::Vector3d::Zero();
  Eigen::Vector3d acc = gravity ? Eigen::Vector3d(-arm.gravity()) : Eigen::Vector3d::Zero();

  for (int i = 0; i < kNumJoints; ++i) {
    const auto k = static_cast<std::size_t>(i);
    t = t * dh_link_transform(i + 1, q(i));
    rot[k] = t.linear();
    origin[k + 1] = t.translation();
    axis[k + 1] = t.linear().col(2);

    const Eigen::Vector3d& z = axis[k];
    const Eigen::Vector3d w_prev = w;
    w = w_prev + z * qd(i);
    dw = dw + z * qdd(i) + w_prev.cross(z * qd(i));
    // Acceleration of the frame-i origin: p_{i-1} lies on the joint axis, so it moves with both
    // links.
    const Eigen::Vector3d r = origin[k + 1] - origin[k];
    acc = acc + dw.cross(r) + w.cross(w.cross(r));

    const Rigid body = to_rigid(arm.inertials()[k]);
    const Eigen::Vector3d rc = rot[k] * body.com;
    com[k] = origin[k + 1] + rc;
    const Eigen::Vector3d acc_c = acc + dw.cross(rc) + w.cross(w.cross(rc));
    const Eigen::Matrix3d inertia = rot[k] * body.inertia * rot[k].transpose();
    force[k] = body.mass * acc_c;
    torque[k] = inertia * dw + w.cross(inertia * w);
  }

  // Backward pass: f, n = force/moment that link i-1 exerts on link i, moments about p_{i-1}.
  Eigen::Vector3d f = Eigen::Vector3d::Zero(), n = Eigen::Vector3d::Zero();
  for (int i = kNumJoints - 1; i >= 0; --i) {
    const auto k = static_cast<std::size_t>(i);
    const Eigen::Vector3d& p = origin[k];
    // n currently holds the moment of link i+1 about p_i = origin[k+1].
    n = n + (origin[k + 1] - p).cross(f) + torque[k] + (com[k] - p).cross(force[k]);
    f = f + force[k];
    tau(i) = n.dot(axis[k]);
  }
}

bool finite(const Vector7& v) { return v.allFinite(); }

}  // namespace

RtStatus inverse_dynamics(const ArmModel& arm, const Vector7& q, const Vector7& qd,
                          const Vector7& qdd, Vector7& tau, const DynamicsTerms& terms) {
  if (!finite(q) || !finite(qd) || !finite(qdd)) {
    tau.setZero();
    return RtStatus::kInvalidInput;
  }
  rnea(arm, q, qd, qdd, terms.gravity, tau);
  if (terms.armature) tau += arm.armature().cwiseProduct(qdd);
  if (terms.damping) tau += arm.damping().cwiseProduct(qd);
  return RtStatus::kOk;
}

RtStatus gravity_torque(const ArmModel& arm, const Vector7& q, Vector7& tau) {
  if (!finite(q)) {
    tau.setZero();
    return RtStatus::kInvalidInput;
  }
  rnea(arm, q, Vector7::Zero(), Vector7::Zero(), true, tau);
  return RtStatus::kOk;
}

RtStatus mass_matrix(const ArmModel& arm, const Vector7& q, Matrix7& mass, bool with_armature) {
  if (!finite(q)) {
    mass.setZero();
    return RtStatus::kInvalidInput;
  }
  Vector7 col;
  for (int j = 0; j < kNumJoints; ++j) {
    rnea(arm, q, Vector7::Zero(), Vector7::Unit(j), false, col);
    mass.col(j) = col;
  }
  if (with_armature) mass.diagonal() += arm.armature();
  mass = 0.5 * (mass + mass.transpose()).eval();
  return RtStatus::kOk;
}

}  // namespace mg::robot
