#pragma once
// Upstream OpenIGTLink's receive path, as ReceiveClient, PLUS and Slicer do it: the header, then a
// body buffer of exactly the announced size, then Unpack with the CRC check. Messages of other
// types are skipped (at most `maxSkipped`). Shared by rpIgtlUpstreamTest and rpUpstreamIgtlClient.
#include <cstring>

#include <igtlMessageHeader.h>
#include <igtlSocket.h>

namespace rptest {

/// The next message of `type`, unpacked (`result`: upstream's Unpack flags); null on a closed
/// socket, a timeout or too many other messages.
template <class M>
typename M::Pointer UpstreamReceive(::igtl::Socket* socket, const char* type, int& result, int maxSkipped = 200) {
  for (int i = 0; i < maxSkipped; ++i) {
    auto header = ::igtl::MessageHeader::New();
    header->InitBuffer();
    bool timeout = false;
    if (socket->Receive(header->GetBufferPointer(), header->GetBufferSize(), timeout) != header->GetBufferSize()) return nullptr;
    header->Unpack();
    if (std::strcmp(header->GetDeviceType(), type) != 0) {
      socket->Skip(header->GetBodySizeToRead(), 0);
      continue;
    }
    auto message = M::New();
    message->SetMessageHeader(header);
    message->AllocateBuffer();
    if (socket->Receive(message->GetBufferBodyPointer(), message->GetBufferBodySize(), timeout) != message->GetBufferBodySize())
      return nullptr;
    result = message->Unpack(1);
    return message;
  }
  return nullptr;
}

}  // namespace rptest
