#include "teacher/bank_shots.hpp"

#include <algorithm>
#include <cmath>

namespace mg::teacher {
namespace {
constexpr double kGravity = 9.81;
}  // namespace

std::vector<BankShot> bank_shots(const field::Field& f, std::array<double, 2> ball,
                                 std::array<double, 2> hole, double arrival) {
  const auto& b = f.bounds;
  const double r = f.ball.radius, e = f.borders.restitution;
  const double a_roll = 5.0 / 7.0 * f.rolling_resistance * kGravity;
  std::vector<BankShot> out;
  for (int side = 0; side < 4; ++side) {
    const bool vertical = side < 2;  // x = const
    const double line = side == 0   ? b[0] + r
                        : side == 1 ? b[1] - r
                        : side == 2 ? b[2] + r
                                    : b[3] - r;
    std::array<double, 2> image = hole;
    image[vertical ? 0 : 1] = 2.0 * line - hole[vertical ? 0 : 1];
    const int k = vertical ? 0 : 1;
    const double denom = image[k] - ball[k];
    if (std::abs(denom) < 1e-9) continue;
    const double t = (line - ball[k]) / denom;
    if (!(t > 0.0 && t < 1.0)) continue;
    const std::array<double, 2> bounce{ball[0] + t * (image[0] - ball[0]),
                                       ball[1] + t * (image[1] - ball[1])};
    if (field::line_blocked(f, ball, bounce, r) || field::line_blocked(f, bounce, hole, r))
      continue;
    const double l1 = std::hypot(bounce[0] - ball[0], bounce[1] - ball[1]);
    const double l2 = std::hypot(hole[0] - bounce[0], hole[1] - bounce[1]);
    const double normal = std::abs(denom) / (l1 + l2);  // sine of the incidence on the line
    const double keep = (1.0 - normal * normal) + e * e * normal * normal;
    const double after = arrival * arrival + 2.0 * a_roll * l2;
    const double v2 = after / std::max(keep, 0.05) + 2.0 * a_roll * l1;
    out.push_back(
        {std::atan2(image[1] - ball[1], image[0] - ball[0]), 7.0 / 5.0 * std::sqrt(v2), l1 + l2});
  }
  std::sort(out.begin(), out.end(),
            [](const BankShot& x, const BankShot& y) { return x.path_length < y.path_length; });
  return out;
}

}  // namespace mg::teacher
