// Which samples of a perceived path show the ball rolling on the open lane (path_fit.hpp:
// rolling_span, rolling_spans): what the green's fit reads of each path.
#include <cmath>
#include <optional>

#include "belief/path_fit.hpp"
#include "belief/roll_model.hpp"

namespace mg::belief {

using namespace detail;  // the rolling model and its constants (roll_model.hpp)

namespace {

/// The rolling run of `path` from sample `first` on: [first, last) and whether it ended for good
/// (a border, an obstacle, the hole, a stop, the path's end) or only for a while (a possible hop
/// or slip over a crest, after which the ball rolls again).
struct Run {
  std::size_t last = 0;
  bool final = true;
};

Run rolling_run(const field::Field& field, const ObservedPath& path, std::size_t first) {
  const auto& s = path.samples;
  const std::size_t n = s.size();
  const double r = field.ball.radius;
  const auto& b = field.bounds;
  const std::array<double, 2> hole = path.hole ? *path.hole : field.hole.position;
  const double hole_clear = 0.5 * field.hole.diameter + r + 0.01;
  std::size_t last = first;
  std::optional<ContactFilter> contact;
  double normal0 = 0.0, gravity0 = 0.0;
  for (; last < n; ++last) {
    const double x = s[last][1], y = s[last][2];
    const double border = std::min({x - b[0], b[1] - x, y - b[2], b[3] - y});
    if (border < r + 0.02) break;
    bool blocked = false;
    for (const auto& o : field.obstacles) blocked = blocked || o.distance({x, y}) < r + 0.02;
    if (blocked) break;
    if (std::hypot(x - hole[0], y - hole[1]) < hole_clear) break;
    double vx, vy;
    if (!velocity_at(s, last, vx, vy)) break;
    double normal, gravity;
    if (about_to_stop(field, x, y, vx, vy, normal, gravity)) break;
    if (!contact) {
      contact.emplace(normal);
    } else if (contact->advance(s[last][0] - s[last - 1][0], normal0, gravity0, normal, gravity) <
               kMinNormal * kGravity) {
      return {last, false};
    }
    const double sunk = -contact->e();
    if (std::hypot(vx, vy) * sunk / (2.0 * r - sunk) > kMaxSlip) return {last, false};
    normal0 = normal;
    gravity0 = gravity;
  }
  return {last, true};
}

/// [s] After a possible hop or slip, the path is read again this much later (the ball has landed
/// and its contact settled).
constexpr double kResume = 0.1;

}  // namespace

std::array<std::size_t, 2> rolling_span(const field::Field& field, const ObservedPath& path) {
  const auto& s = path.samples;
  const std::size_t n = s.size();
  if (n < 3) return {0, 0};
  // The slide: from the first samples' speed (a chord over the first 50 ms).
  std::size_t j = 1;
  while (j + 1 < n && s[j][0] - s[0][0] < 0.05) ++j;
  const double v0 = std::hypot(s[j][1] - s[0][1], s[j][2] - s[0][2]) / (s[j][0] - s[0][0]);
  const double slide = 2.0 * v0 / (7.0 * field.sliding_friction * kGravity);
  const double t_cut = s[0][0] + kSlideFactor * slide + kSlideMargin;
  std::size_t first = 0;
  while (first < n && s[first][0] < t_cut) ++first;
  const std::size_t last = rolling_run(field, path, first).last;
  if (last < first + kMinSamples) return {first, first};
  return {first, last};
}

std::vector<std::array<std::size_t, 2>> rolling_spans(const field::Field& field,
                                                      const ObservedPath& path) {
  std::vector<std::array<std::size_t, 2>> out;
  const auto& s = path.samples;
  const std::size_t n = s.size();
  std::size_t first = rolling_span(field, path)[0];
  while (first < n) {
    const Run run = rolling_run(field, path, first);
    if (run.last >= first + kMinSamples) out.push_back({first, run.last});
    if (run.final || run.last >= n) break;
    std::size_t next = run.last + 1;
    while (next < n && s[next][0] < s[run.last][0] + kResume) ++next;
    first = next;
  }
  return out;
}

}  // namespace mg::belief
