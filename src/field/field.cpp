#include "field/field.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "core/check.hpp"
#include "core/error.hpp"
#include "core/io.hpp"
#include "field/map_reader.hpp"

namespace mg::field {
namespace {

constexpr int kFormatVersion = 1;

SurfaceTerm parse_term(MapReader r, const Field& field, const std::filesystem::path& base_dir) {
  const std::string type = r.text("type", "");
  SurfaceTerm term;
  if (type == "plane") {
    PlaneTerm t;
    t.offset = r.number("offset", 0.0);
    t.slope_x = r.number("slope_x", 0.0);
    t.slope_y = r.number("slope_y", 0.0);
    term = t;
  } else if (type == "bump") {
    BumpTerm t;
    t.center = r.numbers<2>("center");
    t.height = r.number("height");
    t.sigma = r.numbers<2>("sigma");
    if (!(t.sigma[0] > 0 && t.sigma[1] > 0)) r.fail(r.full("sigma"), "expected positive widths");
    term = t;
  } else if (type == "hill") {
    HillTerm t;
    t.crest = r.numbers<2>("crest");
    t.direction = r.numbers<2>("direction", {1.0, 0.0});
    const double n = std::hypot(t.direction[0], t.direction[1]);
    if (!(n > 0)) r.fail(r.full("direction"), "expected a non-zero vector");
    t.direction = {t.direction[0] / n, t.direction[1] / n};
    t.height = r.number("height");
    t.half_width = r.number("half_width");
    if (!(t.half_width > 0)) r.fail(r.full("half_width"), "expected a positive number");
    term = t;
  } else if (type == "arctan") {
    ArctanTerm t;
    t.center = r.numbers<2>("center", {0.0, 0.0});
    t.amplitude = r.number("amplitude");
    t.scale_x = r.number("scale_x");
    t.scale_y = r.number("scale_y", 0.0);
    term = t;
  } else if (type == "flatten") {
    FlattenTerm t;
    t.center = r.numbers<2>("center", field.tee);
    t.radius = r.number("radius", t.radius);
    t.blend_radius = r.number("blend_radius", t.blend_radius);
    if (!(t.radius >= 0.0)) r.fail(r.full("radius"), "expected a number >= 0");
    if (!(t.blend_radius > t.radius))
      r.fail(r.full("blend_radius"),
             fmt::format("expected more than radius ({}), got {}", t.radius, t.blend_radius));
    term = t;
  } else if (type == "heightmap") {
    std::filesystem::path file = r.text("file", "");
    if (file.empty()) r.fail(r.full("file"), "missing (required)");
    if (file.is_relative()) file = base_dir / file;
    const double z_min = r.number("z_min", 0.0);
    const double z_max = r.number("z_max", 0.0);
    const auto bounds = r.numbers<4>("bounds", field.bounds);
    try {
      term = load_heightmap(file.string(), bounds, z_min, z_max);
    } catch (const Error& e) {
      throw InputError(fmt::format("{}: {}: {}", r.source(), r.full("file"), e.what()));
    }
  } else {
    r.fail(r.full("type"), fmt::format("unknown surface type '{}' (expected plane, bump, hill, "
                                       "arctan, heightmap or flatten)",
                                       type));
  }
  r.finish();
  return term;
}

Obstacle parse_obstacle(MapReader r) {
  const std::string type = r.text("type", "");
  Obstacle o;
  if (type == "wall") {
    o.type = ObstacleType::kWall;
    o.from = r.numbers<2>("from");
    o.to = r.numbers<2>("to");
    o.thickness = r.number("thickness", o.thickness);
  } else if (type == "block") {
    o.type = ObstacleType::kBlock;
    o.center = r.numbers<2>("center");
    o.size = r.numbers<2>("size");
    o.yaw = r.number("yaw", 0.0);
  } else {
    r.fail(r.full("type"),
           fmt::format("unknown obstacle type '{}' (expected wall or block)", type));
  }
  o.height = r.number("height", o.height);
  o.restitution = r.number("restitution", o.restitution);
  r.finish();
  return o;
}

/// One region's shape from `r` (exactly one of line, grid, box, list).
void parse_region(MapReader& r, Region& s) {
  int shapes = 0;
  if (r.has("line")) {
    ++shapes;
    MapReader l = r.child("line");
    s.shape = RegionShape::kLine;
    s.from = l.numbers<2>("from");
    s.to = l.numbers<2>("to");
    s.count = l.integer("count");
    l.finish();
  }
  for (const char* kind : {"grid", "box"}) {
    if (!r.has(kind)) continue;
    ++shapes;
    MapReader g = r.child(kind);
    s.shape = std::string(kind) == "grid" ? RegionShape::kGrid : RegionShape::kBox;
    s.x_range = g.numbers<2>("x");
    s.y_range = g.numbers<2>("y");
    s.counts = g.integers<2>("counts");
    g.finish();
  }
  if (r.has("list")) {
    ++shapes;
    MapReader l = r.child("list");
    s.shape = RegionShape::kList;
    const YAML::Node pts = l.require("points");
    if (!pts.IsSequence()) l.fail(l.full("points"), "expected a list of [x, y]");
    for (std::size_t i = 0; i < pts.size(); ++i)
      s.points.push_back(l.to_numbers<2>(pts[i], fmt::format("{}[{}]", l.full("points"), i)));
    l.finish();
  }
  if (shapes != 1)
    r.fail(r.full("(shape)"),
           fmt::format("expected exactly one of line, grid, box, list; got {}", shapes));
}

Situations parse_situations(MapReader r, const Field& field) {
  Situations s;
  s.from_file = true;
  parse_region(r, s);
  if (r.has("ball")) {
    MapReader b = r.child("ball");
    Region balls;
    parse_region(b, balls);
    b.finish();
    s.balls = balls;
    s.ball_inputs = !translation_invariant(field);
  }
  if (r.has("outputs")) {
    const auto outputs = r.texts("outputs");
    if (outputs == std::vector<std::string>{"angle"})
      s.learn_speed = false;
    else if (outputs == std::vector<std::string>{"angle", "speed"})
      s.learn_speed = true;
    else
      r.fail(r.full("outputs"), "expected [angle] or [angle, speed]");
  }
  s.speed = r.number("speed", 0.0);
  if (s.learn_speed && r.has("speed"))
    r.fail(r.full("speed"), "only for outputs: [angle] (the fixed club speed)");
  if (!s.learn_speed && !r.has("speed"))
    r.fail(r.full("speed"), "missing (required with outputs: [angle])");
  s.strategy = r.text("strategy", s.strategy);
  r.finish();
  s.validate(field);
  return s;
}

}  // namespace

void Field::validate() const {
  const auto where = [&](std::string_view what) { return fmt::format("{}: {}", source, what); };
  for (double b : bounds) require_finite(where("lane.bounds"), b);
  if (!(bounds[1] - bounds[0] >= 0.5 && bounds[3] - bounds[2] >= 0.2))
    throw InputError(fmt::format("{}: expected a lane of at least 0.5 x 0.2 m, got {} x {} m",
                                 where("lane.bounds"), bounds[1] - bounds[0],
                                 bounds[3] - bounds[2]));
  if (bounds[1] - bounds[0] > 50 || bounds[3] - bounds[2] > 50)
    throw InputError(fmt::format("{}: expected a lane of at most 50 x 50 m", where("lane.bounds")));
  require_in_range(where("lane.cell_size"), cell_size, 0.005, 0.25);
  const double cells = (bounds[1] - bounds[0]) / cell_size * (bounds[3] - bounds[2]) / cell_size;
  if (cells > 4e6)
    throw InputError(fmt::format("{}: expected at most 4e6 heightfield cells, got {:.0f}",
                                 where("lane.cell_size"), cells));
  require_in_range(where("ball.radius"), ball.radius, 0.005, 0.1);
  require_in_range(where("ball.mass"), ball.mass, 0.001, 1.0);
  require_in_range(where("hole.diameter"), hole.diameter, 2.0 * ball.radius + 1e-3, 1.0);
  require_in_range(where("hole.depth"), hole.depth, 0.002, 0.5);
  require_in_range(where("rolling_resistance"), rolling_resistance, 0.0, 1.0);
  require_in_range(where("sliding_friction"), sliding_friction, 0.01, 2.0);
  require_in_range(where("borders.height"), borders.height, 2.0 * ball.radius, 1.0);
  require_in_range(where("borders.thickness"), borders.thickness, 0.005, 0.5);
  require_in_range(where("borders.restitution"), borders.restitution, 0.0, kMaxWallRestitution);
  const double margin = ball.radius;
  if (tee[0] < bounds[0] + margin || tee[0] > bounds[1] - margin || tee[1] < bounds[2] + margin ||
      tee[1] > bounds[3] - margin)
    throw InputError(fmt::format("{}: expected a point inside the lane, got ({}, {})", where("tee"),
                                 tee[0], tee[1]));
  if (obstacles.size() > kMaxObstacles)
    throw InputError(fmt::format("{}: expected at most {} obstacles, got {}", where("obstacles"),
                                 kMaxObstacles, obstacles.size()));
  for (std::size_t i = 0; i < obstacles.size(); ++i) {
    const Obstacle& o = obstacles[i];
    const auto key = [&](std::string_view k) {
      return where(fmt::format("obstacles[{}].{}", i, k));
    };
    if (o.type == ObstacleType::kWall) {
      for (std::size_t k = 0; k < 2; ++k) {
        require_in_range(key("from"), o.from[k], -100.0, 100.0);
        require_in_range(key("to"), o.to[k], -100.0, 100.0);
      }
      const double length = std::hypot(o.to[0] - o.from[0], o.to[1] - o.from[1]);
      if (!(length >= 0.01))
        throw InputError(
            fmt::format("{}: expected a wall at least 0.01 m long, got {} m", key("to"), length));
      require_in_range(key("thickness"), o.thickness, 0.005, 0.5);
    } else {
      for (std::size_t k = 0; k < 2; ++k) {
        require_in_range(key("center"), o.center[k], -100.0, 100.0);
        require_in_range(key("size"), o.size[k], 0.01, 50.0);
      }
      require_in_range(key("yaw"), o.yaw, -10.0, 10.0);
    }
    require_in_range(key("height"), o.height, 2.0 * ball.radius, 1.0);
    require_in_range(key("restitution"), o.restitution, 0.0, kMaxWallRestitution);
    const Footprint fp = o.footprint();
    if (fp.center[0] < bounds[0] || fp.center[0] > bounds[1] || fp.center[1] < bounds[2] ||
        fp.center[1] > bounds[3])
      throw InputError(fmt::format("{}: the obstacle's centre ({}, {}) lies outside the lane",
                                   key("type"), fp.center[0], fp.center[1]));
    if (o.distance(tee) < ball.radius)
      throw InputError(fmt::format("{}: the tee ({}, {}) lies inside this {}", where("tee"), tee[0],
                                   tee[1], to_string(o.type)));
  }
  check_hole_position(*this, hole.position);
  // The surface must be finite and not absurdly steep anywhere on the lane.
  const int n = 64;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double x = bounds[0] + (bounds[1] - bounds[0]) * i / n;
      const double y = bounds[2] + (bounds[3] - bounds[2]) * j / n;
      const double z = height(x, y);
      if (!std::isfinite(z) || std::abs(z) > 10.0)
        throw InputError(
            fmt::format("{}: height {} at ({:.3f}, {:.3f}) is not a finite value "
                        "within +-10 m",
                        where("surface"), z, x, y));
      const auto g = surface.gradient(x, y);
      if (std::hypot(g[0], g[1]) > 1.0)
        throw InputError(
            fmt::format("{}: slope {:.2f} at ({:.3f}, {:.3f}) is steeper than 45 "
                        "degrees",
                        where("surface"), std::hypot(g[0], g[1]), x, y));
    }
}

void check_hole_position(const Field& field, std::array<double, 2> p) {
  const double r = 0.5 * field.hole.diameter;
  const auto& b = field.bounds;
  if (!std::isfinite(p[0]) || !std::isfinite(p[1]))
    throw InputError(
        fmt::format("hole position: expected finite numbers, got ({}, {})", p[0], p[1]));
  if (p[0] - r < b[0] || p[0] + r > b[1] || p[1] - r < b[2] || p[1] + r > b[3])
    throw InputError(
        fmt::format("hole position: ({}, {}) puts the hole outside the lane of field '{}' "
                    "(x in [{}, {}], y in [{}, {}], hole radius {})",
                    p[0], p[1], field.name, b[0], b[1], b[2], b[3], r));
  for (std::size_t i = 0; i < field.obstacles.size(); ++i)
    if (field.obstacles[i].distance(p) < r)
      throw InputError(
          fmt::format("hole position: ({}, {}) puts the hole inside obstacle {} ({}) "
                      "of field '{}'",
                      p[0], p[1], i, to_string(field.obstacles[i].type), field.name));
  // A ball resting in or over the cup before the stroke is not a putt.
  const double gap = std::hypot(p[0] - field.tee[0], p[1] - field.tee[1]);
  if (gap < r + field.ball.radius)
    throw InputError(
        fmt::format("hole position: ({}, {}) puts the hole on the tee ({}, {}) of field '{}' "
                    "(they must be at least {:.4g} m apart)",
                    p[0], p[1], field.tee[0], field.tee[1], field.name, r + field.ball.radius));
}

Field parse_field(std::string_view yaml_text, const std::string& source,
                  const std::filesystem::path& base_dir) {
  const YAML::Node root = load_yaml(yaml_text, source);
  if (!root || root.IsNull()) throw InputError(fmt::format("{}: empty field file", source));
  Field f;
  f.source = source;
  try {
    MapReader r(root, source, "");
    const double version = r.number("format_version");
    if (version != kFormatVersion)
      r.fail("format_version", fmt::format("expected {}, got {}", kFormatVersion, version));
    f.name = r.name("name", std::filesystem::path(source).stem().string());
    f.description = r.text("description", "");
    {
      MapReader lane = r.child("lane");
      f.bounds = lane.numbers<4>("bounds");
      f.cell_size = lane.number("cell_size", f.cell_size);
      lane.finish();
    }
    f.tee = r.numbers<2>("tee");
    {
      MapReader hole = r.child("hole");
      f.hole.position = hole.numbers<2>("position");
      f.hole.diameter = hole.number("diameter", f.hole.diameter);
      f.hole.depth = hole.number("depth", f.hole.depth);
      hole.finish();
    }
    if (r.has_child("ball")) {
      MapReader ball = r.child("ball");
      f.ball.radius = ball.number("radius", f.ball.radius);
      f.ball.mass = ball.number("mass", f.ball.mass);
      ball.finish();
    }
    f.rolling_resistance = r.number("rolling_resistance");
    f.sliding_friction = r.number("sliding_friction", f.sliding_friction);
    if (r.has_child("borders")) {
      MapReader borders = r.child("borders");
      f.borders.height = borders.number("height", f.borders.height);
      f.borders.thickness = borders.number("thickness", f.borders.thickness);
      f.borders.restitution = borders.number("restitution", f.borders.restitution);
      borders.finish();
    }
    if (r.has("obstacles")) {
      const YAML::Node obstacles = r.require("obstacles");
      if (!obstacles.IsSequence()) r.fail("obstacles", "expected a list of walls and blocks");
      if (obstacles.size() > kMaxObstacles)
        r.fail("obstacles", fmt::format("expected at most {} obstacles, got {}", kMaxObstacles,
                                        obstacles.size()));
      for (std::size_t i = 0; i < obstacles.size(); ++i)
        f.obstacles.push_back(
            parse_obstacle(MapReader(obstacles[i], source, fmt::format("obstacles[{}]", i))));
    }
    const YAML::Node surface = r.require("surface");
    if (!surface.IsSequence() || surface.size() == 0)
      r.fail("surface", "expected a non-empty list of terms");
    for (std::size_t i = 0; i < surface.size(); ++i)
      f.surface.terms.push_back(
          parse_term(MapReader(surface[i], source, fmt::format("surface[{}]", i)), f, base_dir));
    f.situations =
        r.has("situations") ? parse_situations(r.child("situations"), f) : default_situations(f);
    r.finish();
  } catch (const YAML::Exception& e) {
    throw InputError(fmt::format("{}: malformed field: {}", source, e.what()));
  }
  f.validate();
  return f;
}

Field load_field(std::string_view name_or_path) {
  const std::string arg(name_or_path);
  if (arg.empty()) throw InputError("field: expected a name or a path, got ''");
  const bool is_path =
      arg.find('/') != std::string::npos || arg.ends_with(".yaml") || arg.ends_with(".yml");
  std::filesystem::path path;
  if (is_path) {
    path = arg;
  } else {
    path = data_dir() / "fields" / (arg + ".yaml");
    std::error_code ec;
    if (!std::filesystem::exists(path, ec))  // ec: a name too long is unknown, not a crash
      throw InputError(
          fmt::format("field: unknown field '{}' (shipped: {}; give a path for your "
                      "own file)",
                      shown_path(arg), fmt::join(list_shipped_fields(), ", ")));
  }
  return parse_field(read_text_file(path), path.string(), path.parent_path());
}

std::vector<std::string> list_shipped_fields() {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(data_dir() / "fields", ec))
    if (entry.path().extension() == ".yaml") names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::array<double, 2> height_range(const Field& f) {
  const auto& b = f.bounds;
  const int ncol = static_cast<int>(std::lround((b[1] - b[0]) / f.cell_size)) + 1;
  const int nrow = static_cast<int>(std::lround((b[3] - b[2]) / f.cell_size)) + 1;
  double z_min = 1e9, z_max = -1e9;
  for (int r = 0; r < nrow; ++r)
    for (int c = 0; c < ncol; ++c) {
      const double z =
          f.height(b[0] + (b[1] - b[0]) * c / (ncol - 1), b[2] + (b[3] - b[2]) * r / (nrow - 1));
      z_min = std::min(z_min, z);
      z_max = std::max(z_max, z);
    }
  return {z_min, z_max};
}

double obstacle_top(const Field& f, const Obstacle& ob) {
  const Footprint fp = ob.footprint();
  const double c = std::cos(fp.yaw), s = std::sin(fp.yaw);
  double ground = -1e9;
  const int n = 8;
  for (int u = 0; u <= n; ++u)
    for (int v = 0; v <= n; ++v) {
      const double lu = fp.half[0] * (2.0 * u / n - 1.0), lv = fp.half[1] * (2.0 * v / n - 1.0);
      ground = std::max(ground,
                        f.height(fp.center[0] + c * lu - s * lv, fp.center[1] + s * lu + c * lv));
    }
  return ground + ob.height;
}

void check_ball_position(const field::Field& field, std::array<double, 2> ball,
                         const std::string& what) {
  const auto& b = field.bounds;
  const double r = field.ball.radius;
  if (!std::isfinite(ball[0]) || !std::isfinite(ball[1]) || ball[0] < b[0] + r ||
      ball[0] > b[1] - r || ball[1] < b[2] + r || ball[1] > b[3] - r)
    throw InputError(
        fmt::format("{}: expected a ball on the lane [{}, {}] x [{}, {}], got ({}, {})", what,
                    b[0] + r, b[1] - r, b[2] + r, b[3] - r, ball[0], ball[1]));
  for (std::size_t i = 0; i < field.obstacles.size(); ++i)
    if (field.obstacles[i].distance(ball) < r)
      throw InputError(fmt::format("{}: the ball at ({}, {}) lies inside obstacle {} ({})", what,
                                   ball[0], ball[1], i, to_string(field.obstacles[i].type)));
}

bool line_blocked(const Field& field, std::array<double, 2> a, std::array<double, 2> b,
                  double clearance) {
  if (field.obstacles.empty()) return false;
  const double len = std::hypot(b[0] - a[0], b[1] - a[1]);
  const int n = std::max(2, static_cast<int>(std::ceil(len / 0.01)));
  for (int k = 0; k <= n; ++k) {
    const double t = static_cast<double>(k) / n;
    const std::array<double, 2> p{a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])};
    for (const auto& o : field.obstacles)
      if (o.distance(p) < clearance) return true;
  }
  return false;
}

}  // namespace mg::field
