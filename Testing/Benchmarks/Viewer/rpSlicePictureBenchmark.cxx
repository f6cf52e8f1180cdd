// A slice node's picture, our one pass (rp::CompositeSlice on the row-ordered copies of
// rp::SliceLayoutCache) against VTK's way (a vtkImageResliceToColors per layer and a
// vtkImageBlend), in the same run, on the real knee CT (../shared/data/knee-ct-vhf): the CT as
// background (grey, air transparent), the CT through a turned and shifted registration as a 40 %
// foreground (a second volume through an oblique transform, as the demo's MR), the bone labels
// at 60 %. Axial, coronal, sagittal and oblique planes at 1 mm pixels, the plane stepped off the
// voxel grid every iteration (as a tool moves it). rpSliceCompositeTest holds the two to the same
// pixels. Figures: slice-picture.csv and slice-picture.png (ms per picture) in
// $ROBOPLAN_BENCHMARK_OUTPUT (the chart on a private Xvfb where there is no display).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include <vtkImageBlend.h>
#include <vtkImageData.h>
#include <vtkImageResliceToColors.h>
#include <vtkLookupTable.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkSmartPointer.h>
#include <vtkTransform.h>

#include "rpBenchmarkChart.h"
#include "rpBenchmarkMain.h"
#include "rpImagingReaders.h"
#include "rpSliceComposite.h"
#include "rpViewerApplication.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"

namespace {

const char* const Planes[] = {"axial", "coronal", "sagittal", "oblique"};

struct Case {
  vtkSmartPointer<vtkImageData> CT, Labels;  // in index space (origin 0, spacing 1)
  vtkNew<vtkLookupTable> Background, Foreground, Segments;
  std::vector<std::uint32_t> BackgroundWords, ForegroundWords, SegmentWords;
  std::string Error;

  bool Load() {
    const std::string data = std::string(ROBOPLAN_SHARED_DATA_DIR) + "/knee-ct-vhf";
    rp::RegisterImagingReaders();  // the DICOM folder through the loader (rpImagingReaders.h)
    vtkNew<vtkRPScene> scene;
    if (!rp::LoadSceneOrDataFile(scene, data + "/dicom", this->Error) ||
        !rp::LoadSceneOrDataFile(scene, data + "/labels.nrrd", this->Error)) {
      return false;
    }
    auto volumes = scene->GetNodesByClass("vtkRPScalarVolumeNode");
    auto segmentations = scene->GetNodesByClass("vtkRPSegmentationNode");
    if (volumes.empty()) return (this->Error = "no CT in " + data), false;
    vtkImageData* labels = !segmentations.empty() ? vtkRPSegmentationNode::SafeDownCast(segmentations[0])->GetImageData()
                           : volumes.size() > 1   ? vtkRPScalarVolumeNode::SafeDownCast(volumes[1])->GetImageData()
                                                  : nullptr;
    if (!labels) return (this->Error = "labels.nrrd did not load"), false;
    this->CT = IndexSpace(vtkRPScalarVolumeNode::SafeDownCast(volumes[0])->GetImageData());
    this->Labels = IndexSpace(labels);
    // Tables as vtkRPSliceLogic makes them: grey over the window, air transparent in the background.
    Grey(this->Background, -160, 240, -400);
    Grey(this->Foreground, -1000, 1500, -1e9);
    this->Segments->SetNumberOfTableValues(4);
    this->Segments->SetTableRange(-0.5, 3.5);
    this->Segments->SetTableValue(0, 0, 0, 0, 0);
    this->Segments->SetTableValue(1, 0.9, 0.8, 0.5, 1);
    this->Segments->SetTableValue(2, 0.3, 0.6, 0.9, 1);
    this->Segments->SetTableValue(3, 0.9, 0.3, 0.3, 1);
    this->BackgroundWords = Words(this->Background);
    this->ForegroundWords = Words(this->Foreground);
    this->SegmentWords = Words(this->Segments);
    return true;
  }

  static vtkSmartPointer<vtkImageData> IndexSpace(vtkImageData* image) {
    auto copy = vtkSmartPointer<vtkImageData>::New();
    copy->ShallowCopy(image);
    copy->SetOrigin(0, 0, 0);
    copy->SetSpacing(1, 1, 1);
    copy->SetDirectionMatrix(1, 0, 0, 0, 1, 0, 0, 0, 1);
    return copy;
  }
  static void Grey(vtkLookupTable* table, double lo, double hi, double air) {
    const int n = 1024;
    const double first = std::min(lo, air), last = hi;
    table->SetNumberOfTableValues(n);
    table->SetTableRange(first, last);
    for (int k = 0; k < n; ++k) {
      const double v = first + (k + 0.5) * (last - first) / n;
      const double g = std::clamp((v - lo) / (hi - lo), 0.0, 1.0);
      table->SetTableValue(k, g, g, g, v < air ? 0.0 : 1.0);
    }
  }
  // The table's own bytes (what vtkImageResliceToColors maps through), as RGBA8 words.
  static std::vector<std::uint32_t> Words(vtkLookupTable* table) {
    std::vector<std::uint32_t> words(static_cast<size_t>(table->GetNumberOfTableValues()));
    for (vtkIdType k = 0; k < table->GetNumberOfTableValues(); ++k) {
      const unsigned char* c = table->GetPointer(k);
      words[static_cast<size_t>(k)] = c[0] | c[1] << 8 | c[2] << 16 | std::uint32_t(c[3]) << 24;
    }
    return words;
  }
};

Case* TheCase() {
  static Case* c = [] {
    auto* loaded = new Case;
    if (!loaded->Load()) std::cerr << "[slice-picture-bench] " << loaded->Error << "\n";
    return loaded;
  }();
  return c;
}

// Plane → IJK for the named plane through the middle, `step` mm along its normal (off the grid).
void PlaneToIJK(vtkImageData* image, int plane, double step, vtkMatrix4x4* axes, vtkMatrix4x4* registered) {
  int e[6];
  image->GetExtent(e);
  vtkNew<vtkTransform> t;
  t->Translate(0.5 * (e[0] + e[1]), 0.5 * (e[2] + e[3]), 0.5 * (e[4] + e[5]));
  if (plane == 1) t->RotateX(90);
  if (plane == 2) t->RotateY(90), t->RotateZ(90);
  if (plane == 3) t->RotateX(23), t->RotateY(-31), t->RotateZ(12);
  t->Translate(0, 0, step);
  axes->DeepCopy(t->GetMatrix());
  vtkNew<vtkTransform> r;
  r->Translate(3.3, -1.7, 2.1);
  r->RotateWXYZ(8, 0.3, 0.9, 0.2);
  r->Concatenate(t->GetMatrix());
  registered->DeepCopy(r->GetMatrix());
}

constexpr int Side = 200;  // pixels a side at 1 mm: the crop's planes and the air around them
constexpr double Origin[2] = {-100, -100};
std::map<std::string, std::map<std::string, double>> Figures;  // method → plane → ms per picture

void BM_SlicePicture_VTK(benchmark::State& state) {
  Case* c = TheCase();
  if (!c->CT) return state.SkipWithError(c->Error.c_str());
  const int plane = static_cast<int>(state.range(0));
  vtkNew<vtkMatrix4x4> axes, registered;
  std::vector<vtkSmartPointer<vtkImageResliceToColors>> layers;
  vtkNew<vtkImageBlend> blend;
  blend->SetBlendModeToNormal();
  const std::pair<vtkImageData*, vtkLookupTable*> inputs[3] = {
      {c->CT, c->Background}, {c->CT, c->Foreground}, {c->Labels, c->Segments}};
  for (int l = 0; l < 3; ++l) {
    auto reslice = vtkSmartPointer<vtkImageResliceToColors>::New();
    reslice->SetInputData(inputs[l].first);
    reslice->SetResliceAxes(l == 1 ? registered.GetPointer() : axes.GetPointer());
    reslice->SetOutputDimensionality(2);
    reslice->SetOutputOrigin(Origin[0], Origin[1], 0);
    reslice->SetOutputSpacing(1, 1, 1);
    reslice->SetOutputExtent(0, Side - 1, 0, Side - 1, 0, 0);
    reslice->SetLookupTable(inputs[l].second);
    reslice->SetOutputFormatToRGBA();
    reslice->SetBackgroundColor(0, 0, 0, 0);
    if (l == 2) reslice->SetInterpolationModeToNearestNeighbor();
    else reslice->SetInterpolationModeToLinear();
    blend->AddInputConnection(reslice->GetOutputPort());
    layers.push_back(reslice);
  }
  blend->SetOpacity(1, 0.4);
  blend->SetOpacity(2, 0.6);
  int i = 0;
  for (auto _ : state) {
    PlaneToIJK(c->CT, plane, 0.37 * (i++ % 7), axes, registered);
    axes->Modified();
    registered->Modified();
    blend->Update();
    benchmark::DoNotOptimize(blend->GetOutput()->GetScalarPointer());
  }
}

// `vectorized`: the 16-bit layers sampled eight at a time where the CPU has AVX2 (the default),
// or one at a time (the same pixels; rpSliceCompositeTest).
template <bool vectorized>
void BM_SlicePicture_OnePass(benchmark::State& state) {
  Case* c = TheCase();
  if (!c->CT) return state.SkipWithError(c->Error.c_str());
  rp::SetCompositeVectorized(vectorized);
  const int plane = static_cast<int>(state.range(0));
  vtkNew<vtkMatrix4x4> axes, registered;
  rp::SliceLayoutCache layouts;
  std::vector<std::uint32_t> picture(Side * Side);
  int i = 0;
  for (auto _ : state) {
    PlaneToIJK(c->CT, plane, 0.37 * (i++ % 7), axes, registered);
    const std::pair<vtkImageData*, vtkMatrix4x4*> sources[3] = {{c->CT, axes}, {c->CT, registered}, {c->Labels, axes}};
    const std::vector<std::uint32_t>* words[3] = {&c->BackgroundWords, &c->ForegroundWords, &c->SegmentWords};
    vtkLookupTable* tables[3] = {c->Background, c->Foreground, c->Segments};
    rp::SliceLayer layers[3];
    for (int l = 0; l < 3; ++l) {
      double rows[3][4];
      for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 4; ++k) rows[r][k] = sources[l].second->GetElement(r, k);
      layers[l] = rp::SliceLayerOf(sources[l].first, rows, Origin, 1.0);
      const double* range = tables[l]->GetTableRange();
      layers[l].Table = words[l]->data();
      layers[l].TableSize = static_cast<int>(words[l]->size());
      layers[l].TableMin = range[0];
      layers[l].TableScale = words[l]->size() / (range[1] - range[0]);
      layers[l].Nearest = l == 2;
      layers[l].Opacity = l == 0 ? 1.0 : l == 1 ? 0.4 : 0.6;
      layouts.Apply(sources[l].first, layers[l]);
    }
    rp::CompositeSlice(layers, 3, Side, Side, picture.data());
    benchmark::DoNotOptimize(picture.data());
  }
  rp::SetCompositeVectorized(true);
}

BENCHMARK(BM_SlicePicture_VTK)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_SlicePicture_OnePass, false)->Name("BM_SlicePicture_OnePassOneSampleAtATime")->DenseRange(0, 3)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_SlicePicture_OnePass, true)->Name("BM_SlicePicture_OnePass")->DenseRange(0, 3)->Unit(benchmark::kMillisecond);

// Keeps each run's real time per picture for the CSV and the chart.
class Collector : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& run : runs) {
      const std::string name = run.benchmark_name();
      const std::string method = name.find("_VTK") != std::string::npos ? "VTK (vtkImageResliceToColors x3 + vtkImageBlend)"
                                 : name.find("OneSampleAtATime") != std::string::npos
                                     ? "one pass, one sample at a time"
                                     : "one pass (rp::CompositeSlice)";
      const int plane = std::stoi(name.substr(name.rfind('/') + 1));
      if (run.iterations > 0 && !run.error_occurred) Figures[method][Planes[plane]] = run.GetAdjustedRealTime();
    }
    ConsoleReporter::ReportRuns(runs);
  }
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  rp::bench::AddConditionsToContext();
  Collector reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  rp::bench::FinishConditions(rp::bench::OutputDirectory(), "rpSlicePictureBenchmark");
  const std::string out = rp::bench::OutputDirectory();
  std::vector<std::string> categories(std::begin(Planes), std::end(Planes));
  std::vector<rp::bench::Series> series;
  std::vector<std::vector<double>> rows(4);
  for (const auto& [method, planes] : Figures) {
    rp::bench::Series s;
    s.Name = method;
    for (size_t p = 0; p < categories.size(); ++p) {
      // A plane the filter left out: no bar, "nan" in the CSV.
      const auto found = planes.find(categories[p]);
      s.Y.push_back(found != planes.end() ? found->second : 0.0);
      rows[p].push_back(found != planes.end() ? found->second : std::nan(""));
    }
    series.push_back(s);
  }
  std::string error;
  std::vector<std::string> header = {"plane"};
  for (const auto& [method, planes] : Figures) header.push_back(method + " ms");
  for (size_t p = 0; p < rows.size(); ++p) rows[p].insert(rows[p].begin(), double(p));  // 0 axial … 3 oblique
  rp::bench::WriteCSV(out + "/slice-picture.csv", header, rows, error);
  rp::bench::ChartOptions options;
  options.Title = "Slice picture (CT + registered CT + labels, 200x200 px), real knee CT";
  options.YLabel = "ms per picture";
  rp::bench::WriteBarChartPNG(out + "/slice-picture.png", categories, series, options, error);
  for (size_t p = 0; p < categories.size(); ++p) {
    std::cerr << "[slice-picture-bench] " << categories[p];
    for (const auto& [method, planes] : Figures)
      if (const auto found = planes.find(categories[p]); found != planes.end())
        std::cerr << "; " << method << " " << found->second << " ms";
    std::cerr << "\n";
  }
  return 0;
}
