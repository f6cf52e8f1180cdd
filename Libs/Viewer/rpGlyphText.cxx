#include "rpGlyphText.h"

#include <algorithm>
#include <cmath>

#include <vtkImageData.h>
#include <vtkPointData.h>
#include <vtkStdString.h>
#include <vtkTextProperty.h>
#include <vtkTextRenderer.h>
#include <vtkUnsignedCharArray.h>

namespace rp {

GlyphText::GlyphText() = default;
GlyphText::~GlyphText() = default;

void GlyphText::SetStyle(vtkTextProperty* style) {
  this->Style->ShallowCopy(style);
  this->Style->SetJustificationToLeft();
  this->Style->SetVerticalJustificationToBottom();
  this->Style->SetOrientation(0);
  for (Glyph& glyph : this->Glyphs) glyph = Glyph{};
}

const GlyphText::Glyph& GlyphText::Get(unsigned char c) {
  Glyph& glyph = this->Glyphs[c];
  if (glyph.Ready) return glyph;
  glyph.Ready = true;  // a character FreeType cannot render stays empty (drawn as nothing)
  vtkTextRenderer* renderer = vtkTextRenderer::GetInstance();
  if (!renderer) return glyph;
  // 72 dpi: the size a vtkTextActor draws the font at in a window of VTK's default DPI.
  // The advance: twenty of the character laid out by VTK, less one, over nineteen (a space
  // has an advance and nothing to draw).
  const std::string one(1, static_cast<char>(c)), twenty(20, static_cast<char>(c));
  int box1[4], box20[4];
  if (renderer->GetBoundingBox(this->Style, vtkStdString(one), box1, 72) &&
      renderer->GetBoundingBox(this->Style, vtkStdString(twenty), box20, 72)) {
    glyph.Advance = static_cast<int>(std::lround(((box20[1] - box20[0]) - (box1[1] - box1[0])) / 19.0));
  }
  vtkNew<vtkImageData> image;
  int size[2] = {0, 0};
  if (!renderer->RenderString(this->Style, vtkStdString(one), image, size, 72)) return glyph;
  ++this->Rendered;
  auto* scalars = vtkUnsignedCharArray::SafeDownCast(image->GetPointData()->GetScalars());
  int dims[3];
  image->GetDimensions(dims);
  if (!scalars || scalars->GetNumberOfComponents() != 4) return glyph;
  glyph.Width = std::min(size[0], dims[0]);
  glyph.Height = std::min(size[1], dims[1]);
  glyph.Stride = dims[0];
  glyph.Rgba.assign(scalars->GetPointer(0), scalars->GetPointer(0) + 4 * static_cast<size_t>(dims[0]) * dims[1]);
  return glyph;
}

int GlyphText::Draw(const std::string& text, int x, int y, unsigned char* picture, int width, int height) {
  int pen = x;
  for (char ch : text) {
    const Glyph& glyph = this->Get(static_cast<unsigned char>(ch));
    for (int row = 0; row < glyph.Height; ++row) {
      const int ty = y + row;
      if (ty < 0 || ty >= height) continue;
      for (int column = 0; column < glyph.Width; ++column) {
        const int tx = pen + column;
        if (tx < 0 || tx >= width) continue;
        const unsigned char* in = &glyph.Rgba[4 * (static_cast<size_t>(row) * glyph.Stride + column)];
        const unsigned a = in[3];
        if (a == 0) continue;
        unsigned char* out = picture + 4 * (static_cast<size_t>(ty) * width + tx);
        for (int c = 0; c < 3; ++c) out[c] = static_cast<unsigned char>((in[c] * a + out[c] * (255 - a) + 127) / 255);
      }
    }
    pen += glyph.Advance;
  }
  return pen - x;
}

}  // namespace rp
