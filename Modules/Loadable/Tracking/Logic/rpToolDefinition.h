#pragma once
// Tool definitions: NDI passive tool definition (.rom) bytes, and the JSON description under
// Resources/Tools/ that the simulator uses (markers, stylus tip offset, scripted trajectory).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace rp {

/// Reverse-engineered ROM layout (see the protocol notes): 752 bytes, "NDI\0", u16 checksum of
/// bytes 6..end at 4, marker count at 28, marker positions at 72, normals at 312. We also keep a
/// part number (20 chars) at 8 so a simulator can tell tools apart.
namespace rom {
constexpr size_t Size = 752;
std::vector<uint8_t> Build(const std::string& partNumber, const std::vector<std::array<double, 3>>& markers);
/// Checks the signature, size and checksum; error says what is wrong.
bool Validate(const std::vector<uint8_t>& bytes, std::string& error);
std::string PartNumber(const std::vector<uint8_t>& bytes);
int MarkerCount(const std::vector<uint8_t>& bytes);
}  // namespace rom

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
/// the file; no markers or trajectory). Throws std::runtime_error naming the file.
ToolDefinition ReadToolFile(const std::string& path);

/// Pose of a tool on its trajectory at time t (seconds): row-major 4x4 ToolToTracker.
void EvaluateTrajectory(const ToolDefinition& tool, double t, double m[16]);

}  // namespace rp
