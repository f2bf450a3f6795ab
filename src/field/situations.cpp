#include "field/situations.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/error.hpp"
#include "field/field.hpp"

namespace mg::field {
namespace {

constexpr int kMaxPoints = 10000;

double lerp(double a, double b, int i, int n) {
  return n <= 1 ? 0.5 * (a + b) : a + (b - a) * i / (n - 1);
}

std::vector<std::string> split(const std::string& text, char sep) {
  std::vector<std::string> parts;
  std::string cell;
  std::istringstream in(text);
  while (std::getline(in, cell, sep)) parts.push_back(cell);
  if (!text.empty() && text.back() == sep) parts.emplace_back();
  return parts;
}

double spec_number(const std::string& spec, const std::string& cell) {
  std::size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(cell, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != cell.size() || !std::isfinite(v))
    throw InputError(
        fmt::format("--situations '{}': expected a finite number, got '{}'", spec, cell));
  return v;
}

template <std::size_t N>
std::array<double, N> spec_numbers(const std::string& spec, const std::string& part) {
  const auto cells = split(part, ',');
  if (cells.size() != N)
    throw InputError(fmt::format("--situations '{}': expected {} comma-separated numbers, got '{}'",
                                 spec, N, part));
  std::array<double, N> out{};
  for (std::size_t i = 0; i < N; ++i) out[i] = spec_number(spec, cells[i]);
  return out;
}

int spec_count(const std::string& spec, double v) {
  if (v != std::floor(v) || v < 1 || v > kMaxPoints)
    throw InputError(
        fmt::format("--situations '{}': expected a count 1..{}, got {}", spec, kMaxPoints, v));
  return static_cast<int>(v);
}

}  // namespace

std::string to_string(RegionShape shape) {
  switch (shape) {
    case RegionShape::kLine:
      return "line";
    case RegionShape::kGrid:
      return "grid";
    case RegionShape::kBox:
      return "box";
    case RegionShape::kList:
      return "list";
  }
  return "?";
}

double situation_input(const Field& field, std::string_view name, const Situation& situation) {
  const auto& [ball, hole] = situation;
  if (name == "xi_x") return hole[0] - ball[0];
  if (name == "xi_y") return hole[1] - ball[1];
  if (name == "hole_x") return hole[0];
  if (name == "hole_y") return hole[1];
  if (name == "ball_x") return ball[0];
  if (name == "ball_y") return ball[1];
  (void)field;
  throw InputError(fmt::format("input '{}' is not a situation (expected one of {})", name,
                               fmt::join(kSituationInputs, ", ")));
}

double situation_input(const Field& field, std::string_view name, std::array<double, 2> hole) {
  return situation_input(field, name, Situation{field.tee, hole});
}

bool translation_invariant(const Field& field) {
  if (!field.obstacles.empty()) return false;
  const auto& b = field.bounds;
  const auto g0 = field.surface.gradient(b[0], b[2]);
  constexpr int kSteps = 40;
  for (int i = 0; i <= kSteps; ++i)
    for (int j = 0; j <= kSteps; ++j) {
      const auto g = field.surface.gradient(b[0] + (b[1] - b[0]) * i / kSteps,
                                            b[2] + (b[3] - b[2]) * j / kSteps);
      if (std::abs(g[0] - g0[0]) > 1e-9 || std::abs(g[1] - g0[1]) > 1e-9) return false;
    }
  return true;
}

std::vector<std::string> Situations::learner_inputs() const {
  if (balls) {
    if (ball_inputs) return {"xi_x", "xi_y", "ball_x", "ball_y"};
    return {"xi_x", "xi_y"};
  }
  if (shape == RegionShape::kLine)
    return {std::abs(to[1] - from[1]) >= std::abs(to[0] - from[0]) ? "xi_y" : "xi_x"};
  return {"xi_x", "xi_y"};
}

std::vector<std::string> Situations::learner_outputs() const {
  if (learn_speed) return {"angle", "speed"};
  return {"angle"};
}

std::vector<std::array<double, 2>> Region::collection_points() const {
  std::vector<std::array<double, 2>> p;
  switch (shape) {
    case RegionShape::kLine:
      for (int i = 0; i < count; ++i)
        p.push_back({lerp(from[0], to[0], i, count), lerp(from[1], to[1], i, count)});
      break;
    case RegionShape::kGrid:
    case RegionShape::kBox:
      for (int i = 0; i < counts[0]; ++i)
        for (int j = 0; j < counts[1]; ++j)
          p.push_back({lerp(x_range[0], x_range[1], i, counts[0]),
                       lerp(y_range[0], y_range[1], j, counts[1])});
      break;
    case RegionShape::kList:
      p = points;
      break;
  }
  return p;
}

std::array<double, 2> Region::sample(Rng& rng) const {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  switch (shape) {
    case RegionShape::kLine: {
      const double s = u(rng);
      return {from[0] + s * (to[0] - from[0]), from[1] + s * (to[1] - from[1])};
    }
    case RegionShape::kGrid:
    case RegionShape::kBox: {
      const double sx = u(rng), sy = u(rng);
      return {x_range[0] + sx * (x_range[1] - x_range[0]),
              y_range[0] + sy * (y_range[1] - y_range[0])};
    }
    case RegionShape::kList: {
      std::uniform_int_distribution<std::size_t> pick(0, points.size() - 1);
      return points[pick(rng)];
    }
  }
  return {0, 0};
}

std::vector<std::array<double, 2>> Region::sample(int n, std::uint64_t seed) const {
  std::vector<std::array<double, 2>> out;
  out.reserve(static_cast<std::size_t>(std::max(n, 0)));
  for (int i = 0; i < n; ++i) {
    Rng rng(derive_seed(seed, static_cast<std::uint64_t>(i)));
    out.push_back(sample(rng));
  }
  return out;
}

std::vector<std::array<double, 2>> Region::corners() const {
  switch (shape) {
    case RegionShape::kLine:
      return {from, to};
    case RegionShape::kList:
      return points;
    case RegionShape::kGrid:
    case RegionShape::kBox:
      break;
  }
  return {{x_range[0], y_range[0]},
          {x_range[0], y_range[1]},
          {x_range[1], y_range[0]},
          {x_range[1], y_range[1]}};
}

void Region::check_shape(const std::string& where) const {
  const auto bad = [&](const std::string& why) {
    throw InputError(fmt::format("{}: {}", where, why));
  };
  switch (shape) {
    case RegionShape::kLine:
      if (count < 1 || count > kMaxPoints)
        bad(fmt::format("line.count: expected 1..{}, got {}", kMaxPoints, count));
      break;
    case RegionShape::kGrid:
    case RegionShape::kBox:
      if (counts[0] < 1 || counts[1] < 1 || counts[0] * counts[1] > kMaxPoints)
        bad(fmt::format("counts: expected two counts >= 1 with at most {} points, got [{}, {}]",
                        kMaxPoints, counts[0], counts[1]));
      if (x_range[1] < x_range[0] || y_range[1] < y_range[0])
        bad(fmt::format("expected x and y ranges as [low, high], got [{}, {}], [{}, {}]",
                        x_range[0], x_range[1], y_range[0], y_range[1]));
      break;
    case RegionShape::kList:
      if (points.empty() || points.size() > kMaxPoints)
        bad(fmt::format("list.points: expected 1..{} points", kMaxPoints));
      break;
  }
}

void Situations::validate(const Field& field, const std::string& where_arg) const {
  const std::string where =
      where_arg.empty() ? fmt::format("{}: situations", field.source) : where_arg;
  const auto bad = [&](const std::string& why) {
    throw InputError(fmt::format("{}: {}", where, why));
  };
  check_shape(where);
  if (strategy != "min-speed" && strategy != "min-angle")
    bad(fmt::format("strategy: expected min-speed or min-angle, got '{}'", strategy));
  if (!learn_speed && !(speed > 0.0 && speed <= 10.0))
    bad(fmt::format("speed: an angle-only region needs its club speed in (0, 10] m/s, got {}",
                    speed));
  // Every hole of the region (its corners suffice for lines and rectangles) must fit the lane.
  for (const auto& c : corners()) {
    try {
      check_hole_position(field, c);
    } catch (const InputError& e) {
      bad(e.what());
    }
    if (std::hypot(c[0] - field.tee[0], c[1] - field.tee[1]) < field.hole.diameter)
      bad(fmt::format("hole ({}, {}) lies on the tee", c[0], c[1]));
  }
  if (!balls) return;
  balls->check_shape(where + ": ball");
  // A rectangle's corners on the lane leave its inside on it only without obstacles: the
  // collection grid is checked too.
  auto ball_points = balls->corners();
  for (const auto& p : balls->collection_points()) ball_points.push_back(p);
  for (const auto& p : ball_points) check_ball_position(field, p, where + ": ball");
  if (collection_situations(field).empty())
    bad(fmt::format(
        "no (ball, hole) pair to play: every hole covers every ball, or the balls lie on slopes a "
        "ball does not rest on (steeper than {} x rolling_resistance)",
        kRestSlopeFraction));
}

std::array<double, 4> Region::bounds() const {
  const auto c = corners();
  if (c.empty()) throw InputError("situations: an empty list of points");
  std::array<double, 4> b{c[0][0], c[0][0], c[0][1], c[0][1]};
  for (const auto& p : c) {
    b[0] = std::min(b[0], p[0]), b[1] = std::max(b[1], p[0]);
    b[2] = std::min(b[2], p[1]), b[3] = std::max(b[3], p[1]);
  }
  return b;
}

bool ball_rests(const Field& field, std::array<double, 2> p) {
  const auto g = field.surface.gradient(p[0], p[1]);
  return std::hypot(g[0], g[1]) <= kRestSlopeFraction * field.rolling_resistance;
}

bool playable(const Field& field, const Situation& s) {
  if (std::hypot(s.hole[0] - s.ball[0], s.hole[1] - s.ball[1]) < field.hole.diameter) return false;
  for (const auto& o : field.obstacles)
    if (o.distance(s.ball) < field.ball.radius) return false;
  return s.ball == field.tee || ball_rests(field, s.ball);
}

std::vector<Situation> Situations::collection_situations(const Field& field) const {
  const std::vector<std::array<double, 2>> ball_points =
      balls ? balls->collection_points() : std::vector<std::array<double, 2>>{field.tee};
  std::vector<Situation> out;
  for (const auto& b : ball_points)
    for (const auto& h : collection_points())
      if (const Situation s{b, h}; playable(field, s)) out.push_back(s);
  return out;
}

std::vector<Situation> Situations::sample_situations(const Field& field, int n,
                                                     std::uint64_t seed) const {
  std::vector<Situation> out;
  out.reserve(static_cast<std::size_t>(std::max(n, 0)));
  for (int i = 0; i < n; ++i) {
    Rng rng(derive_seed(seed, static_cast<std::uint64_t>(i)));
    out.push_back(sample_situation(field, rng));
  }
  return out;
}

Situation Situations::sample_situation(const Field& field, Rng& rng) const {
  constexpr int kRedraws = 100;
  Situation s{field.tee, sample(rng)};
  if (!balls) return s;
  int tries = 0;
  do {
    s.ball = balls->sample(rng);
  } while (!playable(field, s) && ++tries < kRedraws);
  if (!playable(field, s))
    throw InputError(fmt::format(
        "situations: no ball of the ball region clears the hole at ({}, {}) and the obstacles "
        "on a slope a ball rests on",
        s.hole[0], s.hole[1]));
  return s;
}

Situations region_from_spec(const Field& field, const std::string& spec,
                            const std::string& balls_spec) {
  Situations r = spec.empty() ? field.situations : parse_situations_spec(spec, field.situations);
  const std::string holes_where = spec.empty() ? "" : fmt::format("--situations '{}'", spec);
  if (!balls_spec.empty()) {
    r.validate(field, holes_where);  // a bad hole region is named as such
    try {
      r.balls = parse_situations_spec(balls_spec, Situations{});
    } catch (const InputError& e) {  // name the option the spec came from
      std::string what = e.what();
      if (what.rfind("--situations", 0) == 0) what.replace(0, 12, "--balls");
      throw InputError(what);
    }
    r.ball_inputs = !translation_invariant(field);
  }
  r.validate(field, balls_spec.empty() ? holes_where : fmt::format("--balls '{}'", balls_spec));
  return r;
}

Situations default_situations(const Field& field) {
  Situations s;
  s.shape = RegionShape::kBox;
  const double r = 0.5 * field.hole.diameter + 1e-3;
  const auto& b = field.bounds;
  const auto& h = field.hole.position;
  s.x_range = {std::max(h[0] - 0.1, b[0] + r), std::min(h[0] + 0.1, b[1] - r)};
  s.y_range = {std::max(h[1] - 0.1, b[2] + r), std::min(h[1] + 0.1, b[3] - r)};
  s.counts = {3, 3};
  s.learn_speed = true;
  s.strategy = "min-speed";
  s.from_file = false;
  return s;
}

Situations parse_situations_spec(const std::string& spec, const Situations& base) {
  Situations s = base;
  s.from_file = false;
  const auto parts = split(spec, ':');
  const std::string kind = parts.empty() ? "" : parts[0];
  const auto need = [&](std::size_t n, const char* form) {
    if (parts.size() != n)
      throw InputError(fmt::format("--situations '{}': expected {}", spec, form));
  };
  if (kind == "line") {
    need(4, "line:X0,Y0:X1,Y1:N");
    s.shape = RegionShape::kLine;
    s.from = spec_numbers<2>(spec, parts[1]);
    s.to = spec_numbers<2>(spec, parts[2]);
    s.count = spec_count(spec, spec_number(spec, parts[3]));
  } else if (kind == "grid" || kind == "box") {
    need(4, kind == "grid" ? "grid:X0,X1:Y0,Y1:NX,NY" : "box:X0,X1:Y0,Y1:NX,NY");
    s.shape = kind == "grid" ? RegionShape::kGrid : RegionShape::kBox;
    s.x_range = spec_numbers<2>(spec, parts[1]);
    s.y_range = spec_numbers<2>(spec, parts[2]);
    const auto n = spec_numbers<2>(spec, parts[3]);
    s.counts = {spec_count(spec, n[0]), spec_count(spec, n[1])};
  } else if (kind == "list") {
    need(2, "list:X,Y;X,Y;...");
    s.shape = RegionShape::kList;
    s.points.clear();
    for (const std::string& p : split(parts[1], ';')) s.points.push_back(spec_numbers<2>(spec, p));
    if (s.points.size() > kMaxPoints)
      throw InputError(fmt::format("--situations '{}': too many points", spec));
  } else {
    throw InputError(
        fmt::format("--situations '{}': expected line:..., grid:..., box:... or list:...", spec));
  }
  return s;
}

}  // namespace mg::field
