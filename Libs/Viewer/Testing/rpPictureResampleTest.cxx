// rp::ResampleOpaqueRGBA against closed forms: bilinear interpolation reproduces a linear ramp
// exactly (to the rounding of 8-bit weights), an identity map copies, pixels beyond half a
// pixel of the picture are black, the edge pixel's colour fills the half pixel, the fast
// axis-aligned path agrees with the general one, and a turned map turns the picture.
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "rpPictureResample.h"

namespace {

// RGBA picture whose red is 10·x + 3·y, green 5·y, blue 200 − 7·x, alpha 77 (ignored).
std::vector<unsigned char> Ramp(int width, int height) {
  std::vector<unsigned char> rgba(static_cast<size_t>(4 * width * height));
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      unsigned char* p = &rgba[static_cast<size_t>(4 * (y * width + x))];
      p[0] = static_cast<unsigned char>(10 * x + 3 * y);
      p[1] = static_cast<unsigned char>(5 * y);
      p[2] = static_cast<unsigned char>(200 - 7 * x);
      p[3] = 77;
    }
  return rgba;
}

const unsigned char* Pixel(const std::vector<unsigned char>& rgba, int width, int i, int j) {
  return &rgba[static_cast<size_t>(4 * (j * width + i))];
}

}  // namespace

TEST(PictureResample, IdentityCopiesTheColoursAndMakesThemOpaque) {
  const auto source = Ramp(7, 5);
  std::vector<unsigned char> target(4 * 7 * 5, 1);
  rp::ResampleOpaqueRGBA(source.data(), 7, 5, rp::PixelMap{}, target.data(), 7, 5);
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 7; ++i) {
      const unsigned char* in = Pixel(source, 7, i, j);
      const unsigned char* out = Pixel(target, 7, i, j);
      EXPECT_EQ(out[0], in[0]);
      EXPECT_EQ(out[1], in[1]);
      EXPECT_EQ(out[2], in[2]);
      EXPECT_EQ(out[3], 255);
    }
}

TEST(PictureResample, MagnifiedRampIsTheRampAtEachPixelCentre) {
  // 3× magnified and shifted: target (i, j) samples u = 0.2 + i/3, v = 0.1 + j/3.
  const int w = 12, h = 9, tw = 30, th = 21;
  const auto source = Ramp(w, h);
  rp::PixelMap map;
  map.Origin[0] = 0.2;
  map.Origin[1] = 0.1;
  map.AlongI[0] = 1.0 / 3.0;
  map.AlongJ[1] = 1.0 / 3.0;
  std::vector<unsigned char> target(static_cast<size_t>(4 * tw * th));
  rp::ResampleOpaqueRGBA(source.data(), w, h, map, target.data(), tw, th);
  for (int j = 0; j < th; ++j)
    for (int i = 0; i < tw; ++i) {
      const double u = 0.2 + i / 3.0, v = 0.1 + j / 3.0;
      const unsigned char* out = Pixel(target, tw, i, j);
      EXPECT_NEAR(out[0], 10 * u + 3 * v, 1.01) << i << "," << j;
      EXPECT_NEAR(out[1], 5 * v, 1.01);
      EXPECT_NEAR(out[2], 200 - 7 * u, 1.01);
      EXPECT_EQ(out[3], 255);
    }
}

TEST(PictureResample, BeyondHalfAPixelIsBlackWithinItTheEdgeColour) {
  const auto source = Ramp(4, 4);
  rp::PixelMap map;
  map.Origin[0] = -0.9;  // target column 0 at u = −0.9 (outside), column 1 at −0.4 (edge half pixel)
  map.AlongI[0] = 0.5;
  map.Origin[1] = 1.0;
  std::vector<unsigned char> target(4 * 12 * 2);
  rp::ResampleOpaqueRGBA(source.data(), 4, 4, map, target.data(), 12, 2);
  const unsigned char* outside = Pixel(target, 12, 0, 0);
  EXPECT_EQ(outside[0], 0);
  EXPECT_EQ(outside[1], 0);
  EXPECT_EQ(outside[2], 0);
  EXPECT_EQ(outside[3], 255);
  const unsigned char* edge = Pixel(target, 12, 1, 0);  // u = −0.4 → column 0's colour
  const unsigned char* first = Pixel(source, 4, 0, 1);
  EXPECT_EQ(edge[0], first[0]);
  EXPECT_EQ(edge[2], first[2]);
  // u = 3.6 > 3.5: black again (column 9); u = 3.1 (column 8): the last column's colour.
  EXPECT_EQ(Pixel(target, 12, 9, 0)[2], 0);
  EXPECT_EQ(Pixel(target, 12, 8, 0)[2], Pixel(source, 4, 3, 1)[2]);
  // Rows beyond the picture are black.
  map.Origin[1] = 4.0;
  rp::ResampleOpaqueRGBA(source.data(), 4, 4, map, target.data(), 12, 2);
  for (int i = 0; i < 12; ++i) EXPECT_EQ(Pixel(target, 12, i, 0)[0] + Pixel(target, 12, i, 0)[2], 0);
}

TEST(PictureResample, TheAxisAlignedPathAgreesWithTheGeneralOne) {
  const int w = 64, h = 48, tw = 90, th = 70;
  std::vector<unsigned char> source(static_cast<size_t>(4 * w * h));
  std::mt19937 random(7);
  for (auto& c : source) c = static_cast<unsigned char>(random() & 0xFF);
  rp::PixelMap aligned;
  aligned.Origin[0] = -3.3;
  aligned.Origin[1] = -2.1;
  aligned.AlongI[0] = 0.77;
  aligned.AlongJ[1] = 0.71;
  rp::PixelMap general = aligned;
  general.AlongI[1] = 1e-6;  // takes the general path; the same map to 1e-4 pixel
  std::vector<unsigned char> a(static_cast<size_t>(4 * tw * th)), b(a.size());
  rp::ResampleOpaqueRGBA(source.data(), w, h, aligned, a.data(), tw, th);
  rp::ResampleOpaqueRGBA(source.data(), w, h, general, b.data(), tw, th);
  // Each path is within a grey level of the exact interpolation (8-bit weights, rounding), so
  // on random full-contrast colours the two may differ by two, never more.
  int worst = 0;
  for (size_t k = 0; k < a.size(); ++k) worst = std::max(worst, std::abs(int(a[k]) - int(b[k])));
  EXPECT_LE(worst, 2);
}

TEST(PictureResample, ATurnedMapTurnsThePicture) {
  // Target (i, j) samples (u, v) = (j, 4 − i): the picture turned a quarter.
  const auto source = Ramp(6, 5);
  rp::PixelMap map;
  map.Origin[0] = 0;
  map.Origin[1] = 4;
  map.AlongI[0] = 0;
  map.AlongI[1] = -1;
  map.AlongJ[0] = 1;
  map.AlongJ[1] = 0;
  std::vector<unsigned char> target(4 * 5 * 6);
  rp::ResampleOpaqueRGBA(source.data(), 6, 5, map, target.data(), 5, 6);
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 5; ++i) {
      EXPECT_EQ(Pixel(target, 5, i, j)[0], Pixel(source, 6, j, 4 - i)[0]);
      EXPECT_EQ(Pixel(target, 5, i, j)[1], Pixel(source, 6, j, 4 - i)[1]);
    }
}
