#include "field/surface.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <png.h>

#include "core/error.hpp"

namespace mg::field {
namespace {

// Every analytic term's gradient against central finite differences (an independent route).
TEST(Surface, GradientMatchesFiniteDifferences) {
  Surface s;
  s.terms.push_back(PlaneTerm{0.1, 0.04, -0.02});
  s.terms.push_back(BumpTerm{{0.8, 0.2}, 0.035, {0.14, 0.12}});
  s.terms.push_back(HillTerm{{1.6, 0.0}, {0.8, 0.6}, 0.06, 0.5});
  s.terms.push_back(ArctanTerm{{1.2, 0.0}, 0.03, 3.0, 4.0});
  const double h = 1e-6;
  for (double x = -0.2; x < 2.6; x += 0.13)
    for (double y = -0.5; y < 0.5; y += 0.11) {
      const auto g = s.gradient(x, y);
      const double fx = (s.height(x + h, y) - s.height(x - h, y)) / (2 * h);
      const double fy = (s.height(x, y + h) - s.height(x, y - h)) / (2 * h);
      EXPECT_NEAR(g[0], fx, 1e-6) << x << "," << y;
      EXPECT_NEAR(g[1], fy, 1e-6) << x << "," << y;
    }
}

// The level pad: gradient vs finite differences over the whole blend ring and beyond, on a
// surface as steep at the pad as the arctan field's tee, with terms before and after it.
TEST(Surface, FlattenGradientMatchesFiniteDifferences) {
  Surface s;
  s.terms.push_back(ArctanTerm{{1.2, 0.0}, 0.03, 3.0, 4.0});
  s.terms.push_back(PlaneTerm{0.0, 0.04, 0.0});
  s.terms.push_back(FlattenTerm{{0.0, 0.0}, 0.03, 0.1});
  s.terms.push_back(BumpTerm{{0.8, 0.2}, 0.035, {0.14, 0.12}});  // after the pad: unchanged
  const double h = 1e-6;
  int in_ring = 0;
  for (double x = -0.137; x < 0.14; x += 0.0093)
    for (double y = -0.131; y < 0.14; y += 0.0089) {
      const auto g = s.gradient(x, y);
      const double fx = (s.height(x + h, y) - s.height(x - h, y)) / (2 * h);
      const double fy = (s.height(x, y + h) - s.height(x, y - h)) / (2 * h);
      EXPECT_NEAR(g[0], fx, 1e-7) << x << "," << y;
      EXPECT_NEAR(g[1], fy, 1e-7) << x << "," << y;
      const double r = std::hypot(x, y);
      in_ring += r > 0.03 && r < 0.1;
    }
  EXPECT_GT(in_ring, 200);
}

TEST(Surface, FlattenLevelsTheTermsBeforeItAndBlendsC1) {
  const ArctanTerm saddle{{1.2, 0.0}, 0.03, 3.0, 4.0};
  const FlattenTerm pad{{0.0, 0.0}, 0.03, 0.1};
  const Surface raw{{saddle}};
  const Surface padded{{saddle, pad, PlaneTerm{0.01, 0.0, 0.0}}};
  const double z0 = raw.height(0.0, 0.0) + 0.01;
  // Level inside the radius: the height of the pad centre, no slope.
  for (double a = 0.0; a < 6.3; a += 0.5) {
    const double x = 0.029 * std::cos(a), y = 0.029 * std::sin(a);
    EXPECT_NEAR(padded.height(x, y), z0, 1e-15);
    EXPECT_EQ(padded.gradient(x, y)[0], 0.0);
    EXPECT_EQ(padded.gradient(x, y)[1], 0.0);
    // Unchanged from the blend radius on.
    const double X = 0.1 * std::cos(a), Y = 0.1 * std::sin(a);
    EXPECT_NEAR(padded.height(X, Y), raw.height(X, Y) + 0.01, 1e-15);
    EXPECT_NEAR(padded.gradient(X, Y)[1], raw.gradient(X, Y)[1], 1e-15);
  }
  // C1: no jump in height or slope across either edge of the blend ring.
  for (double r0 : {0.03, 0.1}) {
    const double e = 1e-7;
    const auto gi = padded.gradient(0.0, r0 - e), go = padded.gradient(0.0, r0 + e);
    EXPECT_NEAR(padded.height(0.0, r0 - e), padded.height(0.0, r0 + e), 1e-6) << r0;  // slope * 2e
    EXPECT_NEAR(gi[0], go[0], 1e-5) << r0;
    EXPECT_NEAR(gi[1], go[1], 1e-5) << r0;
  }
  // The ring is at most 2.5 times as steep as the slope it replaces.
  double steepest = 0.0, raw_steepest = 0.0;
  for (double r = 0.0; r < 0.1; r += 0.001)
    for (double a = 0.0; a < 6.3; a += 0.1) {
      const auto g = padded.gradient(r * std::cos(a), r * std::sin(a));
      const auto gr = raw.gradient(r * std::cos(a), r * std::sin(a));
      steepest = std::max(steepest, std::hypot(g[0], g[1]));
      raw_steepest = std::max(raw_steepest, std::hypot(gr[0], gr[1]));
    }
  EXPECT_LT(steepest, 2.5 * raw_steepest);
}

TEST(Surface, TermsHaveTheirDocumentedShape) {
  const Surface plane{{PlaneTerm{0.0, 0.1, 0.0}}};
  EXPECT_DOUBLE_EQ(plane.height(2.0, 5.0), 0.2);
  const Surface bump{{BumpTerm{{1.0, 0.0}, 0.05, {0.1, 0.1}}}};
  EXPECT_DOUBLE_EQ(bump.height(1.0, 0.0), 0.05);
  EXPECT_NEAR(bump.height(1.1, 0.0), 0.05 * std::exp(-0.5), 1e-15);
  const Surface hill{{HillTerm{{1.6, 0.0}, {1.0, 0.0}, 0.06, 0.5}}};
  EXPECT_DOUBLE_EQ(hill.height(1.6, 0.3), 0.06);
  EXPECT_DOUBLE_EQ(hill.height(2.2, 0.0), 0.0);
  EXPECT_NEAR(hill.height(1.85, 0.0), 0.03, 1e-12);
  const Surface arctan{{ArctanTerm{{1.0, 0.0}, 0.03, 3.0, 4.0}}};
  EXPECT_NEAR(arctan.height(2.0, 0.25), 0.03 * std::atan(3.0) * std::atan(1.0), 1e-15);
  EXPECT_DOUBLE_EQ(arctan.height(1.0, 0.4), 0.0);
}

TEST(Surface, CsvHeightmapInterpolatesBilinearly) {
  const auto path = std::filesystem::temp_directory_path() / "mg_heightmap.csv";
  std::ofstream(path) << "0,0.1\n0.2,0.3\n";
  const Surface s{{load_heightmap(path.string(), {0, 1, 0, 1}, 0, 0)}};
  EXPECT_NEAR(s.height(0.0, 0.0), 0.0, 1e-15);
  EXPECT_NEAR(s.height(1.0, 0.0), 0.1, 1e-15);
  EXPECT_NEAR(s.height(0.0, 1.0), 0.2, 1e-15);
  EXPECT_NEAR(s.height(0.5, 0.5), 0.15, 1e-15);
  EXPECT_NEAR(s.gradient(0.5, 0.5)[0], 0.1, 1e-12);
  std::filesystem::remove(path);
}

TEST(Surface, PngHeightmapScalesGreyLevels) {
  const auto path = std::filesystem::temp_directory_path() / "mg_heightmap.png";
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = 2;
  image.height = 2;
  image.format = PNG_FORMAT_GRAY;
  const png_byte pixels[4] = {255, 255, 0, 0};  // top row (y_max) white, bottom row black
  ASSERT_TRUE(png_image_write_to_file(&image, path.c_str(), 0, pixels, 0, nullptr));
  const Surface s{{load_heightmap(path.string(), {0, 1, 0, 1}, -0.1, 0.1)}};
  EXPECT_NEAR(s.height(0.5, 0.0), -0.1, 1e-12);
  EXPECT_NEAR(s.height(0.5, 1.0), 0.1, 1e-12);
  std::filesystem::remove(path);
}

TEST(Surface, BadHeightmapsAreErrors) {
  EXPECT_THROW(load_heightmap("/nonexistent/map.png", {0, 1, 0, 1}, 0, 1), IoError);
  const auto txt = std::filesystem::temp_directory_path() / "mg_heightmap.txt";
  std::ofstream(txt) << "1,2\n";
  EXPECT_THROW(load_heightmap(txt.string(), {0, 1, 0, 1}, 0, 1), InputError);
  const auto fake_png = std::filesystem::temp_directory_path() / "mg_fake.png";
  std::ofstream(fake_png) << "not a png";
  EXPECT_THROW(load_heightmap(fake_png.string(), {0, 1, 0, 1}, 0, 1), InputError);
  const auto bad_csv = std::filesystem::temp_directory_path() / "mg_bad.csv";
  std::ofstream(bad_csv) << "0,1\n2,nan\n";
  EXPECT_THROW(load_heightmap(bad_csv.string(), {0, 1, 0, 1}, 0, 1), InputError);
  for (const auto& p : {txt, fake_png, bad_csv}) std::filesystem::remove(p);
}

}  // namespace
}  // namespace mg::field
