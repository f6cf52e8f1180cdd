// 3D Slicer's scene files (.mrml, .mrb; rpMrmlScene.h) as a DataReader (rpDataLoader.h):
// `roboplan plan.mrb`, the viewer's File > Open, drag and drop and `screenshot` open them through
// rp::LoadPath like any data file.
#include <filesystem>

#include "rpDataLoader.h"
#include "rpStorageFormats.h"
#include "rpMrmlScene.h"

namespace rp {
namespace {

class MrmlSceneReader : public DataReader {
 public:
  std::string Description() const override { return "3D Slicer scene"; }
  bool CanRead(const std::string& path) const override {
    std::error_code ec;
    return (HasExtension(path, ".mrml") || HasExtension(path, ".mrb")) && !std::filesystem::is_directory(path, ec);
  }
  int Priority() const override { return 20; }
  bool ReadsIntoScene() const override { return true; }  // nodes reference each other by ID
  bool Read(const std::string& path, const ReadOptions&, vtkRPScene* scene, LoadResult& result) const override {
    SceneTransferReport report;
    const bool ok = HasExtension(path, ".mrb") ? ReadMrmlBundle(path, scene, report) : ReadMrmlScene(path, scene, report);
    if (!ok) {
      result.Error = report.Error;
      return false;
    }
    for (const auto& skip : report.Skipped) result.Warnings.push_back(skip.What + ": " + skip.Why);
    result.Warnings.insert(result.Warnings.end(), report.Warnings.begin(), report.Warnings.end());
    result.Details["nodes"] = report.NodesByType;
    result.Details["files"] = report.Files;
    return true;
  }
};

}  // namespace

std::shared_ptr<DataReader> MakeMrmlSceneReader() { return std::make_shared<MrmlSceneReader>(); }

}  // namespace rp
