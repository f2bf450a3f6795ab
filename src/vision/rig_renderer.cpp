#include "vision/rig_renderer.hpp"

#include <cmath>

#include <opencv2/imgproc.hpp>

#include "viz/renderer.hpp"

namespace mg::vision {
namespace {

void add_box(mjvScene& scn, const Eigen::Vector3d& centre, const Eigen::Matrix3d& R,
             const Eigen::Vector3d& half, const float rgba[4]) {
  if (scn.ngeom >= scn.maxgeom) return;
  mjvGeom* g = scn.geoms + scn.ngeom++;
  mjtNum size[3] = {half.x(), half.y(), half.z()}, pos[3] = {centre.x(), centre.y(), centre.z()};
  mjtNum mat[9];
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) mat[3 * a + b] = R(a, b);
  mjv_initGeom(g, mjGEOM_BOX, size, pos, mat, rgba);
  g->category = mjCAT_DECOR;
}

void add_board(mjvScene& scn, const Board& b) {
  const float white[4] = {0.95f, 0.95f, 0.95f, 1.0f}, black[4] = {0.02f, 0.02f, 0.02f, 1.0f};
  const double s = b.square;
  // The squares' faces on -z (towards the camera) lie in the board's plane, where the corners
  // are; the plate's face 0.3 mm behind them. White plate with a one-square margin around the
  // (cols + 1) x (rows + 1) squares.
  const Eigen::Vector3d plate_centre(0.5 * (b.cols - 1) * s, 0.5 * (b.rows - 1) * s, 0.0013);
  add_box(scn, b.origin + b.R * plate_centre, b.R,
          {0.5 * (b.cols + 3) * s, 0.5 * (b.rows + 3) * s, 0.001}, white);
  for (int a = -1; a < b.cols; ++a)
    for (int c = -1; c < b.rows; ++c) {
      if (((a + c) % 2 + 2) % 2 != 0) continue;  // (-1, -1) black
      const Eigen::Vector3d centre((a + 0.5) * s, (c + 0.5) * s, 0.0013);
      add_box(scn, b.origin + b.R * centre, b.R, {0.5 * s, 0.5 * s, 0.0013}, black);
    }
}

}  // namespace

struct RigRenderer::Impl {
  const sim::World* world;
  struct Camera {
    CameraModel truth;
    int margin_x = 0, margin_y = 0;  // ideal image margins (distortion pulls pixels from outside)
    std::unique_ptr<viz::Renderer> renderer;
    cv::Mat map_x, map_y;  // distorted pixel -> ideal-image pixel
    viz::Image image;
  };
  std::vector<Camera> cameras;
};

RigRenderer::RigRenderer(const sim::World& world, const Rig& rig)
    : impl_(std::make_unique<Impl>()) {
  impl_->world = &world;
  for (const auto& spec : rig.cameras) {
    Impl::Camera c;
    c.truth = camera_from_spec(spec);
    const CameraModel& m = c.truth;
    const bool distorted = m.dist != std::array<double, 5>{};
    if (distorted) {
      // Where each output pixel comes from in the ideal (pinhole) image.
      c.map_x.create(m.height, m.width, CV_32FC1);
      c.map_y.create(m.height, m.width, CV_32FC1);
      double reach_x = 0, reach_y = 0;
      for (int v = 0; v < m.height; ++v)
        for (int u = 0; u < m.width; ++u) {
          const Eigen::Vector2d n = undistort(m.dist, {(u - m.cx) / m.fx, (v - m.cy) / m.fy});
          const double iu = m.fx * n.x() + m.cx, iv = m.fy * n.y() + m.cy;
          reach_x = std::max(reach_x, std::max(-iu, iu - (m.width - 1)));
          reach_y = std::max(reach_y, std::max(-iv, iv - (m.height - 1)));
          c.map_x.at<float>(v, u) = static_cast<float>(iu);
          c.map_y.at<float>(v, u) = static_cast<float>(iv);
        }
      c.margin_x = static_cast<int>(std::ceil(reach_x)) + 2;
      c.margin_y = static_cast<int>(std::ceil(reach_y)) + 2;
      c.map_x += static_cast<float>(c.margin_x);
      c.map_y += static_cast<float>(c.margin_y);
    }
    c.renderer =
        std::make_unique<viz::Renderer>(world, m.width + 2 * c.margin_x, m.height + 2 * c.margin_y);
    impl_->cameras.push_back(std::move(c));
  }
}

RigRenderer::~RigRenderer() = default;

int RigRenderer::size() const { return static_cast<int>(impl_->cameras.size()); }
const CameraModel& RigRenderer::truth(int i) const {
  return impl_->cameras[static_cast<std::size_t>(i)].truth;
}
const sim::World& RigRenderer::world() const { return *impl_->world; }

const viz::Image& RigRenderer::render(int i, const mjData* d, const Board* board) {
  Impl::Camera& c = impl_->cameras[static_cast<std::size_t>(i)];
  viz::Renderer& r = *c.renderer;
  const sim::World& world = *impl_->world;
  viz::copy_pose(r.model(), d, r.data());
  mjvCamera free;
  mjv_defaultCamera(&free);
  viz::Decorations none;
  none.hole_marker = false;
  r.update_scene(free, none);
  mjvScene& scn = r.scene();
  // The cup's opening: the dark disc a camera sees where the heightfield covers the cup.
  const field::Field& f = world.field();
  const auto hole = world.hole_position(r.data());
  {
    // Level with the surface there (its normal by central differences), top 1.5 mm above it
    // (the lane as drawn is the heightfield's triangles, not the exact surface).
    const double rad = 0.5 * f.hole.diameter, z = f.height(hole[0], hole[1]), e = 0.01;
    const Eigen::Vector3d n =
        Eigen::Vector3d(
            -(f.height(hole[0] + e, hole[1]) - f.height(hole[0] - e, hole[1])) / (2 * e),
            -(f.height(hole[0], hole[1] + e) - f.height(hole[0], hole[1] - e)) / (2 * e), 1.0)
            .normalized();
    const Eigen::Vector3d ax = (Eigen::Vector3d::UnitX() - n * n.x()).normalized(),
                          ay = n.cross(ax);
    mjtNum mat[9];
    for (int k = 0; k < 3; ++k) mat[3 * k] = ax[k], mat[3 * k + 1] = ay[k], mat[3 * k + 2] = n[k];
    // Sizes as mjModel.geom_size: a cylinder's are (radius, half-height).
    const mjtNum size[3] = {rad, 0.001, 0.0};
    const mjtNum at[3] = {hole[0] + 0.0005 * n.x(), hole[1] + 0.0005 * n.y(), z + 0.0005 * n.z()};
    const float dark[4] = {0.05f, 0.05f, 0.05f, 1.0f};
    if (scn.ngeom < scn.maxgeom) {
      mjvGeom* g = scn.geoms + scn.ngeom++;
      mjv_initGeom(g, mjGEOM_CYLINDER, size, at, mat, dark);
      g->category = mjCAT_DECOR;
    }
  }
  if (board) add_board(scn, *board);
  // The camera exactly: optical centre, axis, up, and a frustum with fy = c.truth.fy.
  const CameraModel& m = c.truth;
  const Eigen::Vector3d pos = m.centre(), fwd = m.R.row(2).transpose(),
                        up = -m.R.row(1).transpose();
  const double near = 0.02;
  for (int e = 0; e < 2; ++e) {
    mjvGLCamera& g = scn.camera[e];
    for (int k = 0; k < 3; ++k) {
      g.pos[k] = static_cast<float>(pos[k]);
      g.forward[k] = static_cast<float>(fwd[k]);
      g.up[k] = static_cast<float>(up[k]);
    }
    g.frustum_center = 0.0f;
    g.frustum_top = static_cast<float>(near * 0.5 * r.height() / m.fy);
    g.frustum_bottom = -g.frustum_top;
    g.frustum_near = static_cast<float>(near);
    g.frustum_far = 50.0f;
  }
  mjr_setBuffer(mjFB_OFFSCREEN, &r.context());
  const mjrRect viewport{0, 0, r.width(), r.height()};
  r.draw(viewport, none);
  if (c.margin_x == 0 && c.margin_y == 0) {
    c.image = r.read(viewport);
    return c.image;
  }
  viz::Image ideal = r.read(viewport);
  if (c.image.width != m.width || c.image.height != m.height)
    c.image = viz::Image(m.width, m.height);
  const cv::Mat src(ideal.height, ideal.width, CV_8UC3, ideal.rgb.data());
  cv::Mat dst(m.height, m.width, CV_8UC3, c.image.rgb.data());
  cv::remap(src, dst, c.map_x, c.map_y, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  return c.image;
}

}  // namespace mg::vision
