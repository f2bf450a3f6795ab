#pragma once
/// Drawing a minigolf world with MuJoCo's renderer (mjv scene + mjr context) into a GLFW window or
/// an off-screen buffer. The renderer owns a copy of the model and its own mjData: the simulation's
/// state is copied in (pose only), so drawing can never change a simulation.
///
/// Needs an OpenGL context: GlWindow makes one from a GLFW window, shown (the viewer) or hidden
/// (off-screen rendering, e.g. under `xvfb-run -a`). Without a display it throws Error with one
/// line saying so.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include <mujoco/mujoco.h>

#include "sim/world.hpp"
#include "viz/image.hpp"

struct GLFWwindow;

namespace mg::viz {

/// InputError unless `width` x `height` is 16..4096 pixels each way.
void check_image_size(int width, int height);

/// A GLFW window with a current OpenGL context. Throws InputError for a bad size, Error (one line)
/// when GLFW cannot start (no display) or the window cannot be made. GLFW stays started until the
/// process exits, so windows may come and go and live side by side.
class GlWindow {
 public:
  GlWindow(int width, int height, bool visible, const std::string& title);
  ~GlWindow();
  GlWindow(const GlWindow&) = delete;
  GlWindow& operator=(const GlWindow&) = delete;
  GLFWwindow* handle() const { return window_; }
  /// Makes this window's OpenGL context current on the calling thread.
  void make_current();
  /// Leaves the calling thread without a current context (so another thread may take it).
  static void release_current();
  /// The framebuffer's size [pixels] (the window's, times the screen's scale).
  std::array<int, 2> framebuffer_size() const;
  /// Shows what was drawn (visible windows) and handles the window's events.
  void present();
  /// True once the user asked to close the window.
  bool should_close() const;

 private:
  GLFWwindow* window_ = nullptr;
};

/// The pose of a simulation (what drawing needs): time, joint positions, mocap bodies, and the
/// user data (the world keeps the hole position there).
struct Pose {
  double time = 0.0;
  std::vector<mjtNum> qpos, mocap_pos, mocap_quat, userdata;
};
Pose capture_pose(const mjModel* m, const mjData* d);
/// Copies qpos, mocap, user data and time of `src` into `dst` (same model layout); no allocation.
void copy_pose(const mjModel* m, const mjData* src, mjData* dst);

/// What is drawn on top of the model.
struct Decorations {
  bool hole_marker = true;  ///< a dark disc and a flag at the hole (the heightfield covers the cup)
  std::optional<double> aim_angle;          ///< [rad] an arrow from the ball: the hitting direction
  std::vector<std::array<double, 3>> path;  ///< the ball's path [m], drawn as a line
  std::string label;                        ///< text at the top left
  std::string overlay;                      ///< text block at the bottom left
};

/// Camera presets: "overview" (behind the tee, the lane and the hole), "side" (across the lane at
/// the arm and the ball), "top" (the whole lane from above), "follow" (tracks the ball).
const std::vector<std::string>& camera_names();
/// InputError for an unknown name.
mjvCamera camera_preset(const std::string& name, const sim::World& world, const mjData* d);

/// Errors: the constructor throws InputError for a bad size and Error when the model cannot be
/// copied. MuJoCo's own fatal errors while drawing (an OpenGL context too old, no framebuffer) go
/// to its process-wide handler, which the renderer leaves alone: the `minigolf` command and the
/// Python module set one that prints one line and exits 1 (sim/mujoco_errors.hpp).
class Renderer {
 public:
  /// Needs a current OpenGL context. `width` x `height`: the off-screen buffer [pixels].
  Renderer(const sim::World& world, int width, int height);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  const mjModel* model() const { return m_; }
  mjData* data() {
    return d_;
  }  ///< the renderer's own state: copy a pose in (copy_pose / set_pose)
  void set_pose(const Pose& pose);
  int width() const { return width_; }
  int height() const { return height_; }

  /// Builds the scene from data() with the camera and the decorations.
  void update_scene(mjvCamera& camera, const Decorations& decorations);
  /// Draws the scene into the current framebuffer's `viewport` (window or off-screen).
  void draw(mjrRect viewport, const Decorations& decorations);
  /// update_scene + draw into the off-screen buffer + read back (rows top down).
  Image render(mjvCamera& camera, const Decorations& decorations);
  /// Reads the current framebuffer's `viewport` (rows top down).
  Image read(mjrRect viewport);

  /// Pixel (column, row from the top) of world point `p` in the last scene drawn at the
  /// off-screen size; nullopt behind the camera.
  std::optional<std::array<double, 2>> project(const std::array<double, 3>& p) const;

  mjvScene& scene() { return scn_; }
  mjrContext& context() { return con_; }
  mjvOption& option() { return opt_; }

 private:
  const sim::World& world_;
  mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
  int width_, height_;
  mjvScene scn_;
  mjvOption opt_;
  mjrContext con_;
};

}  // namespace mg::viz
