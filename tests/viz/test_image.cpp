#include <gtest/gtest.h>

#include <unistd.h>

#include "core/error.hpp"
#include "viz/image.hpp"
#include "viz_test_util.hpp"

namespace mg::viz {
namespace {

TEST(Image, PngRoundTripKeepsEveryPixel) {
  Image a(37, 21);
  for (std::size_t i = 0; i < a.rgb.size(); ++i)
    a.rgb[i] = static_cast<std::uint8_t>((i * 7919) % 256);
  const auto path = testing::temp_dir("png") / "a.png";
  write_png(path, a);
  const Image b = read_png(path);
  EXPECT_EQ(b.width, 37);
  EXPECT_EQ(b.height, 21);
  EXPECT_EQ(a.rgb, b.rgb);
  EXPECT_EQ(mean_abs_difference(a, b), 0.0);
}

TEST(Image, FilmstripPlacesFramesSideBySide) {
  Image red(4, 3), blue(4, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x) {
      red.pixel(x, y)[0] = 255;
      blue.pixel(x, y)[2] = 255;
    }
  const Image s = filmstrip({red, blue}, 2, 128);
  ASSERT_EQ(s.width, 10);
  ASSERT_EQ(s.height, 3);
  EXPECT_EQ(s.pixel(3, 1)[0], 255);
  EXPECT_EQ(s.pixel(4, 1)[0], 128);  // the gap
  EXPECT_EQ(s.pixel(6, 2)[2], 255);
  EXPECT_EQ(s.pixel(6, 2)[0], 0);
  EXPECT_THROW(filmstrip({red, Image(5, 3)}), InputError);
  EXPECT_THROW(filmstrip({}), InputError);
}

TEST(Image, UnreadablePngIsAnIoError) {
  const auto path = testing::temp_dir("png") / "bad.png";
  {
    std::FILE* f = std::fopen(path.c_str(), "w");
    std::fputs("not a png", f);
    std::fclose(f);
  }
  EXPECT_THROW(read_png(path), IoError);
  EXPECT_THROW(read_png(path.parent_path() / "missing.png"), IoError);
}

}  // namespace
}  // namespace mg::viz
