#include "sim/mujoco_errors.hpp"

#include <cstdio>
#include <cstdlib>

#include <mujoco/mujoco.h>

namespace mg::sim {
namespace {

void print_and_exit(const char* text) {
  std::fprintf(stderr, "minigolf: error: MuJoCo: %s\n", text);
  std::fflush(stderr);
  std::_Exit(1);
}

void print_warning(const char* text) {
  std::fprintf(stderr, "minigolf: warning: MuJoCo: %s\n", text);
  std::fflush(stderr);
}

}  // namespace

void exit_on_mujoco_error() { mju_user_error = print_and_exit; }

void print_mujoco_warnings() { mju_user_warning = print_warning; }

}  // namespace mg::sim
