#include "vision/still_scene.hpp"

#include <chrono>
#include <cmath>
#include <ctime>

#include "robot/wam_model.hpp"
#include "sim_backend/arm_mujoco.hpp"

namespace mg::vision {

void place_still_scene(const sim::World& world, mjData* d, std::array<double, 2> ball,
                       std::array<double, 2> hole) {
  world.reset(d);
  robot::Vector7 rest;
  for (int j = 0; j < 7; ++j) rest[j] = robot::kDefaultRestPosture[static_cast<std::size_t>(j)];
  robot::set_joint_positions(robot::find_arm_ids(world.model()), d, rest);
  world.set_hole(d, hole);
  sim::BallState s = world.ball_state(d);
  const field::Field& f = world.field();
  s.qpos = {ball[0], ball[1], f.height(ball[0], ball[1]) + f.ball.radius, 1, 0, 0, 0};
  s.qvel = {};
  world.set_ball_state(d, s);
  mj_forward(world.model(), d);
}

StillMeasurement measure_still(RigRenderer& renderer, const StereoModel& model, StereoData& data,
                               const mjData* d) {
  StillMeasurement m;
  const sim::World& world = renderer.world();
  const field::Field& f = world.field();
  const int qb = world.ids().ball_qpos;
  m.true_ball = {d->qpos[qb], d->qpos[qb + 1], d->qpos[qb + 2]};
  const auto hole = world.hole_position(d);
  m.true_hole = {hole[0], hole[1], f.height(hole[0], hole[1])};
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < 2; ++i) m.images.push_back(renderer.render(i, d));
  m.render_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const viz::Image* images[2] = {&m.images[0], &m.images[1]};
  const double c0 = thread_cpu_seconds();
  m.ball = locate(model, data, images, true);
  m.hole = locate(model, data, images, false);
  m.cpu_seconds = thread_cpu_seconds() - c0;
  return m;
}

namespace {
void put(viz::Image& img, int x, int y, const std::uint8_t rgb[3]) {
  if (x < 0 || y < 0 || x >= img.width || y >= img.height) return;
  std::uint8_t* p = img.pixel(x, y);
  p[0] = rgb[0], p[1] = rgb[1], p[2] = rgb[2];
}
void ring(viz::Image& img, const Eigen::Vector2d& c, double r, const std::uint8_t rgb[3]) {
  const int steps = std::max(16, static_cast<int>(8 * r));
  for (int k = 0; k < steps; ++k) {
    const double a = 2 * 3.14159265358979323846 * k / steps;
    put(img, static_cast<int>(std::lround(c.x() + r * std::cos(a))),
        static_cast<int>(std::lround(c.y() + r * std::sin(a))), rgb);
  }
}
}  // namespace

viz::Image annotate(const viz::Image& image, const Blob& ball, const Blob& hole,
                    const std::vector<Eigen::Vector2d>& truth) {
  viz::Image out = image;
  const std::uint8_t red[3] = {255, 30, 30}, blue[3] = {40, 120, 255}, green[3] = {0, 255, 0};
  if (ball.found)
    ring(out, ball.pixel, ball.radius + 3, red), ring(out, ball.pixel, ball.radius + 4, red);
  if (hole.found)
    ring(out, hole.pixel, hole.radius + 4, blue), ring(out, hole.pixel, hole.radius + 5, blue);
  for (const auto& t : truth)
    for (int k = -2; k <= 2; ++k) {
      put(out, static_cast<int>(std::lround(t.x())) + k, static_cast<int>(std::lround(t.y())),
          green);
      put(out, static_cast<int>(std::lround(t.x())), static_cast<int>(std::lround(t.y())) + k,
          green);
    }
  return out;
}

}  // namespace mg::vision
