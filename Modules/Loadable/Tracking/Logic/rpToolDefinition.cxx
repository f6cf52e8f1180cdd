#include "rpToolDefinition.h"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace rp {


std::vector<uint8_t> ReadBinaryFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open " + path);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

ToolDefinition ReadToolFile(const std::string& path) {
  if (std::filesystem::path(path).extension() == ".json") return ReadToolDefinition(path);
  ToolDefinition tool;
  tool.Name = std::filesystem::path(path).stem().string();
  tool.Rom = ReadBinaryFile(path);
  rom::Definition definition;
  std::string error;  // an unreadable ROM is still handed to the tracker, which names the problem
  if (rom::Read(tool.Rom.data(), tool.Rom.size(), definition, error)) {
    tool.PartNumber = definition.PartNumber;
    tool.Markers = definition.Markers;
  }
  return tool;
}

ToolDefinition ReadToolDefinition(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open tool definition " + path);
  return ParseToolDefinition(std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()), path);
}

ToolDefinition ParseToolDefinition(const std::string& text, const std::string& path) {
  try {
    const nlohmann::json j = nlohmann::json::parse(text);
    ToolDefinition t;
    t.Name = j.at("name").get<std::string>();
    t.PartNumber = j.value("partNumber", t.Name);
    for (const auto& m : j.at("markers")) t.Markers.push_back({m.at(0).get<double>(), m.at(1).get<double>(), m.at(2).get<double>()});
    if (j.contains("tipOffset"))
      for (int k = 0; k < 3; ++k) t.TipOffset[k] = j["tipOffset"].at(k).get<double>();
    if (j.contains("trajectory")) {
      const auto& tj = j["trajectory"];
      const std::string kind = tj.value("type", "static");
      if (kind == "static") t.Motion.Type = ToolTrajectory::Static;
      else if (kind == "pivot") t.Motion.Type = ToolTrajectory::Pivot;
      else if (kind == "circle") t.Motion.Type = ToolTrajectory::Circle;
      else throw std::runtime_error("unknown trajectory type '" + kind + "'");
      if (tj.contains("center"))
        for (int k = 0; k < 3; ++k) t.Motion.Center[k] = tj["center"].at(k).get<double>();
      if (tj.contains("eulerDeg"))
        for (int k = 0; k < 3; ++k) t.Motion.Euler[k] = tj["eulerDeg"].at(k).get<double>();
      t.Motion.Radius = tj.value("radius", 0.0);
      t.Motion.ConeAngleDeg = tj.value("coneAngleDeg", 25.0);
      t.Motion.PeriodSeconds = tj.value("periodSeconds", 4.0);
    }
    t.Rom = rom::Build(t.PartNumber, t.Markers);
    return t;
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error("bad tool definition " + path + ": " + e.what());
  }
}

namespace {
void Multiply3(const double a[9], const double b[9], double out[9]) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out[3 * r + c] = a[3 * r] * b[c] + a[3 * r + 1] * b[3 + c] + a[3 * r + 2] * b[6 + c];
}
void RotZ(double a, double m[9]) {
  const double c = std::cos(a), s = std::sin(a);
  const double r[9] = {c, -s, 0, s, c, 0, 0, 0, 1};
  std::memcpy(m, r, sizeof r);
}
void RotY(double a, double m[9]) {
  const double c = std::cos(a), s = std::sin(a);
  const double r[9] = {c, 0, s, 0, 1, 0, -s, 0, c};
  std::memcpy(m, r, sizeof r);
}
void RotX(double a, double m[9]) {
  const double c = std::cos(a), s = std::sin(a);
  const double r[9] = {1, 0, 0, 0, c, -s, 0, s, c};
  std::memcpy(m, r, sizeof r);
}
}  // namespace

void EvaluateTrajectory(const ToolDefinition& tool, double t, double m[16]) {
  const ToolTrajectory& tr = tool.Motion;
  const double deg = M_PI / 180.0;
  double R[9], a[9], b[9], c[9], tmp[9];
  RotZ(tr.Euler[0] * deg, a);
  RotY(tr.Euler[1] * deg, b);
  RotX(tr.Euler[2] * deg, c);
  Multiply3(a, b, tmp);
  Multiply3(tmp, c, R);
  double p[3] = {tr.Center[0], tr.Center[1], tr.Center[2]};
  const double phase = tr.PeriodSeconds > 0 ? 2 * M_PI * t / tr.PeriodSeconds : 0.0;
  if (tr.Type == ToolTrajectory::Circle) {
    p[0] += tr.Radius * std::cos(phase);
    p[1] += tr.Radius * std::sin(phase);
  } else if (tr.Type == ToolTrajectory::Pivot) {
    // The stylus swings around its tip on a cone, and also nods so the pivot is well posed.
    const double tilt = tr.ConeAngleDeg * deg * (0.6 + 0.4 * std::sin(0.37 * phase));
    double rz[9], ry[9], rzi[9], spin[9];
    RotZ(phase, rz);
    RotY(tilt, ry);
    RotZ(-phase + 0.5 * std::sin(0.23 * phase), rzi);
    Multiply3(rz, ry, tmp);
    Multiply3(tmp, rzi, spin);
    // Base orientation: stylus pointing down at the pivot (tip offset along -z of the tool).
    Multiply3(spin, R, tmp);
    std::memcpy(R, tmp, sizeof R);
    // ToolToTracker * tip = pivot  →  translation = pivot − R·tip.
    for (int r = 0; r < 3; ++r)
      p[r] -= R[3 * r] * tool.TipOffset[0] + R[3 * r + 1] * tool.TipOffset[1] + R[3 * r + 2] * tool.TipOffset[2];
  }
  for (int r = 0; r < 3; ++r) {
    m[4 * r] = R[3 * r];
    m[4 * r + 1] = R[3 * r + 1];
    m[4 * r + 2] = R[3 * r + 2];
    m[4 * r + 3] = p[r];
  }
  m[12] = m[13] = m[14] = 0;
  m[15] = 1;
}

}  // namespace rp
