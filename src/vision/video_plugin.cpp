// The video plugin: OpenCV's VideoCapture behind the C interface of video_plugin.hpp.
#include "vision/video_plugin.hpp"

#include <exception>

#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

namespace {

struct Video {
  cv::VideoCapture capture;
  cv::Mat bgr, rgb;
};

}  // namespace

extern "C" {

int mg_video_plugin_version(void) { return MG_VIDEO_PLUGIN_VERSION; }

void* mg_video_open(const char* path) {
  try {
    auto video = new Video;
    if (video->capture.open(path, cv::CAP_FFMPEG) && video->capture.isOpened()) return video;
    delete video;
  } catch (const std::exception&) {  // no exception crosses the C interface
  }
  return nullptr;
}

int mg_video_read(void* handle, int* width, int* height, const std::uint8_t** rgb) {
  auto* video = static_cast<Video*>(handle);
  try {
    if (!video->capture.read(video->bgr) || video->bgr.empty()) return 0;
    if (video->bgr.type() != CV_8UC3) return -1;
    cv::cvtColor(video->bgr, video->rgb, cv::COLOR_BGR2RGB);
    if (!video->rgb.isContinuous()) video->rgb = video->rgb.clone();
  } catch (const std::exception&) {
    return 0;  // a decoding failure ends the footage, as VideoCapture::read's false does
  }
  *width = video->rgb.cols;
  *height = video->rgb.rows;
  *rgb = video->rgb.ptr<std::uint8_t>(0);
  return 1;
}

void mg_video_close(void* handle) { delete static_cast<Video*>(handle); }
}
