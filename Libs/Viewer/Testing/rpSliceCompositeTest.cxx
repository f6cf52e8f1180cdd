// rp::CompositeSlice against VTK's own way of making a slice picture (a vtkImageResliceToColors
// per layer and a vtkImageBlend), on the real knee CT and its real label map, through an oblique
// plane off the voxel grid: the CT as background (grey, air transparent), the same CT turned and
// shifted as a foreground at 40 % (a second volume through a registration), the labels at 60 %.
// And closed forms: trilinear sampling reproduces a linear volume, outside the volume (beyond
// half a voxel) is transparent, labels take the nearest voxel. And the copies with another axis
// fastest (rp::SliceLayoutCache) give the same bytes and follow the volume when it changes; 16-bit
// volumes sampled eight at a time (AVX2) give the values sampled one at a time do, signed and
// unsigned; the patient's rectangle of a picture (rp::OpaqueExtent) is the smallest one.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <vtkImageBlend.h>
#include <vtkImageData.h>
#include <vtkImageResliceToColors.h>
#include <vtkLookupTable.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkTransform.h>

#include "rpImagingReaders.h"
#include "rpSharedData.h"
#include "rpSliceComposite.h"
#include "rpViewerApplication.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"

namespace {

struct Table {
  std::vector<double> Rgba;  // entries × 4, in [0, 1]
  double Min = 0, Max = 1;
  int Size() const { return static_cast<int>(this->Rgba.size() / 4); }
  std::vector<std::uint32_t> Words() const {
    std::vector<std::uint32_t> words;
    for (int k = 0; k < this->Size(); ++k) {
      std::uint32_t w = 0;
      for (int c = 0; c < 4; ++c) w |= static_cast<std::uint32_t>(this->Rgba[static_cast<size_t>(4 * k + c)] * 255.0 + 0.5) << (8 * c);
      words.push_back(w);
    }
    return words;
  }
  vtkSmartPointer<vtkLookupTable> Vtk() const {
    auto table = vtkSmartPointer<vtkLookupTable>::New();
    table->SetNumberOfTableValues(this->Size());
    table->SetTableRange(this->Min, this->Max);
    for (int k = 0; k < this->Size(); ++k) {
      const double* c = &this->Rgba[static_cast<size_t>(4 * k)];
      table->SetTableValue(k, c[0], c[1], c[2], c[3]);
    }
    return table;
  }
};

// Grey over [lo, hi]; alpha 0 below `air` when asked (the background's patient mask).
Table GreyTable(double lo, double hi, double air, bool mask) {
  Table t;
  t.Min = std::min(lo, air - 1);
  t.Max = hi;
  const int n = 1024;
  for (int k = 0; k < n; ++k) {
    const double v = t.Min + (k + 0.5) * (t.Max - t.Min) / n;
    const double grey = std::clamp((v - lo) / (hi - lo), 0.0, 1.0);
    t.Rgba.insert(t.Rgba.end(), {grey, grey, grey, mask && v < air ? 0.0 : 1.0});
  }
  return t;
}

// Value v → grey v (of 255) for v in [0, 256).
Table IdentityGreyTable() {
  Table t;
  t.Min = 0;
  t.Max = 256;
  for (int k = 0; k < 256; ++k) t.Rgba.insert(t.Rgba.end(), {k / 255.0, k / 255.0, k / 255.0, 1.0});
  return t;
}

Table LabelTable() {
  Table t;
  t.Min = -0.5;
  t.Max = 3.5;
  t.Rgba = {0, 0, 0, 0, 0.9, 0.8, 0.5, 1, 0.3, 0.6, 0.9, 1, 0.9, 0.3, 0.3, 1};
  return t;
}

rp::SliceLayer Layer(vtkImageData* image, const vtkMatrix4x4* planeToIJK, double origin[2], double spacing,
                     const std::vector<std::uint32_t>& words, const Table& table, bool nearest, double opacity) {
  double rows[3][4];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) rows[r][c] = planeToIJK->GetElement(r, c);
  rp::SliceLayer l = rp::SliceLayerOf(image, rows, origin, spacing);
  l.Table = words.data();
  l.TableSize = static_cast<int>(words.size());
  l.TableMin = table.Min;
  l.TableScale = table.Size() / (table.Max - table.Min);
  l.Nearest = nearest;
  l.Opacity = opacity;
  return l;
}

vtkSmartPointer<vtkImageResliceToColors> VtkLayer(vtkImageData* image, vtkMatrix4x4* planeToIJK, double origin[2],
                                                  double spacing, int nx, int ny, vtkLookupTable* table, bool nearest) {
  auto reslice = vtkSmartPointer<vtkImageResliceToColors>::New();
  reslice->SetInputData(image);
  reslice->SetResliceAxes(planeToIJK);
  reslice->SetOutputDimensionality(2);
  reslice->SetOutputOrigin(origin[0], origin[1], 0);
  reslice->SetOutputSpacing(spacing, spacing, 1);
  reslice->SetOutputExtent(0, nx - 1, 0, ny - 1, 0, 0);
  reslice->SetLookupTable(table);
  reslice->SetOutputFormatToRGBA();
  reslice->SetBackgroundColor(0, 0, 0, 0);
  if (nearest) reslice->SetInterpolationModeToNearestNeighbor();
  else reslice->SetInterpolationModeToLinear();
  return reslice;
}

// The image's own index space with spacing 1 and origin 0 (the reslice axes map into IJK).
vtkSmartPointer<vtkImageData> InIndexSpace(vtkImageData* image) {
  auto copy = vtkSmartPointer<vtkImageData>::New();
  copy->ShallowCopy(image);
  copy->SetOrigin(0, 0, 0);
  copy->SetSpacing(1, 1, 1);
  copy->SetDirectionMatrix(1, 0, 0, 0, 1, 0, 0, 0, 1);
  return copy;
}

}  // namespace

TEST(SliceComposite, MatchesVTKsResliceToColorsAndBlendOnTheRealKneeCT) {
  RP_REQUIRE_SHARED_DATA("knee-ct-vhf/dicom");
  RP_REQUIRE_SHARED_DATA("knee-ct-vhf/labels.nrrd");
  ASSERT_TRUE(rp::RegisterImagingReaders());  // as the viewer module's Setup does
  vtkNew<vtkRPScene> scene;
  std::string error;
  ASSERT_TRUE(rp::LoadSceneOrDataFile(scene, rptest::SharedDataPath("knee-ct-vhf/dicom"), error)) << error;
  ASSERT_TRUE(rp::LoadSceneOrDataFile(scene, rptest::SharedDataPath("knee-ct-vhf/labels.nrrd"), error)) << error;
  auto* ct = vtkRPScalarVolumeNode::SafeDownCast(scene->GetNodesByClass("vtkRPScalarVolumeNode").at(0));
  ASSERT_NE(ct, nullptr);
  vtkImageData* labelsImage = nullptr;
  for (vtkRPNode* node : scene->GetNodesByClass("vtkRPSegmentationNode")) labelsImage = vtkRPSegmentationNode::SafeDownCast(node)->GetImageData();
  for (vtkRPNode* node : scene->GetNodesByClass("vtkRPScalarVolumeNode")) {
    if (node != ct && !labelsImage) labelsImage = vtkRPScalarVolumeNode::SafeDownCast(node)->GetImageData();
  }
  ASSERT_NE(labelsImage, nullptr) << "labels.nrrd did not load as a segmentation or a volume";
  auto image = InIndexSpace(ct->GetImageData());
  auto labels = InIndexSpace(labelsImage);
  int extent[6];
  image->GetExtent(extent);

  // An oblique plane through the middle, off the voxel grid (plane mm = voxels here: 1 mm CT).
  vtkNew<vtkTransform> plane;
  plane->Translate(0.5 * (extent[1] + extent[0]) + 0.37, 0.5 * (extent[3] + extent[2]) - 0.21,
                   0.5 * (extent[5] + extent[4]) + 0.43);
  plane->RotateX(23);
  plane->RotateY(-31);
  plane->RotateZ(12);
  vtkNew<vtkMatrix4x4> planeToIJK;
  planeToIJK->DeepCopy(plane->GetMatrix());
  // The foreground: the same CT seen through a registration (turned 8°, shifted 3.3 voxels).
  vtkNew<vtkTransform> registration;
  registration->Translate(3.3, -1.7, 2.1);
  registration->RotateWXYZ(8, 0.3, 0.9, 0.2);
  registration->Concatenate(plane->GetMatrix());
  vtkNew<vtkMatrix4x4> planeToForeground;
  planeToForeground->DeepCopy(registration->GetMatrix());

  double origin[2] = {-95.3, -88.7};
  const double spacing = 0.83;
  const int nx = 230, ny = 214;
  const Table background = GreyTable(-160, 240, -400, true), foreground = GreyTable(-1000, 1500, 0, false),
              segments = LabelTable();
  const auto bgWords = background.Words(), fgWords = foreground.Words(), labelWords = segments.Words();
  const rp::SliceLayer layers[3] = {
      Layer(image, planeToIJK, origin, spacing, bgWords, background, false, 1.0),
      Layer(image, planeToForeground, origin, spacing, fgWords, foreground, false, 0.4),
      Layer(labels, planeToIJK, origin, spacing, labelWords, segments, true, 0.6)};
  std::vector<std::uint32_t> ours(static_cast<size_t>(nx * ny), 0xDEADBEEFu);
  rp::CompositeSlice(layers, 3, nx, ny, ours.data());

  auto bgTable = background.Vtk(), fgTable = foreground.Vtk(), labelTable = segments.Vtk();
  auto r0 = VtkLayer(image, planeToIJK, origin, spacing, nx, ny, bgTable, false);
  auto r1 = VtkLayer(image, planeToForeground, origin, spacing, nx, ny, fgTable, false);
  auto r2 = VtkLayer(labels, planeToIJK, origin, spacing, nx, ny, labelTable, true);
  vtkNew<vtkImageBlend> blend;
  blend->SetBlendModeToNormal();
  blend->AddInputConnection(r0->GetOutputPort());
  blend->AddInputConnection(r1->GetOutputPort());
  blend->AddInputConnection(r2->GetOutputPort());
  blend->SetOpacity(1, 0.4);
  blend->SetOpacity(2, 0.6);
  blend->Update();
  vtkImageData* theirs = blend->GetOutput();
  ASSERT_EQ(theirs->GetNumberOfPoints(), nx * ny);
  ASSERT_EQ(theirs->GetNumberOfScalarComponents(), 4);
  const auto* expected = static_cast<const unsigned char*>(theirs->GetScalarPointer());

  // Both interpolate in floating point and blend in 8 bits, in a different order: a grey level
  // apart at most here. Where a sample falls right on the half-voxel border the two could decide
  // differently, so a few pixels in a thousand may differ more.
  int close = 0, patient = 0, labelled = 0, worst = 0;
  for (int p = 0; p < nx * ny; ++p) {
    const auto* e = expected + 4 * p;
    const std::uint32_t o = ours[static_cast<size_t>(p)];
    int diff = 0;
    for (int c = 0; c < 4; ++c) diff = std::max(diff, std::abs(int((o >> (8 * c)) & 0xFF) - int(e[c])));
    worst = std::max(worst, diff);
    if (diff <= 2) ++close;
    if (e[3] == 255) ++patient;
    if (std::abs(int(e[0]) - int(e[2])) > 20) ++labelled;  // the label colours are not grey
  }
  // The picture holds patient, air and labelled bone (the test would be empty otherwise).
  EXPECT_GT(patient, nx * ny / 5);
  EXPECT_LT(patient, nx * ny * 9 / 10);
  EXPECT_GT(labelled, 500);
  EXPECT_GE(close, nx * ny * 998 / 1000) << "worst difference " << worst << " grey levels";

  // The same picture from the copies with another axis fastest (SliceLayoutCache): the same
  // voxels, the same arithmetic, so the same bytes. A sagittal plane has its rows along j.
  vtkNew<vtkMatrix4x4> sagittal;
  sagittal->Zero();
  sagittal->SetElement(1, 0, 1);  // picture x → j
  sagittal->SetElement(2, 1, 1);  // picture y → k
  sagittal->SetElement(0, 2, 1);
  sagittal->SetElement(0, 3, 0.5 * (extent[1] + extent[0]) + 0.3);
  sagittal->SetElement(3, 3, 1);
  double sagittalOrigin[2] = {-3.2, -2.6};
  for (vtkMatrix4x4* axes : {planeToIJK.GetPointer(), sagittal.GetPointer()}) {
    rp::SliceLayer direct[3] = {Layer(image, axes, sagittalOrigin, 0.9, bgWords, background, false, 1.0),
                                Layer(image, planeToForeground, sagittalOrigin, 0.9, fgWords, foreground, false, 0.4),
                                Layer(labels, axes, sagittalOrigin, 0.9, labelWords, segments, true, 0.6)};
    rp::SliceLayer copied[3] = {direct[0], direct[1], direct[2]};
    rp::SliceLayoutCache cache;
    cache.Apply(image, copied[0]);
    cache.Apply(image, copied[1]);
    cache.Apply(labels, copied[2]);
    if (axes == sagittal.GetPointer()) {
      EXPECT_NE(copied[0].Scalars, direct[0].Scalars) << "a sagittal picture reads a copy with j fastest";
      EXPECT_EQ(copied[0].Increments[1], 1);
    }
    const int w = 170, h = 160;
    std::vector<std::uint32_t> a(static_cast<size_t>(w * h)), b(static_cast<size_t>(w * h));
    rp::CompositeSlice(direct, 3, w, h, a.data());
    rp::CompositeSlice(copied, 3, w, h, b.data());
    EXPECT_EQ(a, b);
    int shown = 0;
    for (std::uint32_t p : a) shown += (p >> 24) == 255;
    EXPECT_GT(shown, w * h / 5);
  }
}

TEST(SliceComposite, EightSamplesAtATimeGiveTheSameValuesAsOneAtATime) {
  // The 16-bit volumes' samples taken eight at a time (AVX2, where the CPU has it) and one at a
  // time: the same operations in the same order, so the same values. A table of 1/64 HU steps,
  // each entry its own colour, turns any difference in a sample into a different pixel.
  RP_REQUIRE_SHARED_DATA("knee-ct-vhf/dicom");
  ASSERT_TRUE(rp::RegisterImagingReaders());  // as the viewer module's Setup does
  vtkNew<vtkRPScene> scene;
  std::string error;
  ASSERT_TRUE(rp::LoadSceneOrDataFile(scene, rptest::SharedDataPath("knee-ct-vhf/dicom"), error)) << error;
  auto* ct = vtkRPScalarVolumeNode::SafeDownCast(scene->GetNodesByClass("vtkRPScalarVolumeNode").at(0));
  ASSERT_NE(ct, nullptr);
  auto signedImage = InIndexSpace(ct->GetImageData());
  ASSERT_EQ(signedImage->GetScalarType(), VTK_SHORT) << signedImage->GetScalarTypeAsString();
  // The same CT as unsigned 16 bits, shifted by 32768 so that tissue and bone have the top bit
  // set (as an unsigned MR's bright values do): read as signed they would come out negative.
  vtkNew<vtkImageData> unsignedImage;
  unsignedImage->CopyStructure(signedImage);
  unsignedImage->AllocateScalars(VTK_UNSIGNED_SHORT, 1);
  {
    const auto* from = static_cast<const short*>(signedImage->GetScalarPointer());
    auto* to = static_cast<unsigned short*>(unsignedImage->GetScalarPointer());
    for (vtkIdType n = 0; n < signedImage->GetNumberOfPoints(); ++n) to[n] = static_cast<unsigned short>(from[n] + 32768);
  }
  int extent[6];
  signedImage->GetExtent(extent);
  std::vector<std::uint32_t> words(static_cast<size_t>(64 * 5000));
  for (size_t k = 0; k < words.size(); ++k) words[k] = static_cast<std::uint32_t>(k * 2654435761u) | 0xFF000000u;

  vtkNew<vtkTransform> oblique;
  oblique->Translate(0.5 * (extent[1] + extent[0]) + 0.37, 0.5 * (extent[3] + extent[2]) - 0.21,
                     0.5 * (extent[5] + extent[4]) + 0.43);
  oblique->RotateX(23);
  oblique->RotateY(-31);
  vtkNew<vtkMatrix4x4> axial, sagittal;
  axial->SetElement(2, 3, 0.5 * (extent[5] + extent[4]) + 0.3);
  sagittal->Zero();
  sagittal->SetElement(1, 0, 1);
  sagittal->SetElement(2, 1, 1);
  sagittal->SetElement(0, 2, 1);
  sagittal->SetElement(0, 3, 0.5 * (extent[1] + extent[0]) + 0.3);
  sagittal->SetElement(3, 3, 1);
  double origin[2] = {-95.3, -88.7};
  for (vtkImageData* image : {signedImage.GetPointer(), static_cast<vtkImageData*>(unsignedImage)})
  for (const vtkMatrix4x4* axes : {oblique->GetMatrix(), axial.GetPointer(), sagittal.GetPointer()}) {
    double rows[3][4];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) rows[r][c] = axes->GetElement(r, c);
    rp::SliceLayer layer = rp::SliceLayerOf(image, rows, origin, 0.83);
    layer.Table = words.data();
    layer.TableSize = static_cast<int>(words.size());
    layer.TableMin = image == signedImage.GetPointer() ? -1100 : 32768 - 1100;
    layer.TableScale = 64;
    rp::SliceLayoutCache cache;
    cache.Apply(image, layer);  // the sagittal plane reads a copy with j fastest
    const int w = 250, h = 230;
    std::vector<std::uint32_t> one(static_cast<size_t>(w * h)), eight(static_cast<size_t>(w * h));
    rp::SetCompositeVectorized(false);
    rp::CompositeSlice(&layer, 1, w, h, one.data());
    rp::SetCompositeVectorized(true);
    rp::CompositeSlice(&layer, 1, w, h, eight.data());
    EXPECT_EQ(one, eight);
    std::vector<std::uint32_t> distinct(one);
    std::sort(distinct.begin(), distinct.end());
    EXPECT_GT(std::unique(distinct.begin(), distinct.end()) - distinct.begin(), 5000) << "the picture is all one colour";
  }
}

TEST(SliceComposite, TheLayoutCopyFollowsTheVolume) {
  // A 6×5×4 short volume, a picture along j (so the cache copies): change a voxel, mark the
  // image modified, and the picture through that voxel changes.
  vtkNew<vtkImageData> image;
  image->SetExtent(0, 5, 0, 4, 0, 3);
  image->AllocateScalars(VTK_SHORT, 1);
  std::fill_n(static_cast<short*>(image->GetScalarPointer()), 120, short(10));
  const Table grey = IdentityGreyTable();
  const auto words = grey.Words();
  vtkNew<vtkMatrix4x4> axes;  // picture (x, y) → IJK (2, x, y)
  axes->Zero();
  axes->SetElement(1, 0, 1);
  axes->SetElement(2, 1, 1);
  axes->SetElement(0, 3, 2);
  axes->SetElement(3, 3, 1);
  double origin[2] = {0, 0};
  rp::SliceLayoutCache cache;
  std::vector<std::uint32_t> picture(5 * 4);
  auto render = [&]() {
    rp::SliceLayer layer = Layer(image, axes, origin, 1.0, words, grey, false, 1.0);
    cache.Apply(image, layer);
    EXPECT_EQ(layer.Increments[1], 1) << "the copy has j fastest";
    rp::CompositeSlice(&layer, 1, 5, 4, picture.data());
    return picture[static_cast<size_t>(2 * 5 + 3)] & 0xFF;  // pixel (3, 2) = voxel (2, 3, 2)
  };
  EXPECT_EQ(render(), 10u);
  *static_cast<short*>(image->GetScalarPointer(2, 3, 2)) = 200;
  image->Modified();
  EXPECT_EQ(render(), 200u);
}

TEST(SliceComposite, TrilinearSamplingReproducesALinearVolume) {
  // v(i, j, k) = 2i + 3j + 5k on a 20×16×12 float grid: trilinear interpolation is exact, so a
  // picture through any plane inside is the plane's own values (table: value → grey value).
  vtkNew<vtkImageData> image;
  image->SetExtent(0, 19, 0, 15, 0, 11);
  image->AllocateScalars(VTK_FLOAT, 1);
  for (int k = 0; k < 12; ++k)
    for (int j = 0; j < 16; ++j)
      for (int i = 0; i < 20; ++i) *static_cast<float*>(image->GetScalarPointer(i, j, k)) = float(2 * i + 3 * j + 5 * k);
  const Table grey = IdentityGreyTable();
  const auto words = grey.Words();
  vtkNew<vtkTransform> plane;
  plane->Translate(9.3, 7.6, 5.45);
  plane->RotateZ(30);
  plane->RotateX(15);
  vtkNew<vtkMatrix4x4> planeToIJK;
  planeToIJK->DeepCopy(plane->GetMatrix());
  double origin[2] = {-6, -4};
  const double spacing = 0.5;
  const int nx = 25, ny = 17;
  const rp::SliceLayer layer = Layer(image, planeToIJK, origin, spacing, words, grey, false, 1.0);
  std::vector<std::uint32_t> picture(static_cast<size_t>(nx * ny));
  rp::CompositeSlice(&layer, 1, nx, ny, picture.data());
  int inside = 0;
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      const double in[4] = {origin[0] + x * spacing, origin[1] + y * spacing, 0, 1};
      double ijk[4];
      planeToIJK->MultiplyPoint(in, ijk);
      const std::uint32_t pixel = picture[static_cast<size_t>(y * nx + x)];
      const bool within = ijk[0] >= -0.5 && ijk[0] <= 19.5 && ijk[1] >= -0.5 && ijk[1] <= 15.5 && ijk[2] >= -0.5 && ijk[2] <= 11.5;
      if (!within) {
        EXPECT_EQ(pixel, 0u) << "outside the volume must be transparent at " << x << ", " << y;
        continue;
      }
      const bool interior = ijk[0] >= 0 && ijk[0] <= 19 && ijk[1] >= 0 && ijk[1] <= 15 && ijk[2] >= 0 && ijk[2] <= 11;
      if (!interior) continue;  // the half-voxel border repeats the edge voxel (clamped), not the ramp
      ++inside;
      const double value = 2 * ijk[0] + 3 * ijk[1] + 5 * ijk[2];
      // The table's entry is floor(value); a value a rounding below an integer may take the one below.
      EXPECT_NEAR(int(pixel & 0xFF), std::clamp(int(std::floor(value)), 0, 255), 1) << "at " << x << ", " << y;
      EXPECT_EQ(pixel >> 24, 255u);
    }
  EXPECT_GT(inside, 100);
}

TEST(SliceComposite, LabelsTakeTheNearestVoxelAndBlendWithTheirOpacity) {
  // Labels 1 where i < 5, else 2, on a 10×4×3 grid; the picture samples the row j = 1.4, k = 0.6
  // (nearest: j = 1, k = 1) at i = 0.2, 0.7, ..., and blends at 50 % over a black background.
  vtkNew<vtkImageData> labels;
  labels->SetExtent(0, 9, 0, 3, 0, 2);
  labels->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 10; ++i) *static_cast<unsigned char*>(labels->GetScalarPointer(i, j, k)) = i < 5 ? 1 : 2;
  vtkNew<vtkImageData> zero;
  zero->SetExtent(0, 9, 0, 3, 0, 2);
  zero->AllocateScalars(VTK_SHORT, 1);
  std::fill_n(static_cast<short*>(zero->GetScalarPointer()), 120, short(0));
  Table black;
  black.Min = -1;
  black.Max = 1;
  black.Rgba = {0, 0, 0, 1, 0, 0, 0, 1};
  Table colours = LabelTable();
  const auto blackWords = black.Words(), labelWords = colours.Words();
  vtkNew<vtkMatrix4x4> planeToIJK;
  planeToIJK->SetElement(1, 3, 1.4);
  planeToIJK->SetElement(2, 3, 0.6);
  double origin[2] = {0.2, 0};
  const rp::SliceLayer layers[2] = {Layer(zero, planeToIJK, origin, 0.5, blackWords, black, false, 1.0),
                                    Layer(labels, planeToIJK, origin, 0.5, labelWords, colours, true, 0.5)};
  const int nx = 19;  // i up to 9.2, inside
  std::vector<std::uint32_t> picture(nx);
  rp::CompositeSlice(layers, 2, nx, 1, picture.data());
  for (int x = 0; x < nx; ++x) {
    const double i = 0.2 + 0.5 * x;
    const int label = i < 4.5 ? 1 : 2;
    const std::uint32_t colour = labelWords[static_cast<size_t>(label)];
    for (int c = 0; c < 3; ++c) {
      const int expected = int(((colour >> (8 * c)) & 0xFF) * 128 + 128) >> 8;  // half over black
      EXPECT_NEAR(int((picture[static_cast<size_t>(x)] >> (8 * c)) & 0xFF), expected, 1) << "x " << x << " channel " << c;
    }
    EXPECT_EQ(picture[static_cast<size_t>(x)] >> 24, 255u) << "the background's alpha stays";
  }
}

TEST(SliceComposite, TheOpaqueExtentIsTheSmallestRectangleAroundThePatient) {
  // A 9 × 7 picture of air with patient pixels at (2, 1), (6, 4) and (3, 5): x 2…6, y 1…5. The
  // 3D view's quad spans these pixels only (a software rasterizer pays for the air it cuts away).
  const int w = 9, h = 7;
  std::vector<std::uint32_t> picture(w * h, 0x00FFFFFFu);  // white air: alpha 0 decides
  int extent[4] = {-1, -1, -1, -1};
  EXPECT_FALSE(rp::OpaqueExtent(picture.data(), w, h, extent));
  picture[1 * w + 2] = 0xFF000000u;
  picture[4 * w + 6] = 0x01000000u;  // any alpha but 0 is patient
  picture[5 * w + 3] = 0xFF102030u;
  ASSERT_TRUE(rp::OpaqueExtent(picture.data(), w, h, extent));
  EXPECT_EQ(extent[0], 2);
  EXPECT_EQ(extent[1], 6);
  EXPECT_EQ(extent[2], 1);
  EXPECT_EQ(extent[3], 5);
  picture[6 * w + 8] = 0xFF000000u;  // the far corner
  picture[0] = 0xFF000000u;          // the first pixel
  ASSERT_TRUE(rp::OpaqueExtent(picture.data(), w, h, extent));
  EXPECT_EQ(extent[0], 0);
  EXPECT_EQ(extent[1], 8);
  EXPECT_EQ(extent[2], 0);
  EXPECT_EQ(extent[3], 6);
}
