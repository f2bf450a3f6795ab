// minigolf.Renderer: frames of a world drawn by MuJoCo's renderer (src/viz) as numpy images, off
// screen (a hidden GLFW window: under `xvfb-run -a` on a server) or in a window of its own. The
// renderer keeps its own copy of the model and its own mjData, so drawing never changes a
// simulation. OpenGL contexts belong to one thread: use a Renderer from the thread that made it.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <cmath>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "python/bindings.hpp"
#include "sim/mujoco_errors.hpp"
#include "viz/renderer.hpp"

namespace py = pybind11;

namespace mg::python {
namespace {

using Points = py::array_t<double, py::array::c_style | py::array::forcecast>;

class PyRenderer {
 public:
  PyRenderer(const sim::World& world, int width, int height, bool visible, std::string camera)
      : world_(world), camera_name_(std::move(camera)) {
    viz::camera_preset(camera_name_, world_,
                       probe());  // an unknown name fails before a window opens
    // MuJoCo's fatal errors while drawing end the process with one line (sim/mujoco_errors.hpp),
    // not with MuJoCo's wait for Enter: the Python module's choice, made where it draws.
    sim::exit_on_mujoco_error();
    window_ = std::make_unique<viz::GlWindow>(width, height, visible, "minigolf");
    renderer_ = std::make_unique<viz::Renderer>(world_, width, height);
    visible_ = visible;
  }

  /// The frame of `data` (pose copied in), with the ball moved to `ball` [m] when given and the
  /// `path` (N x 2 or N x 3 [m]) drawn as a line. Rows top down, (height, width, 3) uint8.
  py::array_t<std::uint8_t> render(const Data& data, std::optional<std::array<double, 3>> ball,
                                   const Points& path, const std::string& label) {
    prepare(data, ball, path, label);
    const viz::Image image = renderer_->render(camera_, decorations_);
    py::array_t<std::uint8_t> out({image.height, image.width, 3});
    std::memcpy(out.mutable_data(), image.rgb.data(), image.rgb.size());
    return out;
  }

  /// Draws the same frame into the window (visible renderers). False once the window was closed.
  bool show(const Data& data, std::optional<std::array<double, 3>> ball, const Points& path,
            const std::string& label) {
    if (!visible_)
      throw InputError("Renderer.show: this renderer is off screen (make it with visible=True)");
    prepare(data, ball, path, label);
    const auto [w, h] = window_->framebuffer_size();
    mjr_setBuffer(mjFB_WINDOW, &renderer_->context());
    renderer_->update_scene(camera_, decorations_);
    renderer_->draw(mjrRect{0, 0, w, h}, decorations_);
    window_->present();
    return !window_->should_close();
  }

  void close() {
    if (window_) window_->make_current();
    renderer_.reset();
    window_.reset();
  }

  int width() const { return live().width(); }
  int height() const { return live().height(); }
  bool closed() const { return !renderer_; }

 private:
  const viz::Renderer& live() const {
    if (!renderer_) throw InputError("Renderer: closed");
    return *renderer_;
  }

  /// A data of the world for checking the camera's name before any window is made.
  const mjData* probe() {
    probe_ = world_.make_data();
    return probe_.get();
  }

  void prepare(const Data& data, const std::optional<std::array<double, 3>>& ball,
               const Points& path, const std::string& label) {
    live();
    const mjData* src = data_of(world_, data);
    window_->make_current();
    viz::copy_pose(world_.model(), src, renderer_->data());
    if (ball) {
      for (double c : *ball)
        if (!std::isfinite(c)) throw InputError("Renderer: ball: expected a finite (x, y, z) [m]");
      std::copy(ball->begin(), ball->end(), renderer_->data()->qpos + world_.ids().ball_qpos);
    }
    decorations_ = viz::Decorations{};
    decorations_.label = label;
    if (path.size() > 0) {
      if (path.ndim() != 2 || (path.shape(1) != 2 && path.shape(1) != 3))
        throw InputError(
            fmt::format("Renderer: path: expected an (N, 2) or (N, 3) array [m], got {} dimensions",
                        path.ndim()));
      const auto p = path.unchecked<2>();
      const field::Field& f = world_.field();
      for (py::ssize_t i = 0; i < p.shape(0); ++i) {
        const double x = p(i, 0), y = p(i, 1);
        if (!std::isfinite(x) || !std::isfinite(y))
          throw InputError("Renderer: path: expected finite points");
        const double z = p.shape(1) == 3 ? p(i, 2) : f.height(x, y) + f.ball.radius;
        decorations_.path.push_back({x, y, z});
      }
    }
    camera_ = viz::camera_preset(camera_name_, world_, renderer_->data());
  }

  const sim::World& world_;
  std::string camera_name_;
  sim::DataPtr probe_;
  std::unique_ptr<viz::GlWindow> window_;
  std::unique_ptr<viz::Renderer> renderer_;
  bool visible_ = false;
  mjvCamera camera_{};
  viz::Decorations decorations_;
};

}  // namespace

void bind_render(py::module_& m) {
  py::class_<PyRenderer>(
      m, "Renderer",
      "Frames of a World drawn by MuJoCo's renderer: off screen (needs a display; on a server run "
      "under `xvfb-run -a`) or in a window (visible=True). Draws its own copy of the model, so a "
      "simulation is never changed. Use it from the thread that made it.")
      .def(py::init<const sim::World&, int, int, bool, std::string>(), py::arg("world"),
           py::arg("width") = 640, py::arg("height") = 480, py::arg("visible") = false,
           py::arg("camera") = "overview", py::keep_alive<1, 2>(),
           "camera: 'overview', 'side', 'top' or 'follow'. Raises RuntimeError without a display, "
           "ValueError "
           "for a bad size (16..4096) or camera.")
      .def("render", &PyRenderer::render, py::arg("data"), py::arg("ball") = py::none(),
           py::arg("path") = Points(std::vector<py::ssize_t>{0, 2}), py::arg("label") = "",
           "The frame of `data` (a Data of the same world) as an (height, width, 3) uint8 array, "
           "rows top down; "
           "ball: draw the ball at (x, y, z) [m] instead; path: (N, 2) or (N, 3) points [m] drawn "
           "as a line "
           "(N x 2: on the lane at ball height); label: text at the top left.")
      .def("show", &PyRenderer::show, py::arg("data"), py::arg("ball") = py::none(),
           py::arg("path") = Points(std::vector<py::ssize_t>{0, 2}), py::arg("label") = "",
           "Draws the same frame into the window (visible=True). Returns False once the window was "
           "closed.")
      .def("close", &PyRenderer::close, "Frees the OpenGL context and the window (idempotent)")
      .def_property_readonly("closed", &PyRenderer::closed)
      .def_property_readonly("width", &PyRenderer::width, "[pixels]")
      .def_property_readonly("height", &PyRenderer::height, "[pixels]");
}

}  // namespace mg::python
