#pragma once
// Tool definitions: NDI passive tool definition (.rom) bytes, and the JSON description under
// Resources/Tools/ that the simulator uses (markers, stylus tip offset, scripted trajectory).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "rpNdiRom.h"

namespace rp {


/// Where a simulated tool goes: tip pivoting about a fixed point, a circle, or standing still.
struct ToolTrajectory {
  enum Kind { Static, Pivot, Circle } Type = Static;
  double Center[3] = {0, 0, -1500};  // mm, tracker frame (pivot point for Pivot)
  double Radius = 0;                 // Circle radius (mm)
  double ConeAngleDeg = 25;          // Pivot: tilt of the stylus from the cone axis
  double PeriodSeconds = 4;          // one turn
  double Euler[3] = {0, 0, 0};       // Static/Circle orientation (deg, z-y-x)
};

struct ToolDefinition {
  std::string Name;                  // scene name, e.g. "Stylus" (transform StylusToTracker)
  std::string PartNumber;            // stored in the ROM
  std::vector<std::array<double, 3>> Markers;
  std::array<double, 3> TipOffset = {0, 0, 0};  // StylusTipToStylus translation (mm)
  ToolTrajectory Motion;
  std::vector<uint8_t> Rom;          // built from the markers when no .rom file is given
};

/// Reads a tool definition JSON file (Resources/Tools/*.json). Throws std::runtime_error naming
/// the file and the problem.
ToolDefinition ReadToolDefinition(const std::string& path);
/// The same from the file's text (`source` names it in messages). Throws std::runtime_error only.
ToolDefinition ParseToolDefinition(const std::string& text, const std::string& source);
std::vector<uint8_t> ReadBinaryFile(const std::string& path);  // throws std::runtime_error
/// A tool file a user gives: a definition .json, or a bare NDI .rom (the tool is named after
/// the file; markers and part number from the ROM when it reads, no trajectory). Throws
/// std::runtime_error naming the file.
ToolDefinition ReadToolFile(const std::string& path);

/// Pose of a tool on its trajectory at time t (seconds): row-major 4x4 ToolToTracker.
void EvaluateTrajectory(const ToolDefinition& tool, double t, double m[16]);

}  // namespace rp
