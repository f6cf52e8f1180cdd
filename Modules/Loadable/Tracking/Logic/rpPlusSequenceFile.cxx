#include "rpPlusSequenceFile.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "rpAtomicFile.h"
#include "rpPlusSequenceWriter.h"
#include "rpTrackingRecording.h"
#include "rpTransformNames.h"
#include "rpStrings.h"

namespace rp {

namespace {

constexpr const char* TransformSuffix = "Transform";
constexpr const char* StatusSuffix = "TransformStatus";
constexpr size_t MaxFrames = 1u << 24;  // far beyond any recording; bounds what a header can ask for

// MetaImage element types and their NRRD spellings, with their sizes (one table).
struct ElementTypeInfo {
  const char* Meta;
  const char* Nrrd;
  int Bytes;
};
const ElementTypeInfo ElementTypes[] = {
    {"MET_UCHAR", "unsigned char", 1}, {"MET_CHAR", "signed char", 1}, {"MET_USHORT", "unsigned short", 2},
    {"MET_SHORT", "short", 2},         {"MET_UINT", "unsigned int", 4}, {"MET_INT", "int", 4},
    {"MET_FLOAT", "float", 4},         {"MET_DOUBLE", "double", 8},     {"MET_OTHER", "", 1}};

const ElementTypeInfo* FindElementType(const std::string& name) {
  static const std::pair<const char*, const char*> nrrdAliases[] = {
      {"uchar", "unsigned char"}, {"uint8", "unsigned char"}, {"uint8_t", "unsigned char"}, {"char", "signed char"},
      {"int8", "signed char"},    {"int8_t", "signed char"},  {"ushort", "unsigned short"}, {"uint16", "unsigned short"},
      {"int16", "short"},         {"short int", "short"},     {"uint", "unsigned int"},     {"uint32", "unsigned int"},
      {"int32", "int"}};
  std::string n = name;
  for (const auto& alias : nrrdAliases)
    if (n == alias.first) n = alias.second;
  for (const ElementTypeInfo& t : ElementTypes)
    if (n == t.Meta || (t.Nrrd[0] && n == t.Nrrd)) return &t;
  return nullptr;
}

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

bool IsLayoutKey(const std::string& key) {
  static const char* keys[] = {"ObjectType", "NDims", "DimSize", "ElementType", "ElementDataFile", "BinaryData",
                               "BinaryDataByteOrderMSB", "CompressedData", "CompressedDataSize",
                               "ElementNumberOfChannels", "Kinds", "ElementByteOrderMSB"};
  for (const char* k : keys)
    if (key == k) return true;
  return false;
}

std::vector<long long> Integers(const std::string& text) {
  std::vector<long long> out;
  std::istringstream in(text);
  long long v;
  while (in >> v) out.push_back(v);
  return out;
}

/// Reads the header fields into `sequence`; the image layout fields into `layout`.
class HeaderReader {
 public:
  HeaderReader(const std::string& path, PlusSequence& sequence) : Path(path), Sequence(sequence) {}
  std::map<std::string, std::string> Layout;

  void Field(const std::string& key, const std::string& value, int line) {
    if (key.rfind("Seq_Frame", 0) == 0) return this->FrameField(key, value, line);
    if (IsLayoutKey(key)) {
      this->Layout[key] = value;
      return;
    }
    this->Sequence.Global.emplace_back(key, value);
  }

  void Finish(size_t frameCount) {
    if (this->Frames.empty() && frameCount == 0) return;
    const size_t used = this->Frames.empty() ? 0 : this->Frames.rbegin()->first + 1;
    if (used > frameCount)
      throw std::runtime_error(this->Path + ": Seq_Frame" + std::to_string(used - 1) + " beyond the " +
                               std::to_string(frameCount) + " frames the header declares");
    this->Sequence.Frames.resize(frameCount);
    for (auto& [index, frame] : this->Frames) {
      frame.Transforms.resize(this->Sequence.TransformNames.size());
      this->Sequence.Frames[index] = std::move(frame);
    }
    for (auto& frame : this->Sequence.Frames) frame.Transforms.resize(this->Sequence.TransformNames.size());
  }

 private:
  [[noreturn]] void Fail(int line, const std::string& what) const {
    throw std::runtime_error(this->Path + ":" + std::to_string(line) + ": " + what);
  }

  void FrameField(const std::string& key, const std::string& value, int line) {
    size_t at = 9;  // after "Seq_Frame"
    size_t index = 0;
    const size_t digits = at;
    while (at < key.size() && std::isdigit(static_cast<unsigned char>(key[at]))) {
      index = index * 10 + static_cast<size_t>(key[at] - '0');
      if (index >= MaxFrames) this->Fail(line, "frame number out of range in '" + key + "'");
      ++at;
    }
    if (at == digits || at >= key.size() || key[at] != '_') this->Fail(line, "expected Seq_FrameNNNN_<Field>, got '" + key + "'");
    const std::string name = key.substr(at + 1);
    PlusSequence::Frame& frame = this->Frames[index];
    if (name == "Timestamp") {
      char* end = nullptr;
      frame.Timestamp = std::strtod(value.c_str(), &end);
      if (end == value.c_str()) this->Fail(line, "timestamp '" + value + "' is not a number");
    } else if (EndsWith(name, StatusSuffix) && name.size() > std::strlen(StatusSuffix)) {
      this->Slot(frame, name.substr(0, name.size() - std::strlen(StatusSuffix))).State = ParsePlusToolStatus(value);
    } else if (EndsWith(name, TransformSuffix) && name.size() > std::strlen(TransformSuffix)) {
      PlusSequence::Transform& t = this->Slot(frame, name.substr(0, name.size() - std::strlen(TransformSuffix)));
      std::istringstream in(value);
      int n = 0;
      while (n < 16 && in >> t.Matrix[n]) ++n;
      std::string extra;
      if (n != 16 || (in >> extra))
        this->Fail(line, "transform '" + name + "' needs 16 numbers (a row-major 4x4 matrix)");
      t.Present = true;
    } else {
      frame.Fields.emplace_back(name, value);
    }
  }

  PlusSequence::Transform& Slot(PlusSequence::Frame& frame, const std::string& transform) {
    const size_t index = static_cast<size_t>(this->Sequence.AddTransform(transform));
    if (frame.Transforms.size() <= index) frame.Transforms.resize(index + 1);
    return frame.Transforms[index];
  }

  std::string Path;
  PlusSequence& Sequence;
  std::map<size_t, PlusSequence::Frame> Frames;
};

/// Size of the frame image and the frame count from the layout; throws on a bad layout.
size_t ApplyLayout(const std::string& path, const std::vector<long long>& sizes, const std::string& elementType,
                   int channels, PlusSequence& s) {
  if (sizes.size() < 2 || sizes.size() > 5) throw std::runtime_error(path + ": expected 2 to 5 image sizes (the last is the frame count)");
  for (long long v : sizes)
    if (v < 0 || v > (1 << 24)) throw std::runtime_error(path + ": image size " + std::to_string(v) + " out of range");
  const ElementTypeInfo* type = FindElementType(elementType);
  if (!type) throw std::runtime_error(path + ": unknown element type '" + elementType + "'");
  if (channels < 1 || channels > 64) throw std::runtime_error(path + ": " + std::to_string(channels) + " channels per voxel");
  s.ElementType = type->Meta;
  s.Channels = channels;
  s.FrameSize.assign(sizes.begin(), sizes.end() - 1);
  const size_t frames = static_cast<size_t>(sizes.back());
  if (frames > MaxFrames) throw std::runtime_error(path + ": " + std::to_string(frames) + " frames");
  return frames;
}

/// Keeps (or checks the presence of) the pixel block that starts at `at`.
void ReadPixels(const std::string& path, const std::string& data, size_t at, bool raw, bool keep, PlusSequence& s) {
  const uint64_t bytes = s.FrameBytes() * s.Frames.size();
  if (!raw) {
    if (keep && bytes) throw std::runtime_error(path + ": compressed image data is not read (tracking data was)");
    return;
  }
  if (data.size() < at || data.size() - at < bytes)
    throw std::runtime_error(path + ": image data truncated: " + std::to_string(bytes) + " bytes expected, " +
                             std::to_string(data.size() > at ? data.size() - at : 0) + " present");
  if (keep) s.Pixels.assign(data.begin() + static_cast<std::ptrdiff_t>(at), data.begin() + static_cast<std::ptrdiff_t>(at + bytes));
}

PlusSequence ParseMetaImage(const std::string& path, const std::string& data, bool keepPixels) {
  PlusSequence s;
  HeaderReader reader(path, s);
  size_t at = 0;
  int line = 0;
  bool dataFileSeen = false;
  while (at < data.size() && !dataFileSeen) {
    size_t end = data.find('\n', at);
    if (end == std::string::npos) end = data.size();
    const std::string text = data.substr(at, end - at);
    at = std::min(data.size(), end + 1);
    ++line;
    if (Trim(text).empty()) continue;
    const size_t eq = text.find('=');
    if (eq == std::string::npos) throw std::runtime_error(path + ":" + std::to_string(line) + ": expected 'Key = Value'");
    const std::string key = Trim(text.substr(0, eq));
    reader.Field(key, Trim(text.substr(eq + 1)), line);
    dataFileSeen = key == "ElementDataFile";
  }
  const auto& layout = reader.Layout;
  if (!layout.count("DimSize") || !layout.count("ElementType"))
    throw std::runtime_error(path + ": not a MetaImage sequence (no DimSize/ElementType header field)");
  const int channels = layout.count("ElementNumberOfChannels") ? std::atoi(layout.at("ElementNumberOfChannels").c_str()) : 1;
  const size_t frames = ApplyLayout(path, Integers(layout.at("DimSize")), layout.at("ElementType"), channels, s);
  reader.Finish(frames);
  const bool compressed = layout.count("CompressedData") && Lower(layout.at("CompressedData")) == "true";
  const bool local = dataFileSeen && Lower(reader.Layout.at("ElementDataFile")) == "local";
  if (!dataFileSeen) throw std::runtime_error(path + ": no ElementDataFile field (the header's last line)");
  ReadPixels(path, data, at, local && !compressed, keepPixels && local, s);
  return s;
}

PlusSequence ParseNrrd(const std::string& path, const std::string& data, bool keepPixels) {
  PlusSequence s;
  HeaderReader reader(path, s);
  std::map<std::string, std::string> fields;
  size_t at = data.find('\n') + 1;  // after "NRRD000N"
  int line = 1;
  while (at < data.size()) {
    size_t end = data.find('\n', at);
    if (end == std::string::npos) end = data.size();
    std::string text = data.substr(at, end - at);
    at = std::min(data.size(), end + 1);
    ++line;
    if (!text.empty() && text.back() == '\r') text.pop_back();
    if (text.empty()) break;  // the blank line before the data
    if (text[0] == '#') continue;
    const size_t kv = text.find(":=");
    const size_t colon = text.find(": ");
    if (kv != std::string::npos && (colon == std::string::npos || kv < colon)) {
      reader.Field(Trim(text.substr(0, kv)), Trim(text.substr(kv + 2)), line);
    } else if (colon != std::string::npos) {
      fields[Lower(Trim(text.substr(0, colon)))] = Trim(text.substr(colon + 2));
    } else {
      throw std::runtime_error(path + ":" + std::to_string(line) + ": expected 'field: value' or 'key:=value'");
    }
  }
  if (!fields.count("sizes") || !fields.count("type"))
    throw std::runtime_error(path + ": NRRD header without 'sizes' or 'type'");
  std::vector<long long> sizes = Integers(fields["sizes"]);
  int channels = 1;
  const std::vector<std::string> kinds = [&] {
    std::vector<std::string> k;
    std::istringstream in(fields["kinds"]);
    std::string w;
    while (in >> w) k.push_back(w);
    return k;
  }();
  if (!kinds.empty() && kinds.size() == sizes.size() && kinds.front() == "vector" && sizes.size() > 2) {
    channels = static_cast<int>(sizes.front());  // PLUS puts the components first
    sizes.erase(sizes.begin());
  }
  const size_t frames = ApplyLayout(path, sizes, fields["type"], channels, s);
  reader.Finish(frames);
  const std::string encoding = Lower(fields.count("encoding") ? fields["encoding"] : "raw");
  const bool attached = !fields.count("data file") && !fields.count("datafile");
  ReadPixels(path, data, at, attached && encoding == "raw", keepPixels && attached, s);
  return s;
}

}  // namespace

const char* PlusToolStatusName(ToolState state) {
  switch (state) {
    case ToolState::OK: return "OK";
    case ToolState::OutOfVolume: return "OUT_OF_VOLUME";
    case ToolState::Missing: return "MISSING";
    case ToolState::Disabled: return "INVALID";
  }
  return "INVALID";
}

ToolState ParsePlusToolStatus(const std::string& text) {
  const std::string t = Trim(text);
  if (t == "OK") return ToolState::OK;
  if (t == "OUT_OF_VOLUME") return ToolState::OutOfVolume;
  if (t == "DISABLED") return ToolState::Disabled;
  return ToolState::Missing;
}

uint64_t PlusSequence::FrameBytes() const {
  const ElementTypeInfo* type = FindElementType(this->ElementType);
  uint64_t n = static_cast<uint64_t>(type ? type->Bytes : 1) * static_cast<uint64_t>(std::max(1, this->Channels));
  for (int v : this->FrameSize) n *= static_cast<uint64_t>(std::max(0, v));
  return n;
}

int PlusSequence::TransformIndex(const std::string& name) const {
  const auto it = std::find(this->TransformNames.begin(), this->TransformNames.end(), name);
  return it == this->TransformNames.end() ? -1 : static_cast<int>(it - this->TransformNames.begin());
}

int PlusSequence::AddTransform(const std::string& name) {
  const int index = this->TransformIndex(name);
  if (index >= 0) return index;
  this->TransformNames.push_back(name);
  return static_cast<int>(this->TransformNames.size()) - 1;
}

Recording PlusSequence::ToRecording() const {
  Recording r;
  r.Tools = this->TransformNames;
  for (size_t f = 0; f < this->Frames.size(); ++f) {
    const Frame& frame = this->Frames[f];
    for (size_t t = 0; t < frame.Transforms.size(); ++t) {
      if (!frame.Transforms[t].Present) continue;
      Recording::Sample sample;
      sample.Time = frame.Timestamp;
      sample.Tool = static_cast<int>(t);
      sample.Pose.FromMatrix(frame.Transforms[t].Matrix);
      sample.Pose.State = frame.Transforms[t].State;
      sample.Pose.Timestamp = frame.Timestamp;
      sample.Pose.Frame = static_cast<uint32_t>(f);
      r.Samples.push_back(sample);
    }
  }
  return r;
}

PlusSequence PlusSequence::FromRecording(const Recording& recording) {
  // One frame per distinct time stamp (the tools a tracker reports together share it).
  PlusSequence s;
  for (const std::string& tool : recording.Tools) s.AddTransform(ToolToTrackerName(tool));
  for (const Recording::Sample& sample : recording.Samples) {
    if (s.Frames.empty() || s.Frames.back().Timestamp != sample.Time) {
      s.Frames.emplace_back();
      s.Frames.back().Timestamp = sample.Time;
      s.Frames.back().Transforms.resize(s.TransformNames.size());
    }
    PlusSequence::Transform& t = s.Frames.back().Transforms[static_cast<size_t>(sample.Tool)];
    sample.Pose.ToMatrix(t.Matrix);
    t.State = sample.Pose.State;
    t.Present = true;
  }
  return s;
}

std::string NrrdTypeOfElementType(const std::string& elementType) {
  const ElementTypeInfo* type = FindElementType(elementType);
  return type && type->Nrrd[0] ? type->Nrrd : "unsigned char";
}

bool IsPlusSequenceFileName(const std::string& path) {
  const std::string p = Lower(path);
  return EndsWith(p, ".mha") || EndsWith(p, ".mhd") || EndsWith(p, ".nrrd");
}

PlusSequence ReadPlusSequence(const std::string& path, bool keepPixels) {
  std::string data, error;
  if (!ReadFile(path, data, error)) throw std::runtime_error(error);
  if (data.rfind("NRRD", 0) == 0) return ParseNrrd(path, data, keepPixels);
  return ParseMetaImage(path, data, keepPixels);
}

void WritePlusSequence(const PlusSequence& s, const std::string& path) {
  const std::string p = Lower(path);
  if (!EndsWith(p, ".nrrd") && !EndsWith(p, ".mha"))
    throw std::runtime_error("cannot write " + path + ": a PLUS sequence is written as .igs.mha or .igs.nrrd");
  const uint64_t bytes = s.FrameBytes() * s.Frames.size();
  if (!s.Pixels.empty() && s.Pixels.size() != bytes)
    throw std::runtime_error("cannot write " + path + ": " + std::to_string(s.Pixels.size()) + " bytes of pixels for " +
                             std::to_string(bytes) + " expected");
  PlusSequenceLayout layout;
  layout.Global = s.Global;
  layout.FrameSize = s.FrameSize;
  layout.ElementType = s.ElementType;
  layout.Channels = s.Channels;
  const std::vector<uint8_t> zeros(s.Pixels.empty() ? static_cast<size_t>(bytes) : 0, 0);
  std::string error;
  const bool written = WriteAtomicallyWith(
      path,
      [&](const std::string& temporary, std::string& e) {
        PlusSequenceWriter writer;
        if (!writer.Create(temporary, e, layout)) return false;
        for (const PlusSequence::Frame& frame : s.Frames) {
          writer.BeginFrame(frame.Timestamp);
          for (size_t t = 0; t < s.TransformNames.size() && t < frame.Transforms.size(); ++t)
            if (frame.Transforms[t].Present)
              writer.AddTransform(s.TransformNames[t].c_str(), frame.Transforms[t].Matrix, frame.Transforms[t].State);
          for (const auto& field : frame.Fields) writer.AddField(field.first, field.second);
          writer.EndFrame();
        }
        return writer.Close(&e, s.Pixels.empty() ? &zeros : &s.Pixels);
      },
      error);
  if (!written) throw std::runtime_error("cannot write " + path + ": " + error);
}

}  // namespace rp
