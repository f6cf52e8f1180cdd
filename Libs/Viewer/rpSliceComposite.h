#pragma once
// A slice node's picture in one pass (what Slicer's layer logics and VTK's
// vtkImageResliceToColors + vtkImageBlend do in one filter per layer and a blend): for each
// picture pixel, each layer's volume is sampled where the pixel lies (trilinear, or nearest for
// labels), mapped through the layer's colour table, and blended over the layers below with the
// layer's opacity. The first layer's alpha is the picture's (the patient mask). No allocation, in
// parallel over rows; the picture is small (the volume's resolution), a few thousand rows' worth
// of samples a frame, so what counts is the cost per sample, not the pipeline around it. So each
// row is split where it enters and leaves a volume: the samples in between need no clamps or
// tests, and 16-bit volumes are sampled there eight at a time where the CPU has AVX2 (the same
// values as one at a time); only the few near the edges take the careful path.
#include <cstdint>
#include <vector>

#include <vtkType.h>

class vtkImageData;

namespace rp {

/// One layer: a scalar volume (its first component), where the picture's pixels fall in it and
/// its colours.
struct SliceLayer {
  const void* Scalars = nullptr;  ///< the voxel at `Extent`'s first corner
  int ScalarType = 0;             ///< VTK_SHORT, VTK_FLOAT, ...
  int Extent[6] = {0, -1, 0, -1, 0, -1};
  vtkIdType Increments[3] = {0, 0, 0};  ///< in scalars, between neighbours along i, j, k
  /// Picture pixel (x, y) → continuous voxel index (IJK, as `Extent`): IJK = PixelToIJK · (x, y, 1).
  double PixelToIJK[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 0}};
  /// Nearest voxel (labels: never blend two labels) instead of trilinear.
  bool Nearest = false;
  /// Colour table, RGBA8 words (little-endian R first): a value v maps to entry
  /// (v − TableMin) · TableScale, clamped to the table (as vtkLookupTable does).
  const std::uint32_t* Table = nullptr;
  int TableSize = 0;
  double TableMin = 0, TableScale = 1;
  /// How much of this layer shows over the ones below (ignored for the first).
  double Opacity = 1;
};

/// A layer sampling `image`'s voxels (their first component; no colours yet) for a picture whose
/// pixel (x, y) lies at plane point (origin + spacing · (x, y), 0); `planeToIJK` maps plane
/// coordinates to the image's continuous voxel index (rows of a 4×4, the last left out). Scalars
/// stays null for an image without scalars.
SliceLayer SliceLayerOf(vtkImageData* image, const double planeToIJK[3][4], const double origin[2], double spacing);

/// Fills `picture` (width × height RGBA8 words, rows from the bottom) with the layers, the first
/// at the bottom. Outside a volume (beyond half a voxel of its edge voxels' centres, as
/// vtkImageReslice's border) a layer is transparent; the first layer's transparency is the
/// picture's. In parallel over rows (vtkSMPTools) unless `parallel` is false: VTK 9.1's
/// vtkSMPTools may be entered by one thread at a time, so a worker thread composites alone.
void CompositeSlice(const SliceLayer* layers, int count, int width, int height, std::uint32_t* picture,
                    bool parallel = true);

/// Whether CompositeSlice may sample 16-bit volumes eight samples at a time where the CPU has
/// AVX2 (on by default). The two ways give the same pixels; tests and benchmarks compare them.
void SetCompositeVectorized(bool vectorized);

/// The smallest pixel rectangle holding every pixel of `picture` (width × height RGBA8 words, as
/// CompositeSlice makes it) whose alpha is not 0 (patient, not air): extent = {x first, x last,
/// y first, y last}. False when there is none.
bool OpaqueExtent(const std::uint32_t* picture, int width, int height, int extent[4]);

/// Copies of volumes with another axis fastest in memory. A picture row steps along the plane's
/// first axis; through a CT stored axially, a sagittal row steps across the CT's rows, and each
/// sample reads new cache lines (twice the time of an axial picture). Apply() points a layer at
/// a copy whose fastest axis is the one its rows step along most (when that is not i), made once
/// and kept until the image changes.
class SliceLayoutCache {
 public:
  /// `layer` is filled from `image` (its own layout); this may repoint Scalars and Increments.
  void Apply(vtkImageData* image, SliceLayer& layer);
  /// Drops the copies of images not in `images` (those no longer drawn).
  void Keep(const std::vector<const vtkImageData*>& images);

 private:
  struct Copy {
    const vtkImageData* Image = nullptr;
    vtkMTimeType Time = 0;
    int Axis = 0;
    std::vector<unsigned char> Bytes;
    vtkIdType Increments[3] = {0, 0, 0};
  };
  std::vector<Copy> Copies;
};

}  // namespace rp
