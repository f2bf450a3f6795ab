#include "vision/stereo_pipeline.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>

namespace mg::vision {
namespace {

/// Radius range [pixels] of a sphere-like blob of `radius` [m] seen anywhere on the lane.
std::array<double, 2> radius_range(const CameraModel& c, const field::Field& f, double radius,
                                   double lo_slack, double hi_slack) {
  double lo = 1e9, hi = 0;
  const auto& b = f.bounds;
  const Eigen::Vector3d centre = c.centre();
  for (int i = 0; i <= 10; ++i)
    for (int j = 0; j <= 10; ++j) {
      const double x = b[0] + (b[1] - b[0]) * i / 10, y = b[2] + (b[3] - b[2]) * j / 10;
      const double d = (Eigen::Vector3d(x, y, f.height(x, y)) - centre).norm();
      const double r = c.fy * radius / d;
      lo = std::min(lo, r), hi = std::max(hi, r);
    }
  return {std::max(0.8, lo * lo_slack), hi * hi_slack};
}

bool on_lane(const field::Field& f, const Eigen::Vector3d& p, double margin) {
  const auto& b = f.bounds;
  return p.x() >= b[0] - margin && p.x() <= b[1] + margin && p.y() >= b[2] - margin &&
         p.y() <= b[3] + margin;
}

}  // namespace

StereoModel::StereoModel(Calibration c, field::Field f, StereoConfig cfg)
    : calibration(std::move(c)), field(std::move(f)), config(cfg) {
  for (const auto& cam : calibration.cameras) {
    ball_radius_px.push_back(radius_range(cam, field, field.ball.radius, 0.5, 1.6));
    hole_radius_px.push_back(radius_range(cam, field, 0.5 * field.hole.diameter, 0.3, 1.5));
  }
}

StereoData::StereoData(const StereoModel& model) {
  for (std::size_t i = 0; i < model.calibration.cameras.size(); ++i)
    detectors.emplace_back(model.config.detector);
}

Sighting locate(const StereoModel& model, StereoData& data, const viz::Image* const* images,
                bool ball, const std::optional<Eigen::Vector2d>* predicted) {
  Sighting s;
  const auto& cams = model.calibration.cameras;
  const field::Field& f = model.field;
  const double above = ball ? f.ball.radius : 0.0;
  std::array<std::array<Blob, kMaxCandidates>, 2> cand{};
  std::array<int, 2> n{0, 0};
  for (std::size_t i = 0; i < 2; ++i) {
    BlobQuery q;
    const auto& range = ball ? model.ball_radius_px[i] : model.hole_radius_px[i];
    q.min_radius = range[0];
    q.max_radius = range[1];
    if (predicted && predicted[i]) {
      q.near = *predicted[i];
      q.search_radius = model.config.search_px;
    }
    n[i] = ball ? data.detectors[i].balls(*images[i], q, cand[i].data(), kMaxCandidates)
                : data.detectors[i].holes(*images[i], q, cand[i].data(), kMaxCandidates);
    if (n[i] > 0) s.blobs[i] = cand[i][0];
  }
  const auto plausible = [&](const Eigen::Vector3d& p) {
    return on_lane(f, p, 0.05) &&
           std::abs(p.z() - (f.height(p.x(), p.y()) + above)) <= model.config.surface_tol;
  };
  // A ball blob much smaller than a whole ball at that distance is partly hidden (the club,
  // the arm): its centre is off. If the other camera sees all of it, that camera alone places it.
  const auto partial = [&](std::size_t i, const Blob& b, const Eigen::Vector3d& p) {
    const double depth = (cams[i].R * p + cams[i].t).z();
    return ball && depth > 0 &&
           b.radius < model.config.partial_ratio * cams[i].fy * f.ball.radius / depth;
  };
  // Epipolar matching: of all candidate pairs, the one with the smallest reprojection error
  // that lies at the surface (the arm's grey, a highlight, the other's wrong blob are refused).
  int best_a = -1, best_b = -1;
  double best_err = model.config.gate_px;
  Eigen::Vector3d best_p = Eigen::Vector3d::Zero();
  for (int ia = 0; ia < n[0]; ++ia)
    for (int ib = 0; ib < n[1]; ++ib) {
      const Blob& a = cand[0][static_cast<std::size_t>(ia)];
      const Blob& b = cand[1][static_cast<std::size_t>(ib)];
      const auto p = triangulate(cams[0], a.pixel, cams[1], b.pixel);
      if (!p || !plausible(*p)) continue;
      const double err = reprojection_error(cams[0], a.pixel, cams[1], b.pixel, *p);
      if (err <= best_err) best_err = err, best_a = ia, best_b = ib, best_p = *p;
    }
  if (best_a >= 0) {
    s.blobs = {cand[0][static_cast<std::size_t>(best_a)],
               cand[1][static_cast<std::size_t>(best_b)]};
    const bool p0 = partial(0, s.blobs[0], best_p), p1 = partial(1, s.blobs[1], best_p);
    if (p0 != p1) {
      const std::size_t whole = p0 ? 1 : 0;
      const auto q = intersect_surface(cams[whole], s.blobs[whole].pixel, f, above);
      if (q && plausible(*q)) {
        s.views = 1;
        s.point = *q;
        s.partial = true;
        return s;
      }
    }
    s.views = 2;
    s.point = best_p;
    s.reprojection_px = best_err;
    return s;
  }
  s.gated = n[0] > 0 && n[1] > 0;
  // One camera: the ray meets the surface (+ the ball's radius). While tracking, the blob nearest
  // the prediction; otherwise only an unambiguous one (one blob in one camera, none in the other).
  for (std::size_t i = 0; i < 2; ++i) {
    if (n[i] == 0) continue;
    const bool tracked = predicted && predicted[i];
    if (!tracked && (n[i] != 1 || n[1 - i] != 0)) continue;
    const auto p = intersect_surface(cams[i], cand[i][0].pixel, f, above);
    if (p && on_lane(f, *p, 0.05)) {
      s.views = 1;
      s.point = *p;
      return s;
    }
  }
  return s;
}

void stereo_frame(const StereoModel& model, StereoData& data, const viz::Image* const* images,
                  double stamp) {
  const auto& cfg = model.config;
  ++data.frames;
  // Where the ball should be in each image while it is tracked (fresh).
  std::optional<Eigen::Vector2d> predicted[2];
  Track& k = data.ball;
  if (k.initialised && stamp - k.last_measured <= cfg.max_age) {
    Track ahead = k;
    track_predict(ahead, cfg.tracker, stamp);
    const double x = ahead.x[0], y = ahead.x[1];
    const Eigen::Vector3d p(x, y, model.field.height(x, y) + model.field.ball.radius);
    for (std::size_t i = 0; i < 2; ++i) predicted[i] = project(model.calibration.cameras[i], p);
  }
  data.last_ball = locate(model, data, images, true, predicted);
  // A stale track says nothing about where the ball is now: a new sighting starts a new one.
  if (data.last_ball.views > 0 && k.initialised && stamp - k.last_measured > cfg.max_age)
    k.initialised = false;
  if (data.last_ball.views > 0)
    track_update(k, cfg.tracker, stamp, data.last_ball.point.head<2>(),
                 data.last_ball.views == 2 ? cfg.sigma_stereo : cfg.sigma_mono);
  else
    track_predict(k, cfg.tracker, stamp);
  // The hole does not move: once seen in 10 frames, it is looked for near where it was.
  std::optional<Eigen::Vector2d> hole_at[2];
  if (data.hole_count >= 10) {
    const Eigen::Vector3d mean = data.hole_sum / data.hole_count;
    for (std::size_t i = 0; i < 2; ++i) hole_at[i] = project(model.calibration.cameras[i], mean);
  }
  data.last_hole = locate(model, data, images, false, hole_at);
  if (data.last_hole.views == 2) {
    const Eigen::Vector3d mean = data.hole_count > 0
                                     ? Eigen::Vector3d(data.hole_sum / data.hole_count)
                                     : data.last_hole.point;
    if ((data.last_hole.point - mean).norm() > 0.05) data.hole_sum.setZero(), data.hole_count = 0;
    data.hole_sum += data.last_hole.point;
    ++data.hole_count;
    data.hole_last = stamp;
  }
}

StereoEstimate stereo_estimate(const StereoModel& model, const StereoData& data, double now) {
  StereoEstimate e;
  const field::Field& f = model.field;
  if (data.hole_count > 0) {
    e.hole_known = true;
    e.hole = data.hole_sum / data.hole_count;
  }
  const Track& k = data.ball;
  if (!k.initialised) return e;
  const double x = k.x[0], y = k.x[1];
  e.ball = {x, y, f.height(x, y) + f.ball.radius};
  e.ball_age = now - k.last_measured;
  e.ball_fresh = e.ball_age <= model.config.max_age;
  if (!e.ball_fresh && e.hole_known &&
      std::hypot(x - e.hole.x(), y - e.hole.y()) <= 0.5 * f.hole.diameter + f.ball.radius)
    e.ball_in_cup = true;
  return e;
}

double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace mg::vision
