#pragma once
/// The C interface of the video plugin (libminigolf_video.so, video_plugin.cpp), loaded at run
/// time by video.cpp: OpenCV's videoio pulls in FFmpeg, GStreamer and a hundred more libraries,
/// which every `minigolf` process would otherwise load at start (0.3 s).
#include <cstddef>
#include <cstdint>

extern "C" {

/// Bumped when a function below changes; the loader refuses a plugin of another version.
#define MG_VIDEO_PLUGIN_VERSION 1

int mg_video_plugin_version(void);
/// Opens `path` (FFmpeg backend); null on failure.
void* mg_video_open(const char* path);
/// The next frame as 8-bit RGB, rows packed, in a buffer owned by the handle (valid until the
/// next call): 1 read, 0 at the end, -1 when the frames are not 8-bit colour.
int mg_video_read(void* handle, int* width, int* height, const std::uint8_t** rgb);
void mg_video_close(void* handle);
}
