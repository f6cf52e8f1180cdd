#include "rpImageTable.h"

#include <cstring>

namespace rp {

// The frame numbers its scalar types as OpenIGTLink's IMAGE does: the wire format's sizes.
size_t ImageFrame::ScalarBytes(uint8_t type) { return igtl::ImageHeader::ScalarBytes(type); }

size_t ImageFrame::ByteCount() const {
  return static_cast<size_t>(this->Dimensions[0]) * this->Dimensions[1] * this->Dimensions[2] * this->Components *
         ScalarBytes(this->ScalarType);
}

bool ImageFrame::SameLayout(const ImageFrame& o) const {
  return std::memcmp(this->Dimensions, o.Dimensions, sizeof this->Dimensions) == 0 && this->Components == o.Components &&
         this->ScalarType == o.ScalarType;
}

int ImageTable::FindOrAdd(const char* name, size_t length) noexcept {
  if (length >= NameLength) length = NameLength - 1;
  const int n = this->NumberOfSlots.load(std::memory_order_relaxed);
  for (int i = 0; i < n; ++i)
    if (std::strncmp(this->Slots[i].Name, name, length) == 0 && this->Slots[i].Name[length] == '\0') return i;
  if (n >= Capacity) return -1;
  std::memcpy(this->Slots[n].Name, name, length);
  this->Slots[n].Name[length] = '\0';
  this->NumberOfSlots.store(n + 1, std::memory_order_release);
  return n;
}

ImageFrame& ImageTable::BeginWrite(int slot) noexcept {
  Slot& s = this->Slots[slot];
  return s.Frames[s.Writing];
}

const ImageFrame* ImageTable::LastPublished(int slot) const noexcept {
  const Slot& s = this->Slots[slot];
  return s.Last < 0 ? nullptr : &s.Frames[s.Last];
}

void ImageTable::EndWrite(int slot) noexcept {
  Slot& s = this->Slots[slot];
  s.Last = s.Writing;
  // Hand the filled frame over; take back whichever frame waited (the reader has not got it).
  s.Writing = static_cast<int>(s.Waiting.exchange(static_cast<uint32_t>(s.Writing) | Fresh, std::memory_order_acq_rel) & 3u);
  s.Published.fetch_add(1, std::memory_order_release);
}

const ImageFrame* ImageTable::TakeNewest(int slot, uint64_t* published) const noexcept {
  Slot& s = this->Slots[slot];
  if (published) *published = s.Published.load(std::memory_order_acquire);
  if (!(s.Waiting.load(std::memory_order_acquire) & Fresh)) return nullptr;
  s.Reading = static_cast<int>(s.Waiting.exchange(static_cast<uint32_t>(s.Reading), std::memory_order_acq_rel) & 3u);
  return &s.Frames[s.Reading];
}

}  // namespace rp
