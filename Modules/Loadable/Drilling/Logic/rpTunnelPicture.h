#pragma once
// A picture of a drilled tunnel (PNG, offscreen VTK rendering; needs a display or Xvfb): on the
// left the drilled bone in 3D, see-through, with the planned axis and the burr's path; on the
// right a section of the voxel bone through the tunnel's axis (the axis runs up the image):
// cortical bone ivory, trabecular tan, what the burr removed blue, protected voxels red, the
// planned tunnel (axis and radius) as green lines and the burr's centre path as yellow dots.
#include <string>
#include <vector>

#include <vtkSmartPointer.h>

#include "rpMaterial.h"
#include "rpTriangleMesh.h"

class vtkPolyData;

namespace rp {

class DrillVolume;

struct TunnelPicture {
  vtkSmartPointer<vtkPolyData> Bone;       // the drilled bone (rpDrillDisplay's mesh: "Material" point array)
  const DrillVolume* Volume = nullptr;     // for the section (densities now and as built)
  std::vector<Material> Materials;         // drillable materials (colours by name)
  vtkSmartPointer<vtkPolyData> Protected;  // optional
  Vec3 From, To;                           // the planned axis
  double Radius = 0;                       // the burr (the planned tunnel's radius)
  std::vector<Vec3> Path;                  // burr centres along the stroke
  std::string Title;
  int Width = 1600, Height = 800;
};

/// Drawn by libRoboPlanDrillingPictures.so (Pictures/rpTunnelPicture.cxx), loaded on the first
/// picture; false with `error` naming that file where it is missing.
bool WriteTunnelPicture(const std::string& path, const TunnelPicture& picture, std::string& error);

}  // namespace rp
