#pragma once
// PLUS tracked-frame sequence files (`.igs.mha`, `.igs.mhd`, `.igs.nrrd`): what PLUS's Capture
// and StartRecording write, and what fCal, PLUS's tests and SlicerIGT's Sequences read. A
// MetaImage (`Key = Value`) or NRRD (`key: value`, `key:=value`) header whose per-frame fields
// are `Seq_FrameNNNN_<Name>`: `<From>To<To>Transform` (16 numbers, row-major), its
// `...TransformStatus` (OK, MISSING, OUT_OF_VIEW, INVALID, ...), `Timestamp`, `ImageStatus`, and
// any other field (kept as text). Global fields (`UltrasoundImageOrientation`, ...) are kept in
// order. The image data is `DimSize` X × Y × frames of `ElementType`: often empty (tracking only,
// `DimSize = 0 0 N`); when present it is kept (or skipped) as raw bytes, never interpreted here.
//
// Reading never trusts the file: a frame index beyond the declared count, a transform with the
// wrong number of values, a missing or truncated pixel block are errors naming the file and line.
// The same text is the PLUS naming of the server's transforms, so ToolState <-> PLUS status
// strings live here once.
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "rpToolPose.h"

namespace rp {

struct Recording;

/// PLUS's status string of a tool state (OK, MISSING, OUT_OF_VOLUME, INVALID), as PLUS writes it
/// in sequence files and in OpenIGTLink `TransformStatus` metadata.
const char* PlusToolStatusName(ToolState state);
/// A PLUS status string to a tool state (OUT_OF_VIEW, REQ_TIMEOUT, INVALID, ... are Missing).
ToolState ParsePlusToolStatus(const std::string& text);

struct PlusSequence {
  struct Transform {
    double Matrix[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};  // row-major, From → To
    ToolState State = ToolState::Missing;
    bool Present = false;  // the frame has this transform
  };
  struct Frame {
    double Timestamp = 0;
    std::vector<Transform> Transforms;                       // one per TransformNames entry
    std::vector<std::pair<std::string, std::string>> Fields;  // other per-frame fields, as written
  };
  std::vector<std::pair<std::string, std::string>> Global;  // header fields other than the image layout
  std::vector<std::string> TransformNames;                  // "StylusToTracker" (without "Transform")
  std::vector<Frame> Frames;
  // Image layout and pixels (empty for tracking-only files).
  std::vector<int> FrameSize = {0, 0};  // voxels per frame along each axis (DimSize without the frames)
  std::string ElementType = "MET_UCHAR";  // MetaImage spelling (NRRD types are mapped to it)
  int Channels = 1;
  std::vector<uint8_t> Pixels;  // FrameSize product × Channels × element bytes × frames, when kept
  /// Bytes of one frame's image (0 for tracking-only files).
  uint64_t FrameBytes() const;

  int TransformIndex(const std::string& name) const;  // -1 when absent
  int AddTransform(const std::string& name);
  /// Pose-by-pose view for replay, pivot and landmark collection: each transform is a tool
  /// named as the transform ("StylusToTracker"); frames without it are skipped.
  Recording ToRecording() const;
  static PlusSequence FromRecording(const Recording& recording);
};

/// Reads `.mha`/`.mhd`/`.nrrd`. `keepPixels`: read the image data into Pixels (else skipped).
/// Throws std::runtime_error naming the file (and line) on anything it cannot read.
PlusSequence ReadPlusSequence(const std::string& path, bool keepPixels = false);
/// Writes atomically, as a MetaImage (`.mha`, pixels inline) or NRRD (`.nrrd`) by the extension,
/// through PlusSequenceWriter (rpPlusSequenceWriter.h: the one place the layout is written).
void WritePlusSequence(const PlusSequence& sequence, const std::string& path);
/// The NRRD spelling of a MetaImage element type ("MET_SHORT" -> "short").
std::string NrrdTypeOfElementType(const std::string& elementType);
/// True for the file names read as PLUS sequences (.mha, .mhd, .nrrd, also .igs.*).
bool IsPlusSequenceFileName(const std::string& path);

}  // namespace rp
