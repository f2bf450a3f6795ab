#include "vision/calibrate.hpp"

#include <cmath>
#include <random>

#include <fmt/format.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.hpp"
#include "core/rng.hpp"

namespace mg::vision {
namespace {

/// The corners of `board` found in `image`, in OpenCV's order made canonical: the square
/// diagonal before corner 0 is black (else the list is reversed: the board seen turned by 180
/// degrees). Empty when not every corner was found.
std::vector<cv::Point2f> find_corners(const viz::Image& image, const Board& board) {
  cv::Mat rgb(image.height, image.width, CV_8UC3, const_cast<std::uint8_t*>(image.rgb.data()));
  cv::Mat grey;
  cv::cvtColor(rgb, grey, cv::COLOR_RGB2GRAY);
  std::vector<cv::Point2f> corners;
  const cv::Size pattern(board.cols, board.rows);
  if (!cv::findChessboardCorners(grey, pattern, corners,
                                 cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE))
    return {};
  // The window: half the smallest corner spacing, 2..5 pixels.
  double spacing = 1e9;
  for (int j = 0; j < board.rows; ++j)
    for (int i = 0; i + 1 < board.cols; ++i)
      spacing = std::min<double>(
          spacing, cv::norm(corners[static_cast<std::size_t>(j * board.cols + i + 1)] -
                            corners[static_cast<std::size_t>(j * board.cols + i)]));
  const int win = std::clamp(static_cast<int>(spacing / 2.5), 2, 5);
  cv::cornerSubPix(grey, corners, cv::Size(win, win), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-4));
  const cv::Point2f c0 = corners[0], c1 = corners[1],
                    cn = corners[static_cast<std::size_t>(board.cols)];
  const cv::Point2f probe = c0 - 0.5f * ((c1 - c0) + (cn - c0));
  const int px = std::clamp(static_cast<int>(std::lround(probe.x)), 0, image.width - 1),
            py = std::clamp(static_cast<int>(std::lround(probe.y)), 0, image.height - 1);
  if (grey.at<std::uint8_t>(py, px) > 100) std::reverse(corners.begin(), corners.end());
  return corners;
}

std::vector<cv::Point3f> board_points(const Board& b) {
  std::vector<cv::Point3f> pts;
  for (int j = 0; j < b.rows; ++j)
    for (int i = 0; i < b.cols; ++i)
      pts.emplace_back(static_cast<float>(i * b.square), static_cast<float>(j * b.square), 0.0f);
  return pts;
}

Eigen::Matrix3d rotation(const Eigen::Vector3d& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

/// A random hand-held pose: the board's centre 12 % to 60 % of the way from a random point of the
/// lane up to the cameras' middle, facing that middle, tilted by up to 45 degrees and turned in
/// its plane by up to 25. Over the poses the corners reach every part of the images where the
/// lane is (boards only near the cameras left the lane's ends, near the images' edges, to the
/// distortion's extrapolation: 7 mm at the lane's corner).
Board random_pose(const std::vector<CameraModel>& cams, const field::Field& f, Board b, Rng& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Eigen::Vector3d mid = Eigen::Vector3d::Zero();
  for (const auto& c : cams) mid += c.centre();
  mid /= static_cast<double>(cams.size());
  const auto& bd = f.bounds;
  const double tx = bd[0] + (bd[1] - bd[0]) * u(rng);  // drawn in order: the same on every compiler
  const double ty = bd[2] + (bd[3] - bd[2]) * u(rng);
  const Eigen::Vector3d target(tx, ty, 0.0);
  const Eigen::Vector3d centre = target + (0.12 + 0.48 * u(rng)) * (mid - target);
  const Eigen::Vector3d normal = (mid - centre).normalized();  // board z towards the cameras
  Eigen::Vector3d x_axis = Eigen::Vector3d::UnitX() - normal * normal.x();
  x_axis.normalize();
  Eigen::Matrix3d R;
  R.col(0) = x_axis;
  R.col(2) = -normal;  // board z away from the cameras (corners seen from the front)
  R.col(1) = R.col(2).cross(R.col(0));
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  const double tilt_x = (u(rng) - 0.5) * 90 * kDeg, tilt_y = (u(rng) - 0.5) * 90 * kDeg,
               turn = (u(rng) - 0.5) * 50 * kDeg;
  R = rotation(R.col(0), tilt_x) * rotation(R.col(1), tilt_y) * rotation(R.col(2), turn) * R;
  b.R = R;
  const Eigen::Vector3d half(0.5 * (b.cols - 1) * b.square, 0.5 * (b.rows - 1) * b.square, 0.0);
  b.origin = centre - R * half;
  return b;
}

bool visible(const std::vector<CameraModel>& cams, const Board& b, double margin) {
  for (const auto& c : cams) {
    const Eigen::Vector3d normal = b.R.col(2);
    const Eigen::Vector3d centre = b.corner(b.cols / 2, b.rows / 2);
    if ((c.centre() - centre).normalized().dot(-normal) < 0.35) return false;  // too oblique
    for (int j = -1; j <= b.rows; j += b.rows + 1)
      for (int i = -1; i <= b.cols; i += b.cols + 1) {
        const auto px = project(c, b.corner(i, j));
        if (!px || !in_image(c, *px, margin)) return false;
      }
  }
  return true;
}

/// Drops the poses where some camera's corner lies more than 1 px from its reprojection by a
/// first calibration (a corner cornerSubPix moved onto the wrong edge); returns how many.
int drop_bad_views(std::vector<std::vector<cv::Point3f>>& object_points,
                   std::vector<std::vector<std::vector<cv::Point2f>>>& image_points,
                   const std::vector<CameraModel>& cams) {
  std::vector<bool> bad(object_points.size(), false);
  for (std::size_t k = 0; k < image_points.size(); ++k) {
    cv::Mat K = cv::Mat::eye(3, 3, CV_64F), D = cv::Mat::zeros(5, 1, CV_64F);
    std::vector<cv::Mat> rvecs, tvecs;
    cv::calibrateCamera(object_points, image_points[k], cv::Size(cams[k].width, cams[k].height), K,
                        D, rvecs, tvecs, cv::CALIB_FIX_K3);
    for (std::size_t v = 0; v < object_points.size(); ++v) {
      std::vector<cv::Point2f> back;
      cv::projectPoints(object_points[v], rvecs[v], tvecs[v], K, D, back);
      for (std::size_t c = 0; c < back.size(); ++c)
        if (cv::norm(back[c] - image_points[k][v][c]) > 1.0) bad[v] = true;
    }
  }
  std::size_t kept = 0;
  for (std::size_t v = 0; v < object_points.size(); ++v) {
    if (bad[v]) continue;
    object_points[kept] = object_points[v];
    for (auto& points : image_points) points[kept] = points[v];
    ++kept;
  }
  const int dropped = static_cast<int>(object_points.size() - kept);
  object_points.resize(kept);
  for (auto& points : image_points) points.resize(kept);
  return dropped;
}

CameraModel from_cv(const CameraModel& like, const cv::Mat& K, const cv::Mat& dist) {
  CameraModel m = like;
  m.fx = K.at<double>(0, 0);
  m.fy = K.at<double>(1, 1);
  m.cx = K.at<double>(0, 2);
  m.cy = K.at<double>(1, 2);
  for (int k = 0; k < 5; ++k) m.dist[static_cast<std::size_t>(k)] = dist.at<double>(k);
  return m;
}

}  // namespace

CalibrateReport calibrate_rig(RigRenderer& renderer, mjData* d, const Rig& rig,
                              const CalibrateOptions& o) {
  if (o.views < 15 || o.views > 200)
    throw InputError(fmt::format("calibrate: views: expected 15..200, got {}", o.views));
  const int n = renderer.size();
  std::vector<CameraModel> truth;
  for (int i = 0; i < n; ++i) truth.push_back(renderer.truth(i));
  const field::Field& f = renderer.world().field();
  Board held;
  held.cols = o.cols, held.rows = o.rows, held.square = o.square;
  Rng rng(o.seed);
  CalibrateReport rep;
  std::vector<std::vector<std::vector<cv::Point2f>>> image_points(static_cast<std::size_t>(n));
  std::vector<std::vector<cv::Point3f>> object_points;
  const auto object = board_points(held);
  // Poses are drawn until `views` were found by every camera (the truth only chooses poses a
  // person would: the board in view of all cameras; the corners come from the images).
  while (static_cast<int>(object_points.size()) < o.views && rep.poses_tried < 6 * o.views) {
    Board b = random_pose(truth, f, held, rng);
    if (!visible(truth, b, 8.0)) continue;
    ++rep.poses_tried;
    std::vector<std::vector<cv::Point2f>> found;
    for (int i = 0; i < n; ++i) {
      found.push_back(find_corners(renderer.render(i, d, &b), b));
      if (found.back().empty()) break;
    }
    if (static_cast<int>(found.size()) < n || found.back().empty()) {
      ++rep.poses_rejected;
      continue;
    }
    for (int i = 0; i < n; ++i)
      image_points[static_cast<std::size_t>(i)].push_back(found[static_cast<std::size_t>(i)]);
    object_points.push_back(object);
  }
  rep.poses_rejected += drop_bad_views(object_points, image_points, truth);
  if (static_cast<int>(object_points.size()) < 15)
    throw Error(
        fmt::format("calibrate: the board was found by every camera in {} of {} poses "
                    "(expected at least 15)",
                    object_points.size(), rep.poses_tried));
  Calibration& cal = rep.calibration;
  cal.rig = rig.name;
  cal.views = static_cast<int>(object_points.size());
  std::vector<cv::Mat> K(static_cast<std::size_t>(n)), D(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const cv::Size size(truth[k].width, truth[k].height);
    std::vector<cv::Mat> rvecs, tvecs;
    K[k] = cv::Mat::eye(3, 3, CV_64F);
    D[k] = cv::Mat::zeros(5, 1, CV_64F);
    const double rms = cv::calibrateCamera(object_points, image_points[k], size, K[k], D[k], rvecs,
                                           tvecs, cv::CALIB_FIX_K3);
    cal.cameras.push_back(from_cv(truth[k], K[k], D[k]));
    cal.rms_px.push_back(rms);
  }
  // The relative pose of the first two cameras, their intrinsics refined with it: one board pose
  // for both cameras ties their focal lengths (fx 0.2-0.7 % off per camera alone, 0.1 % so).
  {
    cv::Mat R, T, E, F;
    cal.stereo_rms_px =
        cv::stereoCalibrate(object_points, image_points[0], image_points[1], K[0], D[0], K[1], D[1],
                            cv::Size(truth[0].width, truth[0].height), R, T, E, F,
                            cv::CALIB_USE_INTRINSIC_GUESS | cv::CALIB_FIX_K3);
    rep.stereo_baseline = cv::norm(T);
    for (std::size_t k = 0; k < 2; ++k) cal.cameras[k] = from_cv(truth[k], K[k], D[k]);
  }
  // The field frame: a larger board laid level on the lane at a known place.
  Board lane;
  lane.cols = o.cols, lane.rows = o.rows, lane.square = o.field_square;
  const auto& bd = f.bounds;
  const double w = (o.cols - 1) * o.field_square, h = (o.rows - 1) * o.field_square;
  const double x0 = std::isnan(o.field_x) ? 0.5 * (bd[0] + bd[1]) - 0.5 * w : o.field_x;
  const double y0 = std::isnan(o.field_y) ? 0.5 * (bd[2] + bd[3]) - 0.5 * h : o.field_y;
  double top = -1e9;
  for (int j = -1; j <= o.rows; ++j)
    for (int i = -1; i <= o.cols; ++i)
      top = std::max(top, f.height(x0 + i * o.field_square, y0 + j * o.field_square));
  // Seen from above like the hand-held boards from the front: the board's z points away from
  // the cameras (down), its rows along -y (so the corner order has the same handedness).
  lane.R = Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal();
  lane.origin = {x0, y0 + h, top + 0.002};
  rep.field_board = lane;
  std::vector<cv::Point3f> world_corners;
  for (int j = 0; j < lane.rows; ++j)
    for (int i = 0; i < lane.cols; ++i) {
      const Eigen::Vector3d p = lane.corner(i, j);
      world_corners.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                 static_cast<float>(p.z()));
    }
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const auto corners = find_corners(renderer.render(i, d, &lane), lane);
    if (corners.empty())
      throw Error(fmt::format("calibrate: camera '{}' does not find the board laid on the lane",
                              truth[k].name));
    cv::Mat rvec, tvec;
    cv::solvePnP(world_corners, corners, K[k], D[k], rvec, tvec, false, cv::SOLVEPNP_ITERATIVE);
    std::vector<cv::Point2f> back;
    cv::projectPoints(world_corners, rvec, tvec, K[k], D[k], back);
    double sum = 0;
    for (std::size_t c = 0; c < back.size(); ++c)
      sum += std::pow(cv::norm(back[c] - corners[c]), 2);
    rep.field_rms_px.push_back(std::sqrt(sum / static_cast<double>(back.size())));
    cv::Mat R;
    cv::Rodrigues(rvec, R);
    CameraModel& m = cal.cameras[k];
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) m.R(a, b) = R.at<double>(a, b);
      m.t[a] = tvec.at<double>(a);
    }
  }
  rep.pnp_baseline = (cal.cameras[0].centre() - cal.cameras[1].centre()).norm();
  cal.source = "calibrated";
  return rep;
}

}  // namespace mg::vision
