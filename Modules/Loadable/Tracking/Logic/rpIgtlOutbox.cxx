#include "rpIgtlOutbox.h"

#include <cstring>

#include "rpIgtlProtocol.h"

namespace rp {

IgtlOutbox::Message* IgtlOutbox::Begin(const char* type, const std::string& name) {
  if (name.empty() || name.size() > MaxName) return nullptr;
  const int used = this->Used.load(std::memory_order_relaxed);
  int slot = 0;
  while (slot < used && (std::strcmp(this->KeyTypes[slot], type) != 0 || name != this->KeyNames[slot])) ++slot;
  if (slot == MaxMessages) return nullptr;
  if (slot == used) {  // the name's first use
    std::strncpy(this->KeyTypes[slot], type, sizeof this->KeyTypes[slot] - 1);
    std::memcpy(this->KeyNames[slot], name.data(), name.size());
  }
  this->PendingSlot = slot;
  std::memset(this->Pending.Type, 0, sizeof this->Pending.Type);
  std::memset(this->Pending.Name, 0, sizeof this->Pending.Name);
  std::strncpy(this->Pending.Type, type, sizeof this->Pending.Type - 1);
  std::memcpy(this->Pending.Name, name.data(), name.size());
  return &this->Pending;
}

void IgtlOutbox::Finish(int slot) {
  this->Slots[static_cast<size_t>(slot)].Publish(this->Pending);
  if (slot == this->Used.load(std::memory_order_relaxed)) this->Used.store(slot + 1, std::memory_order_release);
  this->Ready.Notify();
}

bool IgtlOutbox::PublishTransform(const std::string& name, const double m[16]) {
  Message* message = this->Begin("TRANSFORM", name);
  if (!message) return false;
  igtl::EncodeTransform(m, message->Content);
  message->ContentSize = static_cast<uint32_t>(igtl::TransformSize);
  this->Finish(this->PendingSlot);
  return true;
}

bool IgtlOutbox::PublishString(const std::string& name, const std::string& text) {
  if (igtl::StringHeaderSize + text.size() > MaxContent) return false;
  Message* message = this->Begin("STRING", name);
  if (!message) return false;
  igtl::EncodeString(text.data(), text.size(), message->Content);
  message->ContentSize = static_cast<uint32_t>(igtl::StringHeaderSize + text.size());
  this->Finish(this->PendingSlot);
  return true;
}

}  // namespace rp
