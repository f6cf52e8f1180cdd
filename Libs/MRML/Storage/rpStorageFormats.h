#pragma once
// The file formats and readers this library brings, listed in one place (rpStorageFormats.cxx)
// instead of registering themselves from static initializers: the node-storage registry
// (rpNodeStorage.h) and the loader's registry (rpDataLoader.h) start from these lists the first
// time they are asked. A new format of a node is one maker here and one line in the list; a
// format another library or a module brings registers at its owner's start-up
// (RegisterNodeStorage / RegisterDataReader, as rpImagingReaders.h's RegisterImagingReaders).
#include <memory>
#include <vector>

namespace rp {

class DataReader;
class NodeStorage;

/// Node storages, in the order they are asked (a tie in priority goes to the first).
std::vector<std::shared_ptr<NodeStorage>> BuiltInNodeStorages();
/// Readers of paths (a file or folder that is not one node's, and every node file through the
/// storages), in the order they are asked.
std::vector<std::shared_ptr<DataReader>> BuiltInDataReaders();

// Each format's maker, beside its code.
std::shared_ptr<NodeStorage> MakeMarkupsStorage();          // rpMarkupsIO.cxx
std::shared_ptr<NodeStorage> MakeModelStorage();            // rpModelIO.cxx
std::shared_ptr<NodeStorage> MakeSegmentationStorage();     // rpSegmentationIO.cxx
std::shared_ptr<NodeStorage> MakeLinearTransformStorage();  // rpTransformIO.cxx
std::shared_ptr<NodeStorage> MakeScalarVolumeStorage();     // rpVolumeIO.cxx
std::shared_ptr<DataReader> MakeNodeFileReader();           // rpDataLoader.cxx
std::shared_ptr<DataReader> MakeMrmlSceneReader();          // rpMrmlDataReader.cxx
std::shared_ptr<DataReader> MakeSceneFileReader();          // rpSceneFileReader.cxx

}  // namespace rp
