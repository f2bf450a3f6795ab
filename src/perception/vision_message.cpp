#include "perception/vision_message.hpp"

#include <cmath>
#include <optional>

#include <nlohmann/json.hpp>

#include "core/json_io.hpp"

namespace mg::perception {
namespace {

bool read_point(const nlohmann::json& j, const char* key, std::array<double, 3>& out,
                VisionError& error) {
  const auto it = j.find(key);
  if (it == j.end() || !it->is_array() || it->size() != 3) {
    error = VisionError::kMalformed;
    return false;
  }
  for (std::size_t i = 0; i < 3; ++i) {
    if (!(*it)[i].is_number()) {
      error = VisionError::kMalformed;
      return false;
    }
    out[i] = (*it)[i].get<double>();
    if (!std::isfinite(out[i])) {
      error = VisionError::kNotFinite;
      return false;
    }
  }
  return true;
}

bool inside(const std::array<double, 3>& p, const VisionLimits& l) {
  return p[0] >= l.bounds[0] && p[0] <= l.bounds[1] && p[1] >= l.bounds[2] && p[1] <= l.bounds[3] &&
         p[2] >= l.z_min && p[2] <= l.z_max;
}

}  // namespace

VisionParse parse_vision_message(std::string_view datagram, const VisionLimits& limits) {
  VisionParse r;
  if (datagram.size() > kMaxVisionMessageBytes) {
    r.error = VisionError::kTooLong;
    return r;
  }
  // Parse without exceptions: malformed JSON, a key given twice ("format" twice) and a NUL byte
  // (nlohmann would stop there: a valid message followed by "\0garbage") are malformed. (JSON
  // has no NaN or infinity literals, so those arrive as malformed text or as huge numbers caught
  // below.)
  const std::optional<nlohmann::json> parsed = try_parse_json(datagram);
  if (!parsed || !parsed->is_object()) {
    r.error = VisionError::kMalformed;
    return r;
  }
  const nlohmann::json& j = *parsed;
  const auto format = j.find("format");
  if (format == j.end() || !format->is_string() || format->get<std::string>() != kVisionFormat) {
    r.error = VisionError::kWrongFormat;
    return r;
  }
  const auto seq = j.find("seq");
  const auto stamp = j.find("stamp");
  if (seq == j.end() || !seq->is_number_unsigned() || stamp == j.end() || !stamp->is_number()) {
    r.error = VisionError::kMalformed;
    return r;
  }
  r.message.seq = seq->get<std::uint64_t>();
  if (r.message.seq > kMaxVisionSeq) {  // a sender must not be able to outrun every later seq
    r.error = VisionError::kOutOfRange;
    return r;
  }
  r.message.stamp = stamp->get<double>();
  if (!std::isfinite(r.message.stamp)) {
    r.error = VisionError::kNotFinite;
    return r;
  }
  if (!read_point(j, "ball", r.message.ball, r.error) ||
      !read_point(j, "hole", r.message.hole, r.error))
    return r;
  if (!inside(r.message.ball, limits) || !inside(r.message.hole, limits))
    r.error = VisionError::kOutOfRange;
  return r;
}

std::string format_vision_message(const VisionMessage& m) {
  const nlohmann::json j = {{"format", kVisionFormat},
                            {"seq", m.seq},
                            {"stamp", m.stamp},
                            {"ball", m.ball},
                            {"hole", m.hole}};
  return j.dump();
}

std::string_view to_string(VisionError error) {
  switch (error) {
    case VisionError::kNone:
      return "ok";
    case VisionError::kTooLong:
      return "too long";
    case VisionError::kMalformed:
      return "malformed";
    case VisionError::kWrongFormat:
      return "wrong format tag";
    case VisionError::kNotFinite:
      return "not finite";
    case VisionError::kOutOfRange:
      return "out of range";
  }
  return "?";
}

}  // namespace mg::perception
