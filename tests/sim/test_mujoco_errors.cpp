#include "sim/mujoco_errors.hpp"

#include <mujoco/mujoco.h>

#include <gtest/gtest.h>

namespace mg::sim {
namespace {

// A MuJoCo fatal error ends the program with one line and status 1 (not MuJoCo's default: wait
// for Enter); only a program that asks for it gets the handler.
TEST(MujocoErrors, FatalErrorPrintsOneLineAndExitsOne) {
  EXPECT_EQ(mju_user_error, nullptr);
  EXPECT_EXIT(
      {
        exit_on_mujoco_error();
        mju_error("the stack is full");
      },
      ::testing::ExitedWithCode(1), "^minigolf: error: MuJoCo: the stack is full\n$");
  EXPECT_EQ(mju_user_error, nullptr);  // the death test's child set it, not this process
}

}  // namespace
}  // namespace mg::sim
