#include "vision/video.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <vector>

#include <fmt/format.h>

#include "core/error.hpp"
#include "vision/video_plugin.hpp"

namespace mg::vision {
namespace {

// The plugin's functions, loaded once per process and never unloaded (FFmpeg's threads and
// OpenCV's static state may outlive a reader).
struct Plugin {
  decltype(&mg_video_open) open = nullptr;
  decltype(&mg_video_read) read = nullptr;
  decltype(&mg_video_close) close = nullptr;
  std::string error;  // why it did not load: one line
};

template <typename F>
F symbol(void* lib, const char* name) {
  return reinterpret_cast<F>(::dlsym(lib, name));
}

// Loads `path`; false with `error` set when it is not a usable plugin.
bool load(const std::filesystem::path& path, Plugin& p, std::string& error) {
  void* lib = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!lib) {
    const char* why = ::dlerror();
    error = fmt::format("the video plugin {} cannot be loaded: {}", path.string(),
                        why ? why : "unknown error");
    return false;
  }
  const auto version = symbol<decltype(&mg_video_plugin_version)>(lib, "mg_video_plugin_version");
  p.open = symbol<decltype(&mg_video_open)>(lib, "mg_video_open");
  p.read = symbol<decltype(&mg_video_read)>(lib, "mg_video_read");
  p.close = symbol<decltype(&mg_video_close)>(lib, "mg_video_close");
  if (!version || !p.open || !p.read || !p.close || version() != MG_VIDEO_PLUGIN_VERSION) {
    error = fmt::format("the video plugin {} is not version {} of minigolf's", path.string(),
                        MG_VIDEO_PLUGIN_VERSION);
    ::dlclose(lib);
    return false;
  }
  return true;
}

// In order: $MINIGOLF_VIDEO_PLUGIN; beside the executable (the build tree's
// src/cli/minigolf -> src/vision/, an install's bin/minigolf -> lib/minigolf/); the build tree
// and the install location recorded at build time (a program other than minigolf: Python, tests).
const Plugin& plugin() {
  static const Plugin loaded = [] {
    Plugin p;
    const std::string file = MINIGOLF_VIDEO_PLUGIN_FILE;
    if (const char* env = std::getenv("MINIGOLF_VIDEO_PLUGIN"); env && *env) {
      if (!load(env, p, p.error)) p.error += " (MINIGOLF_VIDEO_PLUGIN)";
      return p;
    }
    std::vector<std::filesystem::path> candidates;
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) {
      candidates.push_back(exe.parent_path() / ".." / "vision" / file);
      candidates.push_back(exe.parent_path() / ".." / MINIGOLF_VIDEO_PLUGIN_LIBDIR / file);
    }
    candidates.emplace_back(MINIGOLF_VIDEO_PLUGIN_BUILD);
    candidates.emplace_back(MINIGOLF_VIDEO_PLUGIN_INSTALLED);
    std::string first_error;  // of a plugin found that did not load
    for (const auto& c : candidates) {
      if (!std::filesystem::is_regular_file(c, ec)) continue;
      std::string error;
      if (load(c.lexically_normal(), p, error)) return p;
      if (first_error.empty()) first_error = error;
    }
    p.error =
        !first_error.empty()
            ? first_error
            : fmt::format("the video plugin {} was not found (set MINIGOLF_VIDEO_PLUGIN)", file);
    return p;
  }();
  return loaded;
}

}  // namespace

struct VideoReader::Impl {
  const Plugin* plugin = nullptr;
  void* handle = nullptr;
};

VideoReader::VideoReader(const std::string& path) : impl_(std::make_unique<Impl>()), path_(path) {
  const Plugin& p = plugin();
  if (!p.open) throw IoError("--video: " + p.error);
  impl_->plugin = &p;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw IoError(fmt::format("--video: '{}': no such file", path));
  impl_->handle = p.open(path.c_str());
  if (!impl_->handle)
    throw IoError(fmt::format("--video: '{}': cannot be read as a video (OpenCV/FFmpeg)", path));
}

VideoReader::~VideoReader() {
  if (impl_->handle) impl_->plugin->close(impl_->handle);
}

bool VideoReader::read(viz::Image& image) {
  int width = 0, height = 0;
  const std::uint8_t* rgb = nullptr;
  const int got = impl_->plugin->read(impl_->handle, &width, &height, &rgb);
  if (got < 0) throw IoError(fmt::format("--video: '{}': expected 8-bit colour frames", path_));
  if (got == 0) return false;
  image.width = width;
  image.height = height;
  image.rgb.assign(rgb, rgb + static_cast<std::size_t>(width) * height * 3);
  return true;
}

}  // namespace mg::vision
