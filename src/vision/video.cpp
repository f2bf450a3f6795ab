#include "vision/video.hpp"

#include <filesystem>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "core/error.hpp"

namespace mg::vision {

struct VideoReader::Impl {
  cv::VideoCapture capture;
  cv::Mat bgr, rgb;
};

VideoReader::VideoReader(const std::string& path) : impl_(std::make_unique<Impl>()), path_(path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw IoError(fmt::format("--video: '{}': no such file", path));
  if (!impl_->capture.open(path, cv::CAP_FFMPEG) || !impl_->capture.isOpened())
    throw IoError(fmt::format("--video: '{}': cannot be read as a video (OpenCV/FFmpeg)", path));
}

VideoReader::~VideoReader() = default;

bool VideoReader::read(viz::Image& image) {
  if (!impl_->capture.read(impl_->bgr) || impl_->bgr.empty()) return false;
  if (impl_->bgr.type() != CV_8UC3)
    throw IoError(fmt::format("--video: '{}': expected 8-bit colour frames", path_));
  cv::cvtColor(impl_->bgr, impl_->rgb, cv::COLOR_BGR2RGB);
  image.width = impl_->rgb.cols;
  image.height = impl_->rgb.rows;
  image.rgb.resize(static_cast<std::size_t>(image.width) * image.height * 3);
  for (int y = 0; y < image.height; ++y)
    std::copy_n(impl_->rgb.ptr<std::uint8_t>(y), image.width * 3,
                image.rgb.data() + static_cast<std::size_t>(y) * image.width * 3);
  return true;
}

}  // namespace mg::vision
