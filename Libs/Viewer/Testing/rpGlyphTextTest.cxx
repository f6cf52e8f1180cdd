// rp::GlyphText against VTK's own text renderer: a label laid out from glyphs rendered once is
// the picture vtkTextRenderer renders for the whole string (the corner texts of the three slice
// views, as a tool moves them), each character is rendered by FreeType only once, and a label is
// clipped to the picture.
#include <algorithm>
#include <cstdlib>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkStdString.h>
#include <vtkTextProperty.h>
#include <vtkTextRenderer.h>

#include "rpGlyphText.h"

namespace {

// `rgba` (a text picture from VTK, coverage in alpha) over black, as GlyphText::Draw blends.
std::vector<unsigned char> OverBlack(vtkImageData* image, const int size[2], int width, int height) {
  std::vector<unsigned char> picture(static_cast<size_t>(4 * width * height), 0);
  int dims[3];
  image->GetDimensions(dims);
  const auto* in = static_cast<const unsigned char*>(image->GetScalarPointer());
  for (int y = 0; y < std::min(size[1], height); ++y)
    for (int x = 0; x < std::min(size[0], width); ++x) {
      const unsigned char* p = in + 4 * (y * dims[0] + x);
      for (int c = 0; c < 3; ++c) picture[static_cast<size_t>(4 * (y * width + x) + c)] = static_cast<unsigned char>((p[c] * p[3] + 127) / 255);
    }
  return picture;
}

}  // namespace

TEST(GlyphText, LabelsAreTheStringsVTKRenders) {
  vtkNew<vtkTextProperty> style;
  style->SetFontSize(14);
  style->SetColor(0.95, 0.35, 0.3);
  rp::GlyphText glyphs;
  glyphs.SetStyle(style);
  vtkTextRenderer* renderer = vtkTextRenderer::GetInstance();
  ASSERT_NE(renderer, nullptr) << "no FreeType text renderer registered";
  for (const std::string text : {"Axial  S 12.3 mm", "Sagittal  L 56.1 mm", "Coronal  ~P 105.6 mm", "Axial  I 0.0 mm"}) {
    const int width = 200, height = 24;
    vtkNew<vtkImageData> image;
    int size[2];
    ASSERT_TRUE(renderer->RenderString(style, vtkStdString(text), image, size, 72));
    const auto expected = OverBlack(image, size, width, height);
    std::vector<unsigned char> ours(static_cast<size_t>(4 * width * height), 0);
    const int drawnWidth = glyphs.Draw(text, 0, 0, ours.data(), width, height);
    EXPECT_NEAR(drawnWidth, size[0], 1) << text;
    int inked = 0, far = 0;
    for (int p = 0; p < width * height; ++p) {
      int worst = 0;
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(int(ours[static_cast<size_t>(4 * p + c)]) - int(expected[static_cast<size_t>(4 * p + c)])));
      if (worst > 24) ++far;
      if (expected[static_cast<size_t>(4 * p)] > 64) ++inked;
    }
    EXPECT_GT(inked, 100) << text << ": VTK drew next to nothing";
    // Where two glyphs' ink overlaps the two blend in a different order: a handful of pixels.
    EXPECT_LE(far, inked / 50) << text << ": " << far << " pixels differ, of " << inked << " inked";
  }
  // Each distinct character once: the four labels above hold 27 of them.
  std::string all = "Axial  S 12.3 mmSagittal  L 56.1 mmCoronal  ~P 105.6 mmAxial  I 0.0 mm";
  std::sort(all.begin(), all.end());
  all.erase(std::unique(all.begin(), all.end()), all.end());
  EXPECT_LE(glyphs.GetNumberOfRenderedGlyphs(), static_cast<int>(all.size()));
  const int before = glyphs.GetNumberOfRenderedGlyphs();
  std::vector<unsigned char> again(4 * 200 * 24, 0);
  glyphs.Draw("Axial  S 21.3 mm", 0, 0, again.data(), 200, 24);
  EXPECT_EQ(glyphs.GetNumberOfRenderedGlyphs(), before) << "a new offset reuses the glyphs";
}

TEST(GlyphText, ALabelIsClippedToThePicture) {
  vtkNew<vtkTextProperty> style;
  style->SetFontSize(14);
  style->SetColor(1, 1, 1);
  rp::GlyphText glyphs;
  glyphs.SetStyle(style);
  // A 30 × 8 picture with a canary row beyond its end: a label at (20, 4) runs off both edges.
  std::vector<unsigned char> picture(4 * 30 * 9, 0);
  std::fill(picture.begin() + 4 * 30 * 8, picture.end(), 77);
  glyphs.Draw("Sagittal 88.8 mm", 20, 4, picture.data(), 30, 8);
  for (size_t i = 4 * 30 * 8; i < picture.size(); ++i) ASSERT_EQ(picture[i], 77) << "wrote past the picture";
  int inked = 0;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 30; ++x) {
      const unsigned char v = picture[static_cast<size_t>(4 * (y * 30 + x))];
      if (v) ++inked;
      if (x < 20 || y < 4) {
        EXPECT_EQ(v, 0) << "ink outside the label's place at " << x << ", " << y;
      }
    }
  EXPECT_GT(inked, 0);
}
