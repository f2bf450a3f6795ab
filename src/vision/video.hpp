#pragma once
/// A camera's recorded footage as a video file (`vision-cam --video`): read frame by frame with
/// OpenCV's VideoCapture (its FFmpeg backend: MJPG in AVI, H.264 in MP4, ...) in the video plugin,
/// loaded on first use (video_plugin.hpp). The same pipeline as rendered frames or PNG pairs reads
/// the images.
#include <memory>
#include <string>

#include "viz/image.hpp"

namespace mg::vision {

class VideoReader {
 public:
  /// Opens `path`. Throws IoError (one line naming it) when it is missing or cannot be decoded, or
  /// when the video plugin cannot be loaded.
  explicit VideoReader(const std::string& path);
  ~VideoReader();
  VideoReader(const VideoReader&) = delete;
  VideoReader& operator=(const VideoReader&) = delete;

  /// The next frame as 8-bit RGB into `image`; false at the end of the footage.
  bool read(viz::Image& image);
  const std::string& path() const { return path_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string path_;
};

}  // namespace mg::vision
