// The node-storage list for the .mrml/.mrb fuzz targets, which build only the parsers they fuzz
// and of the storages only rpModelIO.cxx (the library's own list, for everything else, is
// Libs/MRML/Storage/rpStorageFormats.cxx).
#include "rpNodeStorage.h"
#include "rpStorageFormats.h"

namespace rp {

std::vector<std::shared_ptr<NodeStorage>> BuiltInNodeStorages() { return {MakeModelStorage()}; }

}  // namespace rp
