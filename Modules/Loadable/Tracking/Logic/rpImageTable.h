#pragma once
// Images streamed by a device (OpenIGTLink IMAGE: tracked ultrasound, live slices) handed from
// the I/O thread to the main thread as poses are: one writer, newest wins, the reader never
// blocks the writer. Each named slot is a triple buffer of frames (the writer fills one, one
// waits with the newest, the reader holds one), so a frame of megabytes is never copied under
// a lock nor read while it is written. The writer allocates only when a frame's size changes.
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "rpIgtlProtocol.h"

namespace rp {

/// One whole image in the host's byte order, with its geometry in RAS.
struct ImageFrame {
  /// Scalar types, numbered as OpenIGTLink's IMAGE (the wire format's numbers and sizes).
  enum Scalar : uint8_t {
    Int8 = igtl::ImageHeader::Int8,
    UInt8 = igtl::ImageHeader::UInt8,
    Int16 = igtl::ImageHeader::Int16,
    UInt16 = igtl::ImageHeader::UInt16,
    Int32 = igtl::ImageHeader::Int32,
    UInt32 = igtl::ImageHeader::UInt32,
    Float32 = igtl::ImageHeader::Float32,
    Float64 = igtl::ImageHeader::Float64
  };
  int Dimensions[3] = {0, 0, 0};
  int Components = 1;
  uint8_t ScalarType = UInt8;
  double IjkToRas[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};  // row-major
  double Timestamp = 0;    // sender's time stamp (seconds since 1970)
  double ReceiveTime = 0;  // SteadySeconds() when it arrived
  std::vector<uint8_t> Pixels;

  static size_t ScalarBytes(uint8_t scalarType);
  size_t ByteCount() const;
  /// Same dimensions, components and scalar type.
  bool SameLayout(const ImageFrame& other) const;
};

class ImageTable {
 public:
  static constexpr int Capacity = 8;
  static constexpr int NameLength = 64;

  // ---- writer (one thread)
  /// Slot of a device name, registered when new; -1 when the table is full.
  int FindOrAdd(const char* name, size_t length) noexcept;
  /// The frame to fill for `slot` (the writer's own buffer: it holds an older frame).
  ImageFrame& BeginWrite(int slot) noexcept;
  /// The frame published last for `slot` (nullptr before the first): what a sub-volume update
  /// patches. Read-only: the reader may be reading it too.
  const ImageFrame* LastPublished(int slot) const noexcept;
  /// Publishes the frame filled since BeginWrite.
  void EndWrite(int slot) noexcept;

  // ---- reader (one thread)
  int Count() const noexcept { return this->NumberOfSlots.load(std::memory_order_acquire); }
  const char* Name(int slot) const noexcept { return this->Slots[slot].Name; }
  /// The newest frame if one was published since the last call for this slot, else nullptr.
  /// Valid until the next call for the slot. `published`: frames published so far.
  /// (const: the reader's hand-over state changes, never the frames the writer sees.)
  const ImageFrame* TakeNewest(int slot, uint64_t* published = nullptr) const noexcept;

 private:
  static constexpr uint32_t Fresh = 4;  // flag beside the index (0..2) of the waiting frame
  struct Slot {
    char Name[NameLength] = {};
    ImageFrame Frames[3];
    std::atomic<uint32_t> Waiting{1};  // index of the frame between writer and reader (+ Fresh)
    std::atomic<uint64_t> Published{0};
    int Writing = 0;       // writer only
    int Last = -1;         // writer only: index published last
    int Reading = 2;       // reader only
  };
  mutable Slot Slots[Capacity];  // mutable for the reader's TakeNewest (the hand-over indices)
  std::atomic<int> NumberOfSlots{0};
};

}  // namespace rp
