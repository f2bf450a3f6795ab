#include "vision/detect.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace mg::vision {

struct Detector::Impl {
  DetectorConfig config;
  cv::Mat mask, labels, stats, centroids;
};

Detector::Detector(const DetectorConfig& config) : impl_(std::make_unique<Impl>()) {
  impl_->config = config;
}
Detector::~Detector() = default;
Detector::Detector(Detector&&) noexcept = default;
Detector& Detector::operator=(Detector&&) noexcept = default;
const DetectorConfig& Detector::config() const { return impl_->config; }

namespace {

constexpr double kPi = 3.14159265358979323846;

/// Ball weight of a pixel in [0, 1]: 1 for clearly grey and bright, ramping to 0 over the
/// saturation and value margins, so an anti-aliased rim pixel counts in proportion to the ball
/// in it (sub-pixel centre).
inline double ball_weight(const std::uint8_t* p, const DetectorConfig& c) {
  const int lo = std::min({p[0], p[1], p[2]}), hi = std::max({p[0], p[1], p[2]});
  if (hi == 0) return 0.0;
  const double sat = static_cast<double>(hi - lo) / hi;
  const double ws = std::clamp((c.ball_max_saturation + 0.2 - sat) / 0.3, 0.0, 1.0);
  const double wv = std::clamp((hi - (c.ball_min_value - 30)) / 30.0, 0.0, 1.0);
  return ws * wv;
}
inline double hole_weight(const std::uint8_t* p, const DetectorConfig& c) {
  const int hi = std::max({p[0], p[1], p[2]});
  return std::clamp(((c.hole_max_channel + 40) - hi) / 40.0, 0.0, 1.0);
}

template <typename Weight, typename Inside>
int find(Detector::Impl& d, const viz::Image& img, const BlobQuery& q, Inside inside, Weight weight,
         Blob* out, int max_out) {
  const int w = img.width, h = img.height;
  if (d.mask.rows != h || d.mask.cols != w) d.mask.create(h, w, CV_8UC1);
  // With a prediction only a window around it is searched (a tracked ball: a few percent of the
  // image); coordinates below are the window's, `ox`, `oy` its corner in the image.
  cv::Rect roi(0, 0, w, h);
  if (q.near) {
    const int r = static_cast<int>(std::ceil(std::min(q.search_radius, 1e4) + q.max_radius)) + 3;
    roi = cv::Rect(static_cast<int>(std::lround(q.near->x())) - r,
                   static_cast<int>(std::lround(q.near->y())) - r, 2 * r + 1, 2 * r + 1) &
          cv::Rect(0, 0, w, h);
    if (roi.empty()) return 0;
  }
  const int ox = roi.x, oy = roi.y;
  cv::Mat mask = d.mask(roi);
  for (int y = 0; y < roi.height; ++y) {
    std::uint8_t* m = mask.ptr<std::uint8_t>(y);
    for (int x = 0; x < roi.width; ++x) m[x] = inside(img.pixel(x + ox, y + oy)) ? 255 : 0;
  }
  const int n = cv::connectedComponentsWithStats(mask, d.labels, d.stats, d.centroids, 8, CV_32S);
  // The best `max_out` blobs by score (insertion into a short sorted array: no allocation).
  constexpr int kMax = kMaxCandidates;
  std::array<int, kMax> label{};
  std::array<double, kMax> score{};
  int kept = 0, passed = 0;
  max_out = std::clamp(max_out, 1, kMax);
  for (int k = 1; k < n; ++k) {
    const int* s = d.stats.ptr<int>(k);
    const int bx = s[cv::CC_STAT_LEFT] + ox, by = s[cv::CC_STAT_TOP] + oy;
    const int bw = s[cv::CC_STAT_WIDTH], bh = s[cv::CC_STAT_HEIGHT], area = s[cv::CC_STAT_AREA];
    const double r = std::sqrt(area / kPi);
    if (r < q.min_radius || r > q.max_radius) continue;
    if (area < d.config.min_fill * bw * bh) continue;
    if (std::max(bw, bh) > d.config.max_aspect * std::min(bw, bh)) continue;
    if (bx == 0 || by == 0 || bx + bw == w || by + bh == h) continue;  // cut by the frame
    const Eigen::Vector2d c(d.centroids.at<double>(k, 0) + ox, d.centroids.at<double>(k, 1) + oy);
    // Without a prediction: rounder and larger first; with one: nearer first.
    double sc = -area * static_cast<double>(area) / (bw * bh);
    if (q.near) {
      sc = (c - *q.near).norm();
      if (sc > q.search_radius) continue;
    }
    ++passed;
    int at = std::min(kept, max_out - 1);
    if (kept == max_out && sc >= score[static_cast<std::size_t>(at)]) continue;
    while (at > 0 && score[static_cast<std::size_t>(at - 1)] > sc) {
      label[static_cast<std::size_t>(at)] = label[static_cast<std::size_t>(at - 1)];
      score[static_cast<std::size_t>(at)] = score[static_cast<std::size_t>(at - 1)];
      --at;
    }
    label[static_cast<std::size_t>(at)] = k;
    score[static_cast<std::size_t>(at)] = sc;
    kept = std::min(kept + 1, max_out);
  }
  for (int j = 0; j < kept; ++j) {
    const int lab_j = label[static_cast<std::size_t>(j)];
    const int* s = d.stats.ptr<int>(lab_j);
    Blob& b = out[j];
    b = Blob{};
    b.found = true;
    b.candidates = passed;
    b.radius = std::sqrt(s[cv::CC_STAT_AREA] / kPi);
    b.pixel = {d.centroids.at<double>(lab_j, 0) + ox, d.centroids.at<double>(lab_j, 1) + oy};
    // Sub-pixel centre: weighted moments over the blob's box grown by 2 pixels (in the window),
    // counting only pixels of this blob or its anti-aliased rim (not another blob's).
    const int x0 = std::max(0, s[cv::CC_STAT_LEFT] - 2), y0 = std::max(0, s[cv::CC_STAT_TOP] - 2);
    const int x1 = std::min(roi.width - 1, s[cv::CC_STAT_LEFT] + s[cv::CC_STAT_WIDTH] + 1),
              y1 = std::min(roi.height - 1, s[cv::CC_STAT_TOP] + s[cv::CC_STAT_HEIGHT] + 1);
    double m0 = 0, mx = 0, my = 0;
    for (int y = y0; y <= y1; ++y) {
      const int* lab = d.labels.ptr<int>(y);
      for (int x = x0; x <= x1; ++x) {
        if (lab[x] != 0 && lab[x] != lab_j) continue;
        const double wt = weight(img.pixel(x + ox, y + oy));
        m0 += wt, mx += wt * (x + ox), my += wt * (y + oy);
      }
    }
    if (m0 > 0) b.pixel = {mx / m0, my / m0};
  }
  return kept;
}

}  // namespace

namespace {
bool ball_pixel(const std::uint8_t* p, const DetectorConfig& c) {
  const int lo = std::min({p[0], p[1], p[2]}), hi = std::max({p[0], p[1], p[2]});
  return hi >= c.ball_min_value && hi - lo <= c.ball_max_saturation * hi;
}
bool hole_pixel(const std::uint8_t* p, const DetectorConfig& c) {
  return std::max({p[0], p[1], p[2]}) <= c.hole_max_channel;
}
}  // namespace

int Detector::balls(const viz::Image& img, const BlobQuery& q, Blob* out, int max) {
  const DetectorConfig& c = impl_->config;
  return find(
      *impl_, img, q, [&c](const std::uint8_t* p) { return ball_pixel(p, c); },
      [&c](const std::uint8_t* p) { return ball_weight(p, c); }, out, max);
}

int Detector::holes(const viz::Image& img, const BlobQuery& q, Blob* out, int max) {
  const DetectorConfig& c = impl_->config;
  return find(
      *impl_, img, q, [&c](const std::uint8_t* p) { return hole_pixel(p, c); },
      [&c](const std::uint8_t* p) { return hole_weight(p, c); }, out, max);
}

Blob Detector::ball(const viz::Image& img, const BlobQuery& q) {
  Blob b;
  balls(img, q, &b, 1);
  return b;
}

Blob Detector::hole(const viz::Image& img, const BlobQuery& q) {
  Blob b;
  holes(img, q, &b, 1);
  return b;
}

}  // namespace mg::vision
