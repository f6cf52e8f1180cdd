#pragma once
// A short label that changes every frame (a slice view's offset while a tool moves the slice),
// drawn from glyphs that VTK's text renderer (FreeType) renders once per character: laying out
// a label is a copy of a few hundred pixels. A vtkTextActor instead renders the whole string
// with FreeType and uploads it as a new texture every time it changes (0.5–0.6 ms a slice view
// on llvmpipe, about as much as the rest of the view's overlays together).
//
// Layout as VTK's own: each glyph's picture is as tall as the font's line and starts at the pen;
// the pen moves by the character's advance (hinted, whole pixels; measured once as VTK lays out
// twenty of the character), so the label is the string vtkTextRenderer would render. A glyph's
// ink may reach past its advance ('A'), which is why the two are kept apart.
#include <array>
#include <string>
#include <vector>

#include <vtkNew.h>

class vtkTextProperty;

namespace rp {

class GlyphText {
 public:
  GlyphText();
  ~GlyphText();
  GlyphText(const GlyphText&) = delete;
  GlyphText& operator=(const GlyphText&) = delete;

  /// Font, size and colour of `style` (copied: later changes to it are not seen until the next
  /// call, which forgets the glyphs rendered so far).
  void SetStyle(vtkTextProperty* style);
  /// Draws `text` over an RGBA picture (width × height, rows from the bottom) with its lower-left
  /// corner at pixel (x, y): each glyph's colour weighted by its coverage, clipped to the picture.
  /// Returns the label's width in pixels.
  int Draw(const std::string& text, int x, int y, unsigned char* picture, int width, int height);
  /// Times FreeType rendered a glyph (tests: once per character and style).
  int GetNumberOfRenderedGlyphs() const { return this->Rendered; }

 private:
  struct Glyph {
    bool Ready = false;
    int Width = 0, Height = 0, Stride = 0;  // the glyph's box; Stride: pixels per row of Rgba
    int Advance = 0;                        // how far the pen moves after it
    std::vector<unsigned char> Rgba;
  };
  const Glyph& Get(unsigned char c);

  vtkNew<vtkTextProperty> Style;
  std::array<Glyph, 256> Glyphs;
  int Rendered = 0;
};

}  // namespace rp
