#pragma once
// Writes a PLUS tracked-frame sequence (.igs.mha / .igs.nrrd, rpPlusSequenceFile.h) frame by
// frame as frames come, as PLUS's sequence writers do: the header is written first with the
// frame count padded (`DimSize = 0 0 N`, `sizes: 0 0 N`, PLUS's 40-character field), frames are
// appended in batches (64 KiB or one second of frames) and the count is written in place after
// each batch, so memory stays flat however long a recording runs and the file on disk is a
// readable sequence of every frame written so far (the header's end, `ElementDataFile = LOCAL`
// or NRRD's blank line, is rewritten after each batch).
//
// A batch's blocks are reserved (fallocate) before it is written: a full disk refuses the
// reservation and the file stays as it was, readable, with every frame of the earlier batches;
// the writer then stops (Failed(), Error() names the file and the reason) and drops what follows.
// Where reservation is not supported, a short write is cut back to the last whole frame.
// Names and values that would break a line of the header (control characters, '=', ':') are
// written with '_' in their place. Not thread-safe: one thread writes.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "rpToolPose.h"

namespace rp {

/// What a sequence's header holds besides the frames: global fields and the image layout
/// (tracking-only by default: DimSize 0 0 N, MET_UCHAR).
struct PlusSequenceLayout {
  std::vector<std::pair<std::string, std::string>> Global;
  std::vector<int> FrameSize = {0, 0};
  std::string ElementType = "MET_UCHAR";
  int Channels = 1;
};

class PlusSequenceWriter {
 public:
  struct Options {
    size_t FlushBytes = 64u << 10;  // a batch goes to disk at this size ...
    double FlushSeconds = 1.0;      // ... or when its first frame is this old (frame time stamps)
  };
  PlusSequenceWriter() : PlusSequenceWriter(Options()) {}
  explicit PlusSequenceWriter(Options options);
  ~PlusSequenceWriter();
  PlusSequenceWriter(const PlusSequenceWriter&) = delete;
  PlusSequenceWriter& operator=(const PlusSequenceWriter&) = delete;

  /// Takes `fd` (a new, empty file open for writing; closed by Close) and writes the header.
  /// `path` names the file in messages; its extension chooses the format (.nrrd, else .mha).
  bool Open(int fd, const std::string& path, std::string& error, const PlusSequenceLayout& layout = {});
  /// Creates (or truncates) `path` and opens it.
  bool Create(const std::string& path, std::string& error, const PlusSequenceLayout& layout = {});
  bool IsOpen() const { return this->Fd >= 0; }

  /// One frame: BeginFrame, AddTransform/AddField for what it holds, EndFrame. EndFrame is false
  /// once the writer has stopped (see Error()); frames are then dropped.
  void BeginFrame(double timestamp);
  void AddTransform(const char* name, const double rowMajor[16], ToolState state);
  void AddField(const std::string& name, const std::string& value);
  bool EndFrame();

  /// Writes the last batch and the frame count, appends `pixels` (the image data of every
  /// frame, when the layout has images) and closes. False with `error` when anything failed
  /// (the file then holds the frames written before the failure).
  bool Close(std::string* error = nullptr, const std::vector<uint8_t>* pixels = nullptr);

  uint64_t FramesWritten() const { return this->FramesOnDisk; }     // on disk, in the header's count
  uint64_t Frames() const { return this->FramesOnDisk + this->FramesBuffered; }
  bool Failed() const { return !this->Problem.empty(); }
  const std::string& Error() const { return this->Problem; }
  const std::string& Path() const { return this->FilePath; }
  /// Bytes held in memory (the batch buffer's capacity): bounded, whatever the length.
  size_t BufferCapacity() const { return this->Buffer.capacity(); }

 private:
  bool WriteBatch();
  bool WriteAt(uint64_t offset, const char* data, size_t size);
  void Stop(const std::string& why);
  void AppendKey(const char* field, size_t fieldLength, const char* suffix);
  void AppendNumber(double value);

  Options Opts;
  int Fd = -1;
  bool Nrrd = false;
  std::string FilePath, Problem;
  std::string Trailer;           // the header's last line, after the frames
  std::string Buffer;            // frames not written yet (whole frames only, after EndFrame)
  size_t FrameStart = 0;         // where the open frame begins in Buffer
  double FrameTime = 0, BatchStart = -1;
  uint64_t Offset = 0;           // end of the last whole frame on disk (the trailer starts here)
  uint64_t CountOffset = 0;      // where the frame count is written
  uint64_t FramesOnDisk = 0, FramesBuffered = 0;
  bool FrameOpen = false;
};

}  // namespace rp
