#pragma once
// Fiducial files in 3D Slicer's layouts: .mrk.json (markups schema v1.0.3; control points in
// the file's coordinateSystem, LPS by default as Slicer writes them) and .fcsv (Slicer's
// "# Markups fiducial file version = 4.x" CSV with "# CoordinateSystem = LPS|RAS|0|1").
#include <string>

class vtkRPFiducialListNode;

namespace rp {

bool WriteMarkupsJson(const std::string& path, vtkRPFiducialListNode* node, std::string& error);
bool ReadMarkupsJson(const std::string& path, vtkRPFiducialListNode* node, std::string& error);
bool WriteFcsv(const std::string& path, vtkRPFiducialListNode* node, std::string& error);
bool ReadFcsv(const std::string& path, vtkRPFiducialListNode* node, std::string& error);

}  // namespace rp
