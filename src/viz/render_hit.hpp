#pragma once
/// `minigolf render`: one hit of the console session (lockstep), recorded pose by pose by a
/// session observer, then drawn off-screen: a video (MP4 through ffmpeg, or a PNG sequence where
/// ffmpeg is missing) and a filmstrip of the hit's stages (thesis figure 4.2): rest,
/// acceleration, impact, braking, idle.
///
/// The session steps exactly as `minigolf console` does; the observer copies poses (const), and
/// drawing happens after the run in the renderer's own mjData, so rendering cannot change the
/// simulation (tests/viz compares the outcome bits with and without it).
#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "control/module_config.hpp"
#include "system/session.hpp"
#include "viz/image.hpp"
#include "viz/renderer.hpp"

namespace mg::viz {

/// Where a hit was: the session's poses at the video's frame times and at every step of the hit
/// and the braking, the stage poses, and the outcome.
struct HitRecording {
  std::vector<Pose> frames;  ///< one per 1/fps of simulated time, from the start
  struct Stage {
    std::string name;
    Pose pose;
  };
  std::vector<Stage> stages;  ///< rest, acceleration, impact, braking, idle (those reached)
  std::optional<sim::PuttOutcome> outcome;
  std::array<double, 2> hole{0.0, 0.0};
  double angle = 0.0, speed = 0.0;
  std::string log;                               ///< the session's output
  std::vector<std::array<double, 3>> ball_path;  ///< [m] every 10 ms from the impact on
  std::vector<double> ball_path_time;            ///< [s] of each ball_path point
};

struct HitRequest {
  std::optional<std::array<double, 2>> hole;  ///< default: the field's
  std::optional<double> angle, speed;         ///< both, or a parameter model
  std::string params_model;                   ///< `auto` from this model
  double fps = 30.0;
  double after_outcome = 0.5;  ///< [s] kept after the ball's outcome is decided
  double max_time = 40.0;      ///< [s] give up
};

/// InputError for an incomplete or contradictory request (fps, angle/speed/model).
void validate(const HitRequest& request);

/// Runs the session in lockstep and records the hit. `record_poses` false: the same run without
/// an observer (for the bit-identity test). Throws InputError for a bad request (envelope,
/// hole), Error if the hit never happened.
HitRecording record_hit(const control::ModuleConfig& config, const HitRequest& request,
                        bool record_poses = true);

struct RenderOptions {
  std::string camera = "overview";
  int width = 640, height = 480;
  double fps = 30.0;
  bool video = true;  ///< false: the filmstrip only
};

struct RenderOutputs {
  std::filesystem::path video;      ///< the MP4, or the folder of PNG frames
  std::filesystem::path filmstrip;  ///< PNG
  int frames = 0;
  bool used_ffmpeg = false;
};

/// Draws the recording: `out` is the stem (OUT.mp4 or OUT-frames/, OUT-filmstrip.png).
/// Needs a current OpenGL context (GlWindow).
RenderOutputs render_hit(const sim::World& world, const HitRecording& recording,
                         const RenderOptions& options, const std::filesystem::path& out);

/// IoError unless the outputs of stem `out` can be written: its folder exists, and OUT.mp4 and
/// OUT-filmstrip.png are regular files or absent (never replaced when they are something else).
void check_render_outputs(const std::filesystem::path& out);

/// ffmpeg on the PATH, or empty.
std::filesystem::path find_ffmpeg();

struct VideoOutput {
  std::filesystem::path path;  ///< the MP4, or the folder of PNG frames
  int frames = 0;
  bool used_ffmpeg = false;
};

/// Writes `count` frames of `width` x `height` pixels, `frame(k)` drawing the k-th: OUT.mp4
/// (H.264 through ffmpeg, frames piped as raw RGB, written to OUT.tmp.mp4 and renamed) or, where
/// ffmpeg is not on the PATH, OUT-frames/frame-NNNNN.png. `out` is the stem. IoError if ffmpeg
/// fails; Error if a frame has another size.
VideoOutput write_video(const std::filesystem::path& out, int width, int height, double fps,
                        int count, const std::function<Image(int)>& frame);

}  // namespace mg::viz
