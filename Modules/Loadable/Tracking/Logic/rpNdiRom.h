#pragma once
// NDI tool definition files (.rom, "SROM images"): read, checked and written. NDI does not
// publish the layout; this one follows what open projects worked out (JHU's sawNDITracker
// tool converter, ndicapi's PVWR upload of 1024 zero-padded bytes) and every field we rely on
// is checked against the five real files of PlusLibData (8700248, 8700339, 8700340, 8700449,
// a Robarts stylus): the checksum matches on all five, the markers form NDI's published
// geometry of those tools, the date fields agree with each other (day of year and month), and
// writing the fields back gives the five files byte for byte (rpNdiRomTest).
//
// Layout (752 bytes, little endian):
//   0 "NDI\0" | 4 u16 checksum = sum of bytes 6..751 | 8 u8 1 | 12 u8 tool sub-type | 15 u8 tool
//   main type (1 reference, 2 pointer, ...) | 16 u16 revision | 20..23 sequence number and date |
//   24 u8 maximum marker angle (deg) | 28 u8 marker count (3..20) | 32 u8 minimum markers |
//   36 f32 maximum 3D marker error (mm) | 64 f32 (10.0 in every real file; meaning unknown) |
//   72 20 x f32[3] marker positions (mm) | 312 20 x f32[3] marker normals | 552 u8[20] firing
//   sequence | 572 u8[4] LEDs (31: none) | 576 u8 tool-in-port diode (9) | 577 u8[3] switches |
//   580 char[12] manufacturer | 592 char[20] part number | 612 u8 (9) | 613 u8[20] marker faces |
//   633 u8[20] marker groups | 653 u8 algorithm flags (0x80 unique geometry) | 655 u8 marker type
//   (41 passive sphere) | 656 8 x f32[3] face normals.
// Plain C++ (no VTK): the driver, the simulator and the fuzz targets use it.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace rp {
namespace rom {

constexpr size_t Size = 752;
constexpr size_t MaxMarkers = 20;
constexpr size_t MaxFaces = 8;
using Vec3 = std::array<double, 3>;

/// Every field of a tool definition we know.
struct Definition {
  std::string Manufacturer = "RoboPlan";  // up to 12 characters
  std::string PartNumber;                 // up to 20 characters
  int ToolMainType = 4;                   // 1 reference, 2 pointer, 4 user defined, ...
  int ToolSubType = 2;
  int Revision = 0;
  int SequenceNumber = 0;                 // 10 bits
  int Year = 2026, Month = 1, Day = 1;    // date the definition was made
  int MaxMarkerAngleDeg = 90;
  int MinimumMarkers = 3;
  double MaxMarkerErrorMm = 2.0;
  double Field64 = 10.0;                  // unknown float at 64 (10.0 in every real file)
  std::vector<Vec3> Markers;              // mm, tool coordinates
  std::vector<Vec3> Normals;              // one per marker (zero: none given)
  std::vector<int> FiringSequence;        // one per marker
  std::vector<int> Faces, Groups;         // one per marker
  int AlgorithmFlags = 0x80;
  int MarkerType = 41;                    // 41 passive sphere, 49 passive disc, 57 Radix lens
  std::vector<Vec3> FaceNormals;          // up to 8
  uint16_t Checksum = 0;                  // as stored (Read) / as written (Write)
};

/// Sum of bytes 6.. (the checksum NDI stores at 4).
uint16_t ComputeChecksum(const uint8_t* data, size_t size);
/// Checks the signature, size and checksum; `error` says what is wrong.
bool Validate(const std::vector<uint8_t>& bytes, std::string& error);
/// Reads and validates a definition (marker count 1..20, finite coordinates). False with `error`.
bool Read(const uint8_t* data, size_t size, Definition& definition, std::string& error);
/// The 752 bytes of a definition, its checksum set (markers beyond 20 are dropped).
std::vector<uint8_t> Write(const Definition& definition);
/// A passive tool definition from markers (normals +z, faces and groups 1, a fixed date).
std::vector<uint8_t> Build(const std::string& partNumber, const std::vector<Vec3>& markers);
/// The part number stored at 592 ("" when too short).
std::string PartNumber(const std::vector<uint8_t>& bytes);
int MarkerCount(const std::vector<uint8_t>& bytes);
/// Reads a .rom file: throws std::runtime_error naming the file and the problem.
Definition ReadFile(const std::string& path, std::vector<uint8_t>* bytes = nullptr);

}  // namespace rom
}  // namespace rp
