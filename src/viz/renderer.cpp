#include "viz/renderer.hpp"

#include <GLFW/glfw3.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <mutex>

#include <fmt/format.h>

#include "core/error.hpp"

namespace mg::viz {

namespace {

std::string glfw_last_error;

void on_glfw_error(int, const char* text) { glfw_last_error = text ? text : "unknown"; }

constexpr double kPi = 3.14159265358979323846;

void add_geom(mjvScene& scn, int type, const mjtNum size[3], const mjtNum pos[3],
              const mjtNum mat[9], const float rgba[4]) {
  if (scn.ngeom >= scn.maxgeom) return;
  mjvGeom* g = scn.geoms + scn.ngeom++;
  mjv_initGeom(g, type, size, pos, mat, rgba);
  g->category = mjCAT_DECOR;
}

void add_connector(mjvScene& scn, int type, double width, const std::array<double, 3>& a,
                   const std::array<double, 3>& b, const float rgba[4]) {
  if (scn.ngeom >= scn.maxgeom) return;
  mjvGeom* g = scn.geoms + scn.ngeom++;
  const mjtNum zero[3] = {0, 0, 0};
  mjv_initGeom(g, type, zero, zero, nullptr, rgba);
  mjv_makeConnector(g, type, width, a[0], a[1], a[2], b[0], b[1], b[2]);
  g->category = mjCAT_DECOR;
}

/// GLFW is started once per process and stopped at its exit: glfwTerminate destroys every window
/// (another GlWindow's too), and starting GLFW again right after stopping it failed now and then to
/// reach Xvfb's display.
void start_glfw() {
  static std::mutex mutex;
  static bool started = false;
  const std::lock_guard<std::mutex> lock(mutex);
  if (started) return;
  glfwSetErrorCallback(on_glfw_error);
  if (!glfwInit())
    throw Error(
        fmt::format("no display: GLFW cannot start ({}); run under `xvfb-run -a` on a "
                    "machine without a screen",
                    glfw_last_error));
  started = true;
  std::atexit(glfwTerminate);
}

/// Windows are made and destroyed one at a time (the hints and the last error are GLFW's global
/// state; threads may each own a window: one camera perception per thread).
std::mutex& window_mutex() {
  static std::mutex mutex;
  return mutex;
}

}  // namespace

void check_image_size(int width, int height) {
  if (width < 16 || height < 16 || width > 4096 || height > 4096)
    throw InputError(
        fmt::format("image size {}x{}: expected 16..4096 pixels each way", width, height));
}

GlWindow::GlWindow(int width, int height, bool visible, const std::string& title) {
  check_image_size(width, height);
  start_glfw();
  const std::lock_guard<std::mutex> lock(window_mutex());
  glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
  glfwWindowHint(GLFW_DOUBLEBUFFER, visible ? GLFW_TRUE : GLFW_FALSE);
  glfwWindowHint(GLFW_SAMPLES, 4);
  window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!window_) {
    glfwWindowHint(GLFW_SAMPLES, 0);  // some servers have no multisampled visuals
    window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  }
  if (!window_)
    throw Error(fmt::format("no OpenGL window: GLFW cannot create one ({})", glfw_last_error));
  glfwMakeContextCurrent(window_);
  if (visible) glfwSwapInterval(1);
}

GlWindow::~GlWindow() {
  const std::lock_guard<std::mutex> lock(window_mutex());
  if (window_) glfwDestroyWindow(window_);
}

void GlWindow::make_current() { glfwMakeContextCurrent(window_); }

void GlWindow::release_current() { glfwMakeContextCurrent(nullptr); }

std::array<int, 2> GlWindow::framebuffer_size() const {
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_, &w, &h);
  return {w, h};
}

void GlWindow::present() {
  glfwSwapBuffers(window_);
  glfwPollEvents();
}

bool GlWindow::should_close() const { return glfwWindowShouldClose(window_) != 0; }

Pose capture_pose(const mjModel* m, const mjData* d) {
  Pose p;
  p.time = d->time;
  p.qpos.assign(d->qpos, d->qpos + m->nq);
  p.mocap_pos.assign(d->mocap_pos, d->mocap_pos + 3 * m->nmocap);
  p.mocap_quat.assign(d->mocap_quat, d->mocap_quat + 4 * m->nmocap);
  p.userdata.assign(d->userdata, d->userdata + m->nuserdata);
  return p;
}

void copy_pose(const mjModel* m, const mjData* src, mjData* dst) {
  dst->time = src->time;
  std::memcpy(dst->qpos, src->qpos, sizeof(mjtNum) * static_cast<std::size_t>(m->nq));
  std::memcpy(dst->mocap_pos, src->mocap_pos,
              sizeof(mjtNum) * 3 * static_cast<std::size_t>(m->nmocap));
  std::memcpy(dst->mocap_quat, src->mocap_quat,
              sizeof(mjtNum) * 4 * static_cast<std::size_t>(m->nmocap));
  std::memcpy(dst->userdata, src->userdata,
              sizeof(mjtNum) * static_cast<std::size_t>(m->nuserdata));
}

const std::vector<std::string>& camera_names() {
  static const std::vector<std::string> names{"overview", "side", "top", "follow"};
  return names;
}

mjvCamera camera_preset(const std::string& name, const sim::World& world, const mjData* d) {
  const field::Field& f = world.field();
  const auto hole = world.hole_position(d);
  const double tx = f.tee[0], ty = f.tee[1];
  const double dir = std::atan2(hole[1] - ty, hole[0] - tx);
  const double length = std::hypot(hole[0] - tx, hole[1] - ty);
  mjvCamera c;
  mjv_defaultCamera(&c);
  c.type = mjCAMERA_FREE;
  if (name == "overview") {
    c.lookat[0] = tx + 0.35 * (hole[0] - tx);
    c.lookat[1] = ty + 0.35 * (hole[1] - ty) + 0.3;
    c.lookat[2] = f.height(c.lookat[0], c.lookat[1]) + 0.25;
    c.distance = 0.9 * length + 1.5;
    c.azimuth = dir * 180.0 / kPi + 50.0;  // from behind the tee, on the side away from the arm
    c.elevation = -25.0;
  } else if (name == "side") {
    c.lookat[0] = tx + 0.1;
    c.lookat[1] = ty + 0.3;
    c.lookat[2] = f.height(tx, ty) + 0.4;
    c.distance = 2.4;
    c.azimuth = 90.0;
    c.elevation = -12.0;
  } else if (name == "top") {
    c.lookat[0] = 0.5 * (f.bounds[0] + f.bounds[1]);
    c.lookat[1] = 0.5 * (f.bounds[2] + f.bounds[3]) + 0.2;
    c.lookat[2] = f.height(c.lookat[0], c.lookat[1]);
    c.distance = 1.25 * std::max(f.bounds[1] - f.bounds[0], f.bounds[3] - f.bounds[2] + 0.8);
    c.azimuth = 90.0;
    c.elevation = -89.0;
  } else if (name == "follow") {
    c.type = mjCAMERA_TRACKING;
    c.trackbodyid = world.ids().ball_body;
    c.distance = 1.4;
    c.azimuth = dir * 180.0 / kPi - 20.0;
    c.elevation = -25.0;
  } else {
    throw InputError(
        fmt::format("unknown camera '{}' (expected overview, side, top or follow)", name));
  }
  return c;
}

Renderer::Renderer(const sim::World& world, int width, int height)
    : world_(world), width_(width), height_(height) {
  check_image_size(width, height);
  m_ = mj_copyModel(nullptr, world.model());
  if (!m_) throw Error("renderer: cannot copy the model");
  m_->vis.global.offwidth = width;
  m_->vis.global.offheight = height;
  m_->vis.quality.offsamples = 4;
  d_ = mj_makeData(m_);
  mjv_defaultScene(&scn_);
  mjv_defaultOption(&opt_);
  mjr_defaultContext(&con_);
  mjv_makeScene(m_, &scn_, m_->ngeom + 3000);
  mjr_makeContext(m_, &con_, mjFONTSCALE_150);
  mj_forward(m_, d_);
}

Renderer::~Renderer() {
  mjr_freeContext(&con_);
  mjv_freeScene(&scn_);
  if (d_) mj_deleteData(d_);
  if (m_) mj_deleteModel(m_);
}

void Renderer::set_pose(const Pose& pose) {
  d_->time = pose.time;
  std::copy(pose.qpos.begin(), pose.qpos.end(), d_->qpos);
  std::copy(pose.mocap_pos.begin(), pose.mocap_pos.end(), d_->mocap_pos);
  std::copy(pose.mocap_quat.begin(), pose.mocap_quat.end(), d_->mocap_quat);
  std::copy(pose.userdata.begin(), pose.userdata.end(), d_->userdata);
}

void Renderer::update_scene(mjvCamera& camera, const Decorations& deco) {
  mj_kinematics(m_, d_);
  mj_camlight(m_, d_);
  mjv_updateScene(m_, d_, &opt_, nullptr, &camera, mjCAT_ALL, &scn_);
  const field::Field& f = world_.field();
  const auto hole = world_.hole_position(d_);
  if (deco.hole_marker) {
    const double r = 0.5 * f.hole.diameter;
    const double z = f.height(hole[0], hole[1]);
    const mjtNum disc[3] = {r, r, 0.0015};
    const mjtNum at[3] = {hole[0], hole[1], z + 0.0015};
    const float black[4] = {0.05f, 0.05f, 0.05f, 1.0f};
    add_geom(scn_, mjGEOM_CYLINDER, disc, at, nullptr, black);
    const float white[4] = {0.95f, 0.95f, 0.95f, 1.0f};
    add_connector(scn_, mjGEOM_CAPSULE, 0.004, {hole[0], hole[1], z}, {hole[0], hole[1], z + 0.45},
                  white);
    const mjtNum flag[3] = {0.06, 0.002, 0.04};
    const mjtNum flag_at[3] = {hole[0] + 0.06, hole[1], z + 0.41};
    const float red[4] = {0.9f, 0.1f, 0.1f, 1.0f};
    add_geom(scn_, mjGEOM_BOX, flag, flag_at, nullptr, red);
  }
  const mjtNum* b = d_->qpos + world_.ids().ball_qpos;
  if (deco.aim_angle) {
    const double a = *deco.aim_angle, len = 0.35;
    const float yellow[4] = {1.0f, 0.85f, 0.1f, 0.9f};
    add_connector(scn_, mjGEOM_ARROW, 0.008, {b[0], b[1], b[2]},
                  {b[0] + len * std::cos(a), b[1] + len * std::sin(a), b[2]}, yellow);
  }
  const float path_rgba[4] = {1.0f, 0.4f, 0.1f, 1.0f};
  for (std::size_t k = 1; k < deco.path.size(); ++k) {
    const auto& p = deco.path[k - 1];
    const auto& q = deco.path[k];
    if (std::hypot(q[0] - p[0], q[1] - p[1]) < 1e-4) continue;
    add_connector(scn_, mjGEOM_LINE, 3.0, p, q, path_rgba);
  }
}

void Renderer::draw(mjrRect viewport, const Decorations& deco) {
  mjr_render(viewport, &scn_, &con_);
  if (!deco.label.empty())
    mjr_overlay(viewport.width >= 600 ? mjFONT_BIG : mjFONT_NORMAL, mjGRID_TOPLEFT, viewport,
                deco.label.c_str(), nullptr, &con_);
  if (!deco.overlay.empty())
    mjr_overlay(mjFONT_NORMAL, mjGRID_BOTTOMLEFT, viewport, deco.overlay.c_str(), nullptr, &con_);
}

Image Renderer::read(mjrRect viewport) {
  Image flipped(viewport.width, viewport.height);
  mjr_readPixels(flipped.rgb.data(), nullptr, viewport, &con_);
  Image out(viewport.width, viewport.height);
  const std::size_t row = static_cast<std::size_t>(viewport.width) * 3;
  for (int y = 0; y < viewport.height; ++y)
    std::memcpy(out.pixel(0, y), flipped.pixel(0, viewport.height - 1 - y), row);
  return out;
}

Image Renderer::render(mjvCamera& camera, const Decorations& deco) {
  mjr_setBuffer(mjFB_OFFSCREEN, &con_);
  if (con_.currentBuffer != mjFB_OFFSCREEN) throw Error("renderer: no off-screen framebuffer");
  const mjrRect viewport{0, 0, width_, height_};
  update_scene(camera, deco);
  draw(viewport, deco);
  return read(viewport);
}

std::optional<std::array<double, 2>> Renderer::project(const std::array<double, 3>& p) const {
  // mjr_render's projection: glFrustum(center -+ halfwidth, bottom, top, near) with halfwidth
  // matching the viewport's aspect, viewed from the average of the scene's two eye cameras.
  const mjvGLCamera c = mjv_averageCamera(&scn_.camera[0], &scn_.camera[1]);
  double fwd[3], up[3], right[3], rel[3];
  for (int i = 0; i < 3; ++i) {
    fwd[i] = c.forward[i];
    up[i] = c.up[i];
    rel[i] = p[static_cast<std::size_t>(i)] - c.pos[i];
  }
  right[0] = fwd[1] * up[2] - fwd[2] * up[1];
  right[1] = fwd[2] * up[0] - fwd[0] * up[2];
  right[2] = fwd[0] * up[1] - fwd[1] * up[0];
  const double z = rel[0] * fwd[0] + rel[1] * fwd[1] + rel[2] * fwd[2];
  if (z <= c.frustum_near) return std::nullopt;
  const double xn =
      (rel[0] * right[0] + rel[1] * right[1] + rel[2] * right[2]) * c.frustum_near / z;
  const double yn = (rel[0] * up[0] + rel[1] * up[1] + rel[2] * up[2]) * c.frustum_near / z;
  const double half_h = 0.5 * (c.frustum_top - c.frustum_bottom);
  const double half_w = half_h * width_ / height_;
  const double u = (xn - (c.frustum_center - half_w)) / (2 * half_w) * width_;
  const double v = (c.frustum_top - yn) / (2 * half_h) * height_;
  return std::array<double, 2>{u, v};
}

}  // namespace mg::viz
