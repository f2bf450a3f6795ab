// The controller knows no simulator. Its headers (the module and what it includes: the
// arm interface, the config, the state machine, the hitting DS, perception, the arm model) are
// compiled here alone: had one of them included MuJoCo, mjVERSION_HEADER would be defined.
#include "control/arm_interface.hpp"
#include "control/minigolf_module.hpp"

#ifdef mjVERSION_HEADER
#error \
    "the controller's headers include mujoco.h: the simulator belongs to sim_backend/mujoco_arm.hpp"
#endif

#include <gtest/gtest.h>

namespace mg::control {
namespace {

// The module is built and run without any simulator: an arm model from the mount, a ball radius.
TEST(ControllerHeaders, TheModuleNeedsNoSimulator) {
  const ModuleModel model(robot::ArmModel(robot::WamMount{}),
                          ds::read_hitting_model(std::string(MINIGOLF_SOURCE_DIR) +
                                                 "/data/models/hitting-default.json"),
                          ControllerConfig{}, 0.021335);  // no file, address or thread
  ModuleData data(model);
  robot::Vector7 q;
  for (int j = 0; j < 7; ++j) q[j] = robot::kDefaultRestPosture[static_cast<std::size_t>(j)];
  module_reset(model, data, q);
  MeasuredState s;
  s.q = q;
  const ModuleCommand c = module_update(model, data, s);
  EXPECT_EQ(c.state, ModuleState::kIdle);
  EXPECT_TRUE(c.tau.allFinite());
}

}  // namespace
}  // namespace mg::control
