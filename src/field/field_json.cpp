#include "field/field_json.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace mg::field {
namespace {

struct TermToJson {
  nlohmann::json operator()(const PlaneTerm& t) const {
    return {
        {"type", "plane"}, {"offset", t.offset}, {"slope_x", t.slope_x}, {"slope_y", t.slope_y}};
  }
  nlohmann::json operator()(const BumpTerm& t) const {
    return {{"type", "bump"}, {"center", t.center}, {"height", t.height}, {"sigma", t.sigma}};
  }
  nlohmann::json operator()(const HillTerm& t) const {
    return {{"type", "hill"},
            {"crest", t.crest},
            {"direction", t.direction},
            {"height", t.height},
            {"half_width", t.half_width}};
  }
  nlohmann::json operator()(const ArctanTerm& t) const {
    return {{"type", "arctan"},
            {"center", t.center},
            {"amplitude", t.amplitude},
            {"scale_x", t.scale_x},
            {"scale_y", t.scale_y}};
  }
  nlohmann::json operator()(const FlattenTerm& t) const {
    return {{"type", "flatten"},
            {"center", t.center},
            {"radius", t.radius},
            {"blend_radius", t.blend_radius}};
  }
  nlohmann::json operator()(const HeightmapTerm& t) const {
    return {{"type", "heightmap"},
            {"file", t.source},
            {"bounds", t.bounds},
            {"rows", t.rows},
            {"cols", t.cols}};
  }
};

}  // namespace

nlohmann::json field_to_json(const Field& f) {
  nlohmann::json terms = nlohmann::json::array();
  for (const auto& term : f.surface.terms) terms.push_back(std::visit(TermToJson{}, term));
  double z_min = std::numeric_limits<double>::infinity(), z_max = -z_min;
  const int n = 100;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double z = f.height(f.bounds[0] + (f.bounds[1] - f.bounds[0]) * i / n,
                                f.bounds[2] + (f.bounds[3] - f.bounds[2]) * j / n);
      z_min = std::min(z_min, z);
      z_max = std::max(z_max, z);
    }
  nlohmann::json obstacles = nlohmann::json::array();
  for (const Obstacle& o : f.obstacles) {
    nlohmann::json j = {
        {"type", to_string(o.type)}, {"height", o.height}, {"restitution", o.restitution}};
    if (o.type == ObstacleType::kWall) {
      j["from"] = o.from, j["to"] = o.to, j["thickness"] = o.thickness;
    } else {
      j["center"] = o.center, j["size"] = o.size, j["yaw"] = o.yaw;
    }
    const Footprint fp = o.footprint();
    const double c = std::cos(fp.yaw), s = std::sin(fp.yaw);
    nlohmann::json corners = nlohmann::json::array();
    for (const auto& [u, v] : {std::pair{1, 1}, {-1, 1}, {-1, -1}, {1, -1}})
      corners.push_back({fp.center[0] + c * u * fp.half[0] - s * v * fp.half[1],
                         fp.center[1] + s * u * fp.half[0] + c * v * fp.half[1]});
    j["corners"] = corners;  // the footprint, counter-clockwise, for drawing
    obstacles.push_back(j);
  }
  return {
      {"name", f.name},
      {"description", f.description},
      {"source", f.source},
      {"bounds", f.bounds},
      {"cell_size", f.cell_size},
      {"tee", f.tee},
      {"hole", f.hole.position},
      {"hole_diameter", f.hole.diameter},
      {"hole_depth", f.hole.depth},
      {"ball_radius", f.ball.radius},
      {"ball_mass", f.ball.mass},
      {"rolling_resistance", f.rolling_resistance},
      {"sliding_friction", f.sliding_friction},
      {"borders",
       {{"height", f.borders.height},
        {"thickness", f.borders.thickness},
        {"restitution", f.borders.restitution}}},
      {"height_range", {z_min, z_max}},
      {"surface", terms},
      {"obstacles", obstacles},
  };
}

}  // namespace mg::field
