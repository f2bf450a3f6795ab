#include "viz/viewer.hpp"

#include <poll.h>
#include <unistd.h>

#include <GLFW/glfw3.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/io.hpp"
#include "system/session.hpp"
#include "viz/renderer.hpp"

namespace mg::viz {

namespace {

using control::ModuleState;

/// The ball's path since the latest hit, kept after every physics step on the stepping thread
/// (the core thread in real-time mode: a preallocated array, no allocation, no lock) and read by
/// the drawing thread. Each point is published by the count (release/acquire); a point rewritten
/// after a new hit while being drawn only bends that frame's path.
class PathObserver final : public system::SessionObserver {
 public:
  static constexpr int kCapacity = 6000;  ///< 60 s at 10 ms

  void after_step(const system::SessionView& v) override {
    const double t = v.d->time;
    const ModuleState state = v.module.state;
    if (state == ModuleState::kHitting && previous_ != ModuleState::kHitting)
      count_.store(0, std::memory_order_release);
    previous_ = state;
    const int n = count_.load(std::memory_order_relaxed);
    if ((v.module.ball_hit || v.ball_rolling) && t >= next_ && n < kCapacity) {
      const mjtNum* b = v.d->qpos + v.world.ids().ball_qpos;
      for (int k = 0; k < 3; ++k)
        path_[static_cast<std::size_t>(n)][static_cast<std::size_t>(k)].store(
            b[k], std::memory_order_relaxed);
      count_.store(n + 1, std::memory_order_release);
      next_ = t + 0.01;
    }
    if (!v.ball_rolling && !v.module.ball_hit) next_ = 0.0;
  }

  /// The path so far (any thread).
  void copy_to(std::vector<std::array<double, 3>>& out) const {
    const int n = count_.load(std::memory_order_acquire);
    out.resize(static_cast<std::size_t>(n));
    for (std::size_t i = 0; i < out.size(); ++i)
      for (std::size_t k = 0; k < 3; ++k) out[i][k] = path_[i][k].load(std::memory_order_relaxed);
  }

 private:
  std::array<std::array<std::atomic<double>, 3>, kCapacity> path_{};
  std::atomic<int> count_{0};
  ModuleState previous_ = ModuleState::kIdle;  ///< the stepping thread's
  double next_ = 0.0;                          ///< the stepping thread's
};

struct Mouse {
  bool left = false, middle = false, right = false;
  double x = 0.0, y = 0.0;
  Renderer* renderer = nullptr;
  mjvCamera* camera = nullptr;
};

void on_button(GLFWwindow* w, int, int, int) {
  auto* m = static_cast<Mouse*>(glfwGetWindowUserPointer(w));
  m->left = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
  m->middle = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS;
  m->right = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
  glfwGetCursorPos(w, &m->x, &m->y);
}

void on_move(GLFWwindow* w, double x, double y) {
  auto* m = static_cast<Mouse*>(glfwGetWindowUserPointer(w));
  if (!m->left && !m->middle && !m->right) return;
  const double dx = x - m->x, dy = y - m->y;
  m->x = x;
  m->y = y;
  int width = 0, height = 0;
  glfwGetWindowSize(w, &width, &height);
  if (height <= 0) return;
  const bool shift = glfwGetKey(w, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ||
                     glfwGetKey(w, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS;
  mjtMouse action = mjMOUSE_ZOOM;
  if (m->right)
    action = shift ? mjMOUSE_MOVE_H : mjMOUSE_MOVE_V;
  else if (m->left)
    action = shift ? mjMOUSE_ROTATE_H : mjMOUSE_ROTATE_V;
  mjv_moveCamera(m->renderer->model(), action, dx / height, dy / height, &m->renderer->scene(),
                 m->camera);
}

void on_scroll(GLFWwindow* w, double, double dy) {
  auto* m = static_cast<Mouse*>(glfwGetWindowUserPointer(w));
  mjv_moveCamera(m->renderer->model(), mjMOUSE_ZOOM, 0, -0.05 * dy, &m->renderer->scene(),
                 m->camera);
}

void on_key(GLFWwindow* w, int key, int, int action, int) {
  if (key == GLFW_KEY_ESCAPE && action == GLFW_PRESS) glfwSetWindowShouldClose(w, GLFW_TRUE);
}

/// Lines from standard input without blocking past an interrupt: polls every 100 ms.
bool read_line_interruptible(std::string& line, const system::Session& session) {
  line.clear();
  for (;;) {
    if (session.interrupted()) return false;
    pollfd p{STDIN_FILENO, POLLIN, 0};
    const int r = ::poll(&p, 1, 100);
    if (r < 0) return false;
    if (r == 0) continue;
    char c = 0;
    const ssize_t n = ::read(STDIN_FILENO, &c, 1);
    if (n <= 0) return !line.empty();
    if (c == '\n') return true;
    line += c;
  }
}

std::string overlay_text(const system::SessionView& v) {
  std::string text = fmt::format("t {:.2f} s   state {}   angle {:.3f} rad   speed {:.2f} m/s{}",
                                 v.d->time, control::to_string(v.module.state), v.angle, v.speed,
                                 v.hit_armed ? "   (hit armed)" : "");
  const auto hole = v.world.hole_position(v.d);
  if (v.ball_rolling) {
    text += "\nball rolling";
  } else if (v.last_outcome) {
    const auto& o = *v.last_outcome;
    text += fmt::format("\nlast hit: {} at ({:.3f}, {:.3f}), {:.3f} m from the hole",
                        o.sunk ? "holed" : sim::to_string(o.end), o.rest_position[0],
                        o.rest_position[1],
                        std::hypot(o.rest_position[0] - hole[0], o.rest_position[1] - hole[1]));
  } else {
    text += "\nno hit yet";
  }
  return text;
}

}  // namespace

void run_viewer(const control::ModuleConfig& config, const ViewerOptions& options) {
  std::istringstream script;  // read whole and bounded: a FIFO or /dev/zero is refused
  if (!options.script.empty()) script.str(read_text_file(options.script));
  GlWindow window(options.width, options.height, true, "minigolf view");
  PathObserver observer;
  system::SessionOptions so;
  so.realtime = options.realtime;
  so.paced = !options.realtime;
  so.echo = options.echo;
  so.observer = &observer;
  system::Session session(config, so, std::cout);

  const sim::World* world = nullptr;
  session.inspect([&](const system::SessionView& v) { world = &v.world; });
  Renderer renderer(*world, options.width, options.height);
  session.inspect(
      [&](const system::SessionView& v) { copy_pose(world->model(), v.d, renderer.data()); });
  mjvCamera camera = camera_preset(options.camera, *world, renderer.data());

  Mouse mouse;
  mouse.renderer = &renderer;
  mouse.camera = &camera;
  glfwSetWindowUserPointer(window.handle(), &mouse);
  glfwSetMouseButtonCallback(window.handle(), on_button);
  glfwSetCursorPosCallback(window.handle(), on_move);
  glfwSetScrollCallback(window.handle(), on_scroll);
  glfwSetKeyCallback(window.handle(), on_key);

  std::atomic<bool> done{false};
  const bool interactive = options.script.empty() && isatty(STDIN_FILENO) != 0;
  std::thread commands([&] {
    std::string line;
    for (;;) {
      if (interactive) {
        std::cout << "minigolf> " << std::flush;
      }
      const bool got = options.script.empty() ? read_line_interruptible(line, session)
                                              : static_cast<bool>(std::getline(script, line));
      if (session.interrupted()) break;
      if (!got) {
        std::cout << "end of input: quit\n" << std::flush;
        break;
      }
      if (!session.execute(line)) break;
    }
    done = true;
  });

  // The command thread must be joined whatever happens below.
  struct JoinGuard {
    system::Session& session;
    std::thread& thread;
    ~JoinGuard() {
      session.interrupt();
      if (thread.joinable()) thread.join();
    }
  } guard{session, commands};

  Decorations deco;
  deco.path.reserve(PathObserver::kCapacity);
  Image last;
  auto next_frame = std::chrono::steady_clock::now();
  for (;;) {
    const bool closing = glfwWindowShouldClose(window.handle()) != 0;
    if (closing) session.interrupt();
    const bool finished = done.load() || closing;
    session.inspect([&](const system::SessionView& v) {
      copy_pose(world->model(), v.d, renderer.data());
      deco.overlay = overlay_text(v);
      deco.aim_angle = v.angle;
      observer.copy_to(deco.path);
    });
    int w = 0, h = 0;
    glfwGetFramebufferSize(window.handle(), &w, &h);
    const mjrRect viewport{0, 0, w, h};
    mjr_setBuffer(mjFB_WINDOW, &renderer.context());
    renderer.update_scene(camera, deco);
    renderer.draw(viewport, deco);
    if (finished && !options.screenshot.empty()) last = renderer.read(viewport);
    glfwSwapBuffers(window.handle());
    glfwPollEvents();
    if (finished) break;
    // At most 60 frames a second: a software GL (Xvfb) does not wait for a vertical retrace.
    next_frame += std::chrono::microseconds(16667);
    const auto now = std::chrono::steady_clock::now();
    if (next_frame < now) next_frame = now;
    std::this_thread::sleep_until(next_frame);
  }
  commands.join();
  if (!options.screenshot.empty()) {
    write_png(options.screenshot, last);
    std::cout << fmt::format("screenshot written: {} ({}x{})\n", options.screenshot.string(),
                             last.width, last.height);
  }
}

}  // namespace mg::viz
