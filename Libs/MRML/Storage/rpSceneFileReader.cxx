// The RoboPlan scene file (.rpscene) as a DataReader (rpDataLoader.h): `roboplan scene.rpscene`,
// the viewer's File > Open and `screenshot` open it through rp::LoadPath like any data file.
#include <filesystem>

#include "rpDataLoader.h"
#include "rpStorageFormats.h"
#include "rpSceneFile.h"
#include "rpSceneIO.h"

namespace rp {
namespace {

class SceneFileReader : public DataReader {
 public:
  std::string Description() const override { return "RoboPlan scene"; }
  bool CanRead(const std::string& path) const override {
    std::error_code ec;
    return HasExtension(path, SceneFileExtension) && !std::filesystem::is_directory(path, ec);
  }
  int Priority() const override { return 20; }
  bool ReadsIntoScene() const override { return true; }  // nodes reference each other by ID
  bool Read(const std::string& path, const ReadOptions&, vtkRPScene* scene, LoadResult& result) const override {
    const SceneLoadReport report = LoadScene(scene, path);
    if (!report.Ok) {
      result.Error = report.Error;
      return false;
    }
    result.Warnings.insert(result.Warnings.end(), report.Problems.begin(), report.Problems.end());
    result.Details["nodesLoaded"] = report.NodesLoaded;
    return true;
  }
};

}  // namespace

std::shared_ptr<DataReader> MakeSceneFileReader() { return std::make_shared<SceneFileReader>(); }

}  // namespace rp
