#include "belief/residuals.hpp"

#include <cmath>
#include <map>
#include <set>

#include <fmt/format.h>

#include "core/error.hpp"

namespace mg::belief {

ResidualSummary summarize_residuals(const GreenEstimate& estimate, double bin_width) {
  if (!(std::isfinite(bin_width) && bin_width > 0.0))
    throw InputError(fmt::format("residual bins: expected a positive width, got {}", bin_width));
  ResidualSummary out;
  const auto& res = estimate.residuals;
  out.samples = static_cast<int>(res.size());
  if (res.empty()) return out;

  struct Sums {
    int samples = 0;
    double along = 0.0, across = 0.0, squares = 0.0;
    std::set<int> paths;
  };
  std::map<long, Sums> bins;
  double along2 = 0.0, across2 = 0.0, lagged = 0.0, power = 0.0;
  for (std::size_t i = 0; i < res.size(); ++i) {
    const SampleResidual& r = res[i];
    const double along = r.dx * r.heading[0] + r.dy * r.heading[1];
    const double across = -r.dx * r.heading[1] + r.dy * r.heading[0];
    along2 += along * along;
    across2 += across * across;
    power += r.dx * r.dx + r.dy * r.dy;
    if (i + 1 < res.size() && res[i + 1].path == r.path && res[i + 1].run == r.run)
      lagged += r.dx * res[i + 1].dx + r.dy * res[i + 1].dy;
    Sums& b = bins[static_cast<long>(std::floor(r.x / bin_width))];
    ++b.samples;
    b.along += along;
    b.across += across;
    b.squares += r.dx * r.dx + r.dy * r.dy;
    b.paths.insert(r.path);
  }
  const double n = static_cast<double>(res.size());
  out.rms_along = std::sqrt(along2 / n);
  out.rms_across = std::sqrt(across2 / n);
  out.lag1 = power > 0.0 ? lagged / power : 0.0;
  out.structured = out.lag1 > kStructuredLag1 && out.lag1 > 4.0 / std::sqrt(n);
  for (const auto& [index, b] : bins) {
    ResidualBin bin;
    bin.x_from = static_cast<double>(index) * bin_width;
    bin.x_to = bin.x_from + bin_width;
    bin.samples = b.samples;
    bin.paths = static_cast<int>(b.paths.size());
    bin.along = b.along / b.samples;
    bin.across = b.across / b.samples;
    bin.rms = std::sqrt(b.squares / (2.0 * b.samples));
    out.bins.push_back(bin);
  }
  return out;
}

}  // namespace mg::belief
