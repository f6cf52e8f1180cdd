#include "rpPlusSequenceWriter.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "rpPlusSequenceFile.h"

namespace rp {

namespace {
constexpr size_t PaddedLineLength = 40;  // PLUS pads the fields it rewrites at the end to 40 characters
constexpr size_t CountWidth = 20;        // room for any frame count

bool EndsWithNrrd(const std::string& path) {
  if (path.size() < 5) return false;
  std::string end = path.substr(path.size() - 5);
  for (char& c : end) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return end == ".nrrd";
}

// Characters that would end or split a header line ("Key = Value", "key:=value").
char Safe(char c) { return (static_cast<unsigned char>(c) < 0x20 || c == 0x7F || c == '=' || c == ':') ? '_' : c; }

std::string SafeText(const std::string& text) {
  std::string out = text;
  for (char& c : out) c = Safe(c);
  return out;
}

// "<prefix><count>" padded with spaces: the count can be rewritten in place, whatever it grows to.
std::string CountLine(const std::string& prefix) {
  const size_t length = std::max(PaddedLineLength, prefix.size() + CountWidth);
  return prefix + "0" + std::string(length - prefix.size() - 1, ' ') + "\n";
}

std::string Sizes(const PlusSequenceLayout& layout) {
  std::string sizes;
  for (int v : layout.FrameSize) sizes += std::to_string(v) + " ";
  return sizes;
}
}  // namespace

PlusSequenceWriter::PlusSequenceWriter(Options options) : Opts(options) {}

PlusSequenceWriter::~PlusSequenceWriter() { this->Close(); }

bool PlusSequenceWriter::Create(const std::string& path, std::string& error, const PlusSequenceLayout& layout) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    error = "cannot write " + path + ": " + std::strerror(errno);
    return false;
  }
  return this->Open(fd, path, error, layout);
}

bool PlusSequenceWriter::Open(int fd, const std::string& path, std::string& error, const PlusSequenceLayout& layout) {
  this->Close();
  this->Fd = fd;
  this->FilePath = path;
  this->Problem.clear();
  this->Nrrd = EndsWithNrrd(path);
  this->Offset = this->CountOffset = this->FramesOnDisk = this->FramesBuffered = 0;
  this->BatchStart = -1;
  this->FrameOpen = false;
  this->Buffer.clear();
  this->Buffer.reserve(this->Opts.FlushBytes + (8u << 10));
  std::string header;
  const bool vector = layout.Channels != 1;
  if (this->Nrrd) {
    header = "NRRD0004\n# Complete NRRD file format specification at:\n# http://teem.sourceforge.net/nrrd/format.html\ntype: " +
             NrrdTypeOfElementType(layout.ElementType) + "\ndimension: " +
             std::to_string(layout.FrameSize.size() + 1 + (vector ? 1 : 0)) + "\n";
    const std::string sizes = "sizes: " + (vector ? std::to_string(layout.Channels) + " " : std::string()) + Sizes(layout);
    this->CountOffset = header.size() + sizes.size();
    header += CountLine(sizes) + "kinds: " + (vector ? "vector " : "");
    for (size_t i = 0; i < layout.FrameSize.size(); ++i) header += "domain ";
    header += "list\nendian: little\nencoding: raw\n";
    for (const auto& [key, value] : layout.Global) header += SafeText(key) + ":=" + SafeText(value) + "\n";
    this->Trailer = "\n";
  } else {
    header = "ObjectType = Image\nNDims = " + std::to_string(layout.FrameSize.size() + 1) +
             "\nBinaryData = True\nBinaryDataByteOrderMSB = False\nCompressedData = False\n";
    const std::string sizes = "DimSize = " + Sizes(layout);
    this->CountOffset = header.size() + sizes.size();
    header += CountLine(sizes);
    if (vector) header += "ElementNumberOfChannels = " + std::to_string(layout.Channels) + "\n";
    header += "ElementType = " + layout.ElementType + "\n";
    for (const auto& [key, value] : layout.Global) header += SafeText(key) + " = " + SafeText(value) + "\n";
    this->Trailer = "ElementDataFile = LOCAL\n";
  }
  header += this->Trailer;
  if (!this->WriteAt(0, header.data(), header.size())) {
    error = "cannot write " + path + ": " + std::strerror(errno);
    ::close(this->Fd);
    this->Fd = -1;
    return false;
  }
  this->Offset = header.size() - this->Trailer.size();
  return true;
}

bool PlusSequenceWriter::WriteAt(uint64_t offset, const char* data, size_t size) {
  while (size > 0) {
    const ssize_t n = ::pwrite(this->Fd, data, size, static_cast<off_t>(offset));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (n == 0) errno = ENOSPC;
      return false;
    }
    data += n;
    offset += static_cast<uint64_t>(n);
    size -= static_cast<size_t>(n);
  }
  return true;
}

void PlusSequenceWriter::Stop(const std::string& why) {
  const std::string frames = std::to_string(this->FramesOnDisk);
  this->Problem = "cannot write " + this->FilePath + " after " + frames + " frames: " + why + "; the " + frames +
                  " frames written are kept (a readable sequence)";
  this->Buffer.clear();
  this->FramesBuffered = 0;
}

void PlusSequenceWriter::AppendKey(const char* field, size_t fieldLength, const char* suffix) {
  char index[24];
  const int n = std::snprintf(index, sizeof index, "Seq_Frame%04llu_", static_cast<unsigned long long>(this->Frames()));
  this->Buffer.append(index, static_cast<size_t>(n));
  for (size_t i = 0; i < fieldLength; ++i) this->Buffer.push_back(field[i] == ' ' ? '_' : Safe(field[i]));  // a key is one word
  this->Buffer += suffix;
  this->Buffer += this->Nrrd ? ":=" : " = ";
}

void PlusSequenceWriter::AppendNumber(double value) {
  char text[32];
  const auto result = std::to_chars(text, text + sizeof text, value);  // shortest text that reads back exactly
  this->Buffer.append(text, result.ptr);
}

void PlusSequenceWriter::BeginFrame(double timestamp) {
  if (this->FrameOpen) this->Buffer.resize(this->FrameStart);  // a frame never ended: dropped
  this->FrameOpen = true;
  this->FrameStart = this->Buffer.size();
  this->FrameTime = timestamp;
}

void PlusSequenceWriter::AddTransform(const char* name, const double m[16], ToolState state) {
  if (!this->FrameOpen || this->Failed()) return;
  bool finite = true;
  for (int i = 0; i < 16; ++i) finite &= std::isfinite(m[i]);
  const size_t length = std::strlen(name);
  this->AppendKey(name, length, "Transform");
  for (int i = 0; i < 16; ++i) {
    if (i) this->Buffer.push_back(' ');
    this->AppendNumber(finite ? m[i] : (i % 5 == 0 ? 1.0 : 0.0));  // a broken pose reads as INVALID identity
  }
  this->Buffer.push_back('\n');
  this->AppendKey(name, length, "TransformStatus");
  this->Buffer += finite ? PlusToolStatusName(state) : "INVALID";
  this->Buffer.push_back('\n');
}

void PlusSequenceWriter::AddField(const std::string& name, const std::string& value) {
  if (!this->FrameOpen || this->Failed()) return;
  this->AppendKey(name.c_str(), name.size(), "");
  for (char c : value) this->Buffer.push_back(Safe(c));
  this->Buffer.push_back('\n');
}

bool PlusSequenceWriter::EndFrame() {
  if (!this->FrameOpen) return !this->Failed();
  this->FrameOpen = false;
  if (this->Fd < 0 || this->Failed()) {
    this->Buffer.resize(this->FrameStart);
    return false;
  }
  this->AppendKey("Timestamp", 9, "");
  this->AppendNumber(this->FrameTime);
  this->Buffer.push_back('\n');
  ++this->FramesBuffered;
  if (this->BatchStart < 0) this->BatchStart = this->FrameTime;
  if (this->Buffer.size() >= this->Opts.FlushBytes || this->FrameTime - this->BatchStart >= this->Opts.FlushSeconds)
    return this->WriteBatch();
  return true;
}

bool PlusSequenceWriter::WriteBatch() {
  this->BatchStart = -1;
  if (this->Fd < 0 || this->Failed()) return false;
  if (this->FramesBuffered == 0) return true;
  const size_t frameBytes = this->Buffer.size();
  this->Buffer += this->Trailer;
  // Reserve the batch's blocks first: a full disk says so here, before a byte of the file changes.
  if (::fallocate(this->Fd, FALLOC_FL_KEEP_SIZE, static_cast<off_t>(this->Offset), static_cast<off_t>(this->Buffer.size())) != 0 &&
      errno != EOPNOTSUPP && errno != ENODEV && errno != ENOSYS && errno != EINVAL && errno != ESPIPE) {
    this->Stop(std::strerror(errno));
    return false;
  }
  if (!this->WriteAt(this->Offset, this->Buffer.data(), this->Buffer.size())) {
    // No reservation here (a file system without fallocate): cut back to the last whole frame.
    const std::string why = std::strerror(errno);
    const bool restored = ::ftruncate(this->Fd, static_cast<off_t>(this->Offset + this->Trailer.size())) == 0 &&
                          this->WriteAt(this->Offset, this->Trailer.data(), this->Trailer.size());
    this->Stop(restored ? why : why + " (and the header's end could not be restored: the file may not read)");
    return false;
  }
  this->Offset += frameBytes;
  this->FramesOnDisk += this->FramesBuffered;
  this->FramesBuffered = 0;
  this->Buffer.clear();
  // The count, in place (its bytes exist already: nothing to allocate on a full disk).
  char count[CountWidth + 1];
  const int n = std::snprintf(count, sizeof count, "%llu", static_cast<unsigned long long>(this->FramesOnDisk));
  if (!this->WriteAt(this->CountOffset, count, static_cast<size_t>(n))) {
    this->Stop(std::string("the frame count: ") + std::strerror(errno));
    return false;
  }
  return true;
}

bool PlusSequenceWriter::Close(std::string* error, const std::vector<uint8_t>* pixels) {
  if (this->Fd < 0) return true;
  if (this->FrameOpen) {
    this->Buffer.resize(this->FrameStart);
    this->FrameOpen = false;
  }
  bool ok = this->WriteBatch();
  if (ok && pixels && !pixels->empty() &&
      !this->WriteAt(this->Offset + this->Trailer.size(), reinterpret_cast<const char*>(pixels->data()), pixels->size())) {
    this->Stop(std::string("the image data: ") + std::strerror(errno));
    ok = false;
  }
  if (::close(this->Fd) != 0 && ok) {
    this->Stop(std::strerror(errno));
    ok = false;
  }
  this->Fd = -1;
  if (!ok && error) *error = this->Problem;
  return ok;
}

}  // namespace rp
