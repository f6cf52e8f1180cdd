#include "rpDrillDisplay.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

#include <vtkCellArray.h>
#include <vtkFloatArray.h>
#include <vtkIdTypeArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

namespace rp {

namespace {
double MillisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}
}  // namespace

DisplayTimings SplitDisplayFrames(const std::vector<DisplayFrame>& frames) {
  DisplayTimings t;
  for (const DisplayFrame& f : frames) {
    if (f.Blocks > 0) {
      t.ContourMs.push_back(f.ContourMs);
      t.Blocks.push_back(double(f.Blocks));
    }
    if (f.AssembleMs > 0) t.AssembleMs.push_back(f.AssembleMs);
  }
  return t;
}

double NearestRankPercentile(std::vector<double> values, double q) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const size_t rank = static_cast<size_t>(std::ceil(q * static_cast<double>(values.size())));
  return values[std::min(values.size() - 1, rank > 0 ? rank - 1 : 0)];
}

DrillDisplay::DrillDisplay(DrillVolume& volume) : Blocks(volume) {}

DrillDisplay::~DrillDisplay() { this->Stop(); }

vtkSmartPointer<vtkPolyData> DrillDisplay::Assemble(const BlockMesher& mesher) {
  const size_t points = mesher.PointCount(), triangles = mesher.TriangleCount();
  vtkNew<vtkFloatArray> coordinates;
  coordinates->SetNumberOfComponents(3);
  coordinates->SetNumberOfTuples(static_cast<vtkIdType>(points));
  vtkNew<vtkFloatArray> normals;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  normals->SetNumberOfTuples(static_cast<vtkIdType>(points));
  vtkNew<vtkUnsignedCharArray> materials;
  materials->SetName("Material");  // 1 + index of the drillable material (0 none)
  materials->SetNumberOfTuples(static_cast<vtkIdType>(points));
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfTuples(static_cast<vtkIdType>(triangles + 1));
  connectivity->SetNumberOfTuples(static_cast<vtkIdType>(3 * triangles));
  float* p = coordinates->GetPointer(0);
  float* n = normals->GetPointer(0);
  unsigned char* m = materials->GetPointer(0);
  vtkIdType* o = offsets->GetPointer(0);
  vtkIdType* c = connectivity->GetPointer(0);
  vtkIdType base = 0, cell = 0;
  for (const BlockMesh& block : mesher.Blocks()) {
    const size_t count = block.Points.size() / 3;
    if (count == 0) continue;
    std::memcpy(p + 3 * base, block.Points.data(), block.Points.size() * sizeof(float));
    std::memcpy(n + 3 * base, block.Normals.data(), block.Normals.size() * sizeof(float));
    std::memcpy(m + base, block.Materials.data(), block.Materials.size());
    for (size_t t = 0; t < block.Triangles.size(); t += 3, ++cell) {
      o[cell] = 3 * cell;
      c[3 * cell] = base + block.Triangles[t];
      c[3 * cell + 1] = base + block.Triangles[t + 1];
      c[3 * cell + 2] = base + block.Triangles[t + 2];
    }
    base += static_cast<vtkIdType>(count);
  }
  o[cell] = 3 * cell;
  vtkNew<vtkPoints> pts;
  pts->SetData(coordinates);
  vtkNew<vtkCellArray> polys;
  polys->SetData(offsets, connectivity);
  auto mesh = vtkSmartPointer<vtkPolyData>::New();
  mesh->SetPoints(pts);
  mesh->SetPolys(polys);
  mesh->GetPointData()->SetNormals(normals);
  mesh->GetPointData()->AddArray(materials);
  return mesh;
}

vtkSmartPointer<vtkPolyData> DrillDisplay::Initialize() {
  this->Blocks.ContourAll();
  return Assemble(this->Blocks);
}

DisplayFrame DrillDisplay::Frame() {
  DisplayFrame frame;
  const auto start = std::chrono::steady_clock::now();
  frame.Blocks = this->Blocks.UpdateDirty();
  frame.ContourMs = MillisecondsSince(start);
  if (frame.Blocks == 0) return frame;
  vtkSmartPointer<vtkPolyData> mesh;
  if (this->MeshEveryFrame) mesh = this->AssembleInto(frame);
  std::lock_guard<std::mutex> guard(this->Lock);
  if (mesh) this->Pending = mesh;
  this->History.push_back(frame);
  return frame;
}

void DrillDisplay::PostMesh() {
  DisplayFrame frame;
  vtkSmartPointer<vtkPolyData> mesh = this->AssembleInto(frame);
  std::lock_guard<std::mutex> guard(this->Lock);
  this->Pending = mesh;
  this->History.push_back(frame);
}

vtkSmartPointer<vtkPolyData> DrillDisplay::AssembleInto(DisplayFrame& frame) const {
  const auto start = std::chrono::steady_clock::now();
  vtkSmartPointer<vtkPolyData> mesh = Assemble(this->Blocks);
  frame.AssembleMs = MillisecondsSince(start);
  frame.Triangles = static_cast<size_t>(mesh->GetNumberOfPolys());
  return mesh;
}

bool DrillDisplay::Start(double rateHz, std::string& error) {
  if (this->Running()) {
    error = "drill display: already running";
    return false;
  }
  if (!(rateHz > 0 && rateHz <= 1000)) {
    error = "drill display: the rate must be in (0, 1000] Hz";
    return false;
  }
  this->StopRequested.store(false);
  const auto period = std::chrono::duration<double>(1.0 / rateHz);
  this->Thread = std::thread([this, period] {
    auto next = std::chrono::steady_clock::now();
    while (!this->StopRequested.load(std::memory_order_acquire)) {
      this->Frame();
      next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
      const auto now = std::chrono::steady_clock::now();
      if (next < now) next = now;  // late: do not try to catch up
      std::this_thread::sleep_until(next);
    }
  });
  return true;
}

void DrillDisplay::Stop() {
  this->StopRequested.store(true, std::memory_order_release);
  if (this->Thread.joinable()) this->Thread.join();
}

vtkSmartPointer<vtkPolyData> DrillDisplay::TakeMesh() {
  std::lock_guard<std::mutex> guard(this->Lock);
  vtkSmartPointer<vtkPolyData> mesh = this->Pending;
  this->Pending = nullptr;
  return mesh;
}

std::vector<DisplayFrame> DrillDisplay::Frames() const {
  std::lock_guard<std::mutex> guard(this->Lock);
  return this->History;
}

}  // namespace rp
