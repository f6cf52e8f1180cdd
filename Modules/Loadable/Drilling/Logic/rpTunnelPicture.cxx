// rp::WriteTunnelPicture forwards to libRoboPlanDrillingPictures.so (Pictures/rpTunnelPicture.cxx),
// loaded on the first picture: `roboplan drill` and every module that links the drilling logic map
// no VTK rendering or GL until a command draws.
#include "rpTunnelPicture.h"

#include "rpSiblingLibrary.h"

namespace rp {

bool WriteTunnelPicture(const std::string& path, const TunnelPicture& picture, std::string& error) {
  using Draw = bool (*)(const std::string&, const TunnelPicture&, std::string&);
  std::string why;
  const auto draw = SiblingLibraryFunction<Draw>(reinterpret_cast<const void*>(&WriteTunnelPicture),
                                                 "libRoboPlanDrillingPictures.so", "roboplan_write_tunnel_picture", why);
  if (!draw) {
    error = "picture '" + path + "' not drawn: " + why;
    return false;
  }
  return draw(path, picture, error);
}

}  // namespace rp
