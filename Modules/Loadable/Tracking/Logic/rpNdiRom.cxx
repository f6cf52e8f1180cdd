#include "rpNdiRom.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

namespace rp {
namespace rom {

namespace {
// Field offsets (see the header).
constexpr size_t kChecksum = 4, kOne = 8, kSubType = 12, kMainType = 15, kRevision = 16, kDate = 20,
                 kMaxAngle = 24, kCount = 28, kMinMarkers = 32, kMaxError = 36, kField64 = 64, kMarkers = 72,
                 kNormals = 312, kFiring = 552, kLeds = 572, kPortDiode = 576, kManufacturer = 580,
                 kPartNumber = 592, kField612 = 612, kFaces = 613, kGroups = 633, kFlags = 653, kMarkerType = 655,
                 kFaceNormals = 656;

bool LeapYear(int y) { return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0; }
int DaysInMonth(int y, int m) {
  static const int kDays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  return m == 2 && LeapYear(y) ? 29 : kDays[(m - 1) % 12];
}
int DayOfYear(int y, int m, int d) {  // 0 = 1 January
  int n = d - 1;
  for (int k = 1; k < m; ++k) n += DaysInMonth(y, k);
  return n;
}

float GetF32(const uint8_t* p) {
  uint32_t bits = static_cast<uint32_t>(p[0]) | static_cast<uint32_t>(p[1]) << 8 | static_cast<uint32_t>(p[2]) << 16 |
                  static_cast<uint32_t>(p[3]) << 24;
  float f;
  std::memcpy(&f, &bits, 4);
  return f;
}
void PutF32(uint8_t* p, double v) {
  const float f = static_cast<float>(v);
  uint32_t bits;
  std::memcpy(&bits, &f, 4);
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(bits >> (8 * i));
}
Vec3 GetVec(const uint8_t* p) { return {GetF32(p), GetF32(p + 4), GetF32(p + 8)}; }
void PutVec(uint8_t* p, const Vec3& v) {
  for (int k = 0; k < 3; ++k) PutF32(p + 4 * k, v[static_cast<size_t>(k)]);
}
std::string GetText(const uint8_t* p, size_t n) {
  const char* c = reinterpret_cast<const char*>(p);
  return std::string(c, strnlen(c, n));
}
void PutText(uint8_t* p, const std::string& s, size_t n) { std::memcpy(p, s.data(), std::min(s.size(), n)); }

// Bytes 20..23: sequence number (10 bits) and date, as the JHU converter decodes them: the day
// of the year counted in 64-day blocks (low 6 bits x4 in byte 21, block in byte 22's low 3
// bits), the month in byte 22's middle 4 bits, the year's parity in its top bit, (year-1900)/2
// in byte 23. Reading checks that day and month agree (true on all five real files).
bool ReadDate(const uint8_t* p, Definition& d, std::string& error) {
  d.SequenceNumber = p[0] | (p[1] & 3) << 8;
  const int day = ((p[2] & 7) << 6) | (p[1] >> 2);
  d.Year = 1900 + 2 * p[3] + (p[2] >> 7);
  const int month = ((p[2] & 0x7F) >> 3) + 1;
  int m = 1, left = day;
  while (m <= 12 && left >= DaysInMonth(d.Year, m)) left -= DaysInMonth(d.Year, m++);
  if (m > 12 || m != month) {
    error = "date fields disagree (day " + std::to_string(day + 1) + " of " + std::to_string(d.Year) + " is not in month " +
            std::to_string(month) + ")";
    return false;
  }
  d.Month = m;
  d.Day = left + 1;
  return true;
}
void WriteDate(uint8_t* p, const Definition& d) {
  const int month = std::min(12, std::max(1, d.Month));
  const int day = std::min(DaysInMonth(d.Year, month), std::max(1, d.Day));
  const int doy = DayOfYear(d.Year, month, day);
  const int years = std::min(255 * 2 + 1, std::max(0, d.Year - 1900));
  p[0] = static_cast<uint8_t>(d.SequenceNumber & 0xFF);
  p[1] = static_cast<uint8_t>(((doy & 63) << 2) | ((d.SequenceNumber >> 8) & 3));
  p[2] = static_cast<uint8_t>(((years & 1) << 7) | ((month - 1) << 3) | (doy >> 6));
  p[3] = static_cast<uint8_t>(years / 2);
}
}  // namespace

uint16_t ComputeChecksum(const uint8_t* data, size_t size) {
  uint32_t sum = 0;
  for (size_t i = 6; i < size; ++i) sum += data[i];
  return static_cast<uint16_t>(sum & 0xFFFF);
}

bool Validate(const std::vector<uint8_t>& bytes, std::string& error) {
  if (bytes.size() < kMarkers) {
    error = "tool definition too short (" + std::to_string(bytes.size()) + " bytes)";
    return false;
  }
  if (bytes.size() > 1024) {
    error = "tool definition larger than 1024 bytes";
    return false;
  }
  if (std::memcmp(bytes.data(), "NDI", 3) != 0) {
    error = "not an NDI tool definition (no \"NDI\" signature)";
    return false;
  }
  const uint16_t stored = static_cast<uint16_t>(bytes[kChecksum] | (bytes[kChecksum + 1] << 8));
  if (stored != ComputeChecksum(bytes.data(), bytes.size())) {
    error = "tool definition checksum mismatch (stored " + std::to_string(stored) + ", computed " +
            std::to_string(ComputeChecksum(bytes.data(), bytes.size())) + ")";
    return false;
  }
  return true;
}

bool Read(const uint8_t* data, size_t size, Definition& d, std::string& error) {
  if (!Validate(std::vector<uint8_t>(data, data + size), error)) return false;
  if (size < Size) {
    error = "tool definition of " + std::to_string(size) + " bytes: expected " + std::to_string(Size);
    return false;
  }
  d = Definition();
  d.Checksum = static_cast<uint16_t>(data[kChecksum] | data[kChecksum + 1] << 8);
  d.ToolSubType = data[kSubType];
  d.ToolMainType = data[kMainType];
  d.Revision = data[kRevision] | data[kRevision + 1] << 8;
  if (!ReadDate(data + kDate, d, error)) return false;
  d.MaxMarkerAngleDeg = data[kMaxAngle];
  const size_t count = data[kCount];
  if (count < 1 || count > MaxMarkers) {
    error = "marker count " + std::to_string(count) + " (expected 1 to 20)";
    return false;
  }
  d.MinimumMarkers = data[kMinMarkers];
  d.MaxMarkerErrorMm = GetF32(data + kMaxError);
  d.Field64 = GetF32(data + kField64);
  for (size_t m = 0; m < count; ++m) {
    d.Markers.push_back(GetVec(data + kMarkers + 12 * m));
    d.Normals.push_back(GetVec(data + kNormals + 12 * m));
    d.FiringSequence.push_back(data[kFiring + m]);
    d.Faces.push_back(data[kFaces + m]);
    d.Groups.push_back(data[kGroups + m]);
    for (const Vec3* v : {&d.Markers.back(), &d.Normals.back()})
      for (double x : *v)
        if (!std::isfinite(x) || std::abs(x) > 1e5) {
          error = "marker " + std::to_string(m + 1) + " has an unusable coordinate";
          return false;
        }
  }
  for (size_t f = 0; f < MaxFaces; ++f) {
    const Vec3 n = GetVec(data + kFaceNormals + 12 * f);
    if (n[0] != 0 || n[1] != 0 || n[2] != 0) d.FaceNormals.resize(f + 1);
  }
  for (size_t f = 0; f < d.FaceNormals.size(); ++f) d.FaceNormals[f] = GetVec(data + kFaceNormals + 12 * f);
  d.Manufacturer = GetText(data + kManufacturer, 12);
  d.PartNumber = GetText(data + kPartNumber, 20);
  d.AlgorithmFlags = data[kFlags];
  d.MarkerType = data[kMarkerType];
  return true;
}

std::vector<uint8_t> Write(const Definition& d) {
  std::vector<uint8_t> b(Size, 0);
  std::memcpy(b.data(), "NDI", 3);
  b[kOne] = 1;
  b[kSubType] = static_cast<uint8_t>(d.ToolSubType);
  b[kMainType] = static_cast<uint8_t>(d.ToolMainType);
  b[kRevision] = static_cast<uint8_t>(d.Revision & 0xFF);
  b[kRevision + 1] = static_cast<uint8_t>((d.Revision >> 8) & 0xFF);
  WriteDate(&b[kDate], d);
  b[kMaxAngle] = static_cast<uint8_t>(d.MaxMarkerAngleDeg);
  const size_t count = std::min(d.Markers.size(), MaxMarkers);
  b[kCount] = static_cast<uint8_t>(count);
  b[kMinMarkers] = static_cast<uint8_t>(d.MinimumMarkers);
  PutF32(&b[kMaxError], d.MaxMarkerErrorMm);
  PutF32(&b[kField64], d.Field64);
  for (size_t m = 0; m < count; ++m) {
    PutVec(&b[kMarkers + 12 * m], d.Markers[m]);
    if (m < d.Normals.size()) PutVec(&b[kNormals + 12 * m], d.Normals[m]);
    b[kFiring + m] = static_cast<uint8_t>(m < d.FiringSequence.size() ? d.FiringSequence[m] : static_cast<int>(m));
    b[kFaces + m] = static_cast<uint8_t>(m < d.Faces.size() ? d.Faces[m] : 1);
    b[kGroups + m] = static_cast<uint8_t>(m < d.Groups.size() ? d.Groups[m] : 1);
  }
  std::memset(&b[kLeds], 31, 4);
  b[kPortDiode] = 9;
  PutText(&b[kManufacturer], d.Manufacturer, 12);
  PutText(&b[kPartNumber], d.PartNumber, 20);
  b[kField612] = 9;
  b[kFlags] = static_cast<uint8_t>(d.AlgorithmFlags);
  b[kMarkerType] = static_cast<uint8_t>(d.MarkerType);
  for (size_t f = 0; f < std::min(d.FaceNormals.size(), MaxFaces); ++f) PutVec(&b[kFaceNormals + 12 * f], d.FaceNormals[f]);
  const uint16_t sum = ComputeChecksum(b.data(), b.size());
  b[kChecksum] = static_cast<uint8_t>(sum & 0xFF);
  b[kChecksum + 1] = static_cast<uint8_t>(sum >> 8);
  return b;
}

std::vector<uint8_t> Build(const std::string& partNumber, const std::vector<Vec3>& markers) {
  Definition d;
  d.PartNumber = partNumber;
  d.Markers = markers;
  d.Normals.assign(markers.size(), Vec3{0, 0, 1});  // markers face the camera (+z)
  d.FaceNormals = {Vec3{0, 0, 1}};
  d.MinimumMarkers = static_cast<int>(std::min<size_t>(3, markers.size()));
  return Write(d);  // the Definition's fixed date: the same markers give the same bytes on any day
}

std::string PartNumber(const std::vector<uint8_t>& bytes) {
  return bytes.size() >= kPartNumber + 20 ? GetText(bytes.data() + kPartNumber, 20) : std::string();
}

int MarkerCount(const std::vector<uint8_t>& bytes) { return bytes.size() > kCount ? bytes[kCount] : 0; }

Definition ReadFile(const std::string& path, std::vector<uint8_t>* bytesOut) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::vector<uint8_t> bytes;
  char c;
  while (bytes.size() <= 4096 && in.get(c)) bytes.push_back(static_cast<uint8_t>(c));
  Definition d;
  std::string error;
  if (!Read(bytes.data(), bytes.size(), d, error)) throw std::runtime_error(path + ": " + error);
  if (bytesOut) *bytesOut = bytes;
  return d;
}

}  // namespace rom
}  // namespace rp
