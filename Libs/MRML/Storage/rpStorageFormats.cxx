#include "rpStorageFormats.h"

#include "rpDataLoader.h"
#include "rpNodeStorage.h"

namespace rp {

std::vector<std::shared_ptr<NodeStorage>> BuiltInNodeStorages() {
  return {MakeMarkupsStorage(), MakeModelStorage(), MakeSegmentationStorage(), MakeLinearTransformStorage(),
          MakeScalarVolumeStorage()};
}

std::vector<std::shared_ptr<DataReader>> BuiltInDataReaders() {
  return {MakeNodeFileReader(), MakeMrmlSceneReader(), MakeSceneFileReader()};
}

}  // namespace rp
