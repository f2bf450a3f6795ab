#include "sim_backend/arm_mujoco.hpp"

#include <fmt/format.h>

#include <cstring>
#include <memory>

#include "core/error.hpp"

namespace mg::robot {
namespace {

int require_id(const mjModel* m, mjtObj type, const std::string& name) {
  const int id = mj_name2id(m, type, name.c_str());
  if (id < 0)
    throw InputError(fmt::format("WAM model: expected an element named '{}', found none", name));
  return id;
}

}  // namespace

ArmIds find_arm_ids(const mjModel* m) {
  if (m == nullptr) throw InputError("WAM model: expected an mjModel, got a null pointer");
  ArmIds ids;
  for (int i = 0; i < kNumJoints; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const int j = require_id(m, mjOBJ_JOINT, fmt::format("wam_j{}", i + 1));
    if (m->jnt_type[j] != mjJNT_HINGE)
      throw InputError(fmt::format("WAM model: joint wam_j{} is not a hinge", i + 1));
    ids.qpos[k] = m->jnt_qposadr[j];
    ids.dof[k] = m->jnt_dofadr[j];
    ids.actuator[k] = require_id(m, mjOBJ_ACTUATOR, fmt::format("wam_m{}", i + 1));
  }
  ids.site = require_id(m, mjOBJ_SITE, "club_face");
  ids.flange_body = require_id(m, mjOBJ_BODY, "wam_link7");
  return ids;
}

ArmModel arm_model_from_mujoco(const mjModel* m, const WamMount& mount) {
  const ArmIds ids = find_arm_ids(m);
  JointParameters joints;
  for (int i = 0; i < kNumJoints; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const int j = mj_name2id(m, mjOBJ_JOINT, fmt::format("wam_j{}", i + 1).c_str());
    joints.lower(i) = m->jnt_range[2 * j];
    joints.upper(i) = m->jnt_range[2 * j + 1];
    joints.armature(i) = m->dof_armature[ids.dof[k]];
    joints.damping(i) = m->dof_damping[ids.dof[k]];
    joints.torque_limit(i) = m->actuator_ctrlrange[2 * ids.actuator[k] + 1];
  }
  joints.gravity_world = Eigen::Vector3d(m->opt.gravity[0], m->opt.gravity[1], m->opt.gravity[2]);
  ArmModel arm(mount, joints);

  // The compiled link-1 frame at q = 0 must be world_T_0 * A_1(0): otherwise the mount passed
  // here is not the one the model was generated from.
  mjData* d = mj_makeData(m);
  if (d == nullptr) throw Error("MuJoCo: cannot allocate mjData");
  for (int i = 0; i < kNumJoints; ++i) d->qpos[ids.qpos[static_cast<std::size_t>(i)]] = 0.0;
  mj_kinematics(m, d);
  const int link1 = mj_name2id(m, mjOBJ_BODY, "wam_link1");
  if (link1 < 0) {
    mj_deleteData(d);
    throw InputError("WAM model: expected an element named 'wam_link1', found none");
  }
  Eigen::Isometry3d compiled = Eigen::Isometry3d::Identity();
  compiled.translation() = Eigen::Vector3d(d->xpos + 3 * link1);
  compiled.linear() = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>(d->xmat + 9 * link1);
  mj_deleteData(d);
  const Eigen::Isometry3d expected = arm.shoulder_in_world() * dh_link_transform(1, 0.0);
  const double mismatch = (compiled.matrix() - expected.matrix()).cwiseAbs().maxCoeff();
  if (!(mismatch < 1e-9))
    throw InputError(fmt::format(
        "WAM model: the compiled base does not match the given mount (max difference {})",
        mismatch));
  return arm;
}

Vector7 joint_positions(const ArmIds& arm, const mjData* d) {
  Vector7 q;
  for (int i = 0; i < kNumJoints; ++i) q(i) = d->qpos[arm.qpos[static_cast<std::size_t>(i)]];
  return q;
}

Vector7 joint_velocities(const ArmIds& arm, const mjData* d) {
  Vector7 qd;
  for (int i = 0; i < kNumJoints; ++i) qd(i) = d->qvel[arm.dof[static_cast<std::size_t>(i)]];
  return qd;
}

void set_joint_positions(const ArmIds& arm, mjData* d, const Vector7& q) {
  for (int i = 0; i < kNumJoints; ++i) d->qpos[arm.qpos[static_cast<std::size_t>(i)]] = q(i);
}

Eigen::Isometry3d club_pose(const ArmIds& arm, const mjData* d) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(d->site_xpos + 3 * arm.site);
  t.linear() = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>(d->site_xmat + 9 * arm.site);
  return t;
}

Eigen::Isometry3d flange_pose(const ArmIds& arm, const mjData* d) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(d->xpos + 3 * arm.flange_body);
  t.linear() = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>(d->xmat + 9 * arm.flange_body);
  return t;
}

void club_jacobian(const ArmIds& arm, const mjModel* m, mjData* d, Matrix67& jacobian) {
  const int nv = m->nv;
  mjMARKSTACK;
  mjtNum* jacp = mj_stackAlloc(d, 3 * nv);
  mjtNum* jacr = mj_stackAlloc(d, 3 * nv);
  mj_jacSite(m, d, jacp, jacr, arm.site);
  for (int i = 0; i < kNumJoints; ++i) {
    const int c = arm.dof[static_cast<std::size_t>(i)];
    for (int r = 0; r < 3; ++r) {
      jacobian(r, i) = jacp[r * nv + c];
      jacobian(r + 3, i) = jacr[r * nv + c];
    }
  }
  mjFREESTACK;
}

sim::ModelPtr compile_mjcf(const std::string& xml) {
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  const char* kName = "wam.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), kName, static_cast<int>(xml.size())) != 0) {
    mj_deleteVFS(vfs.get());
    throw Error("MuJoCo: cannot create the in-memory model file");
  }
  std::memcpy(vfs->filedata[mj_findFileVFS(vfs.get(), kName)], xml.data(), xml.size());
  char error[1024] = "";
  sim::ModelPtr model(mj_loadXML(kName, vfs.get(), error, sizeof error));
  mj_deleteVFS(vfs.get());
  if (!model) throw Error(fmt::format("MuJoCo rejected the WAM model: {}", error));
  return model;
}

}  // namespace mg::robot
