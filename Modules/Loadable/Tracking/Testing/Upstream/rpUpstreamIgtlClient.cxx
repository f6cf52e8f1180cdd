// A Slicer-like OpenIGTLink client made of upstream OpenIGTLink 3.x only (the oracle: the
// library PLUS and Slicer's OpenIGTLinkIF are built on), run by rpIgtlNetworkTest as a second
// process standing for another machine: its socket is bound to --from (e.g. 127.0.0.2) before it
// connects, so the server sees that address. It sends a first STATUS in header v2 (as Slicer's
// connector does), then runs its actions in the order given, printing what upstream decoded
// (CRC checked):
//   --wait NAME          the next TRANSFORM named NAME ("*": any) -> TRANSFORM <name> <status> <x> <y> <z>
//   --wait-change NAME   TRANSFORMs named NAME until one is 1 mm from the last printed (3 s) -> TRANSFORM ...
//   --command XML        an upstream CommandMessage; the RTS_COMMAND answering it -> REPLY <id> <Status> <Message>
//   --sleep MS
// Anything that does not come prints ERROR <what> and exits 1.
//
// Usage: rpUpstreamIgtlClient --from ADDR --to ADDR --port N [actions...]
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include <igtlClientSocket.h>
#include <igtlCommandMessage.h>
#include <igtlMessageHeader.h>
#include <igtlStatusMessage.h>
#include <igtlTransformMessage.h>

#include "rpUpstreamReceive.h"

namespace {

// upstream's ClientSocket, bound to a chosen local address before it connects.
class BoundClientSocket : public igtl::ClientSocket {
 public:
  using Pointer = igtl::SmartPointer<BoundClientSocket>;
  static Pointer New() {
    Pointer socket = new BoundClientSocket;
    socket->UnRegister();
    return socket;
  }
  bool ConnectFrom(const std::string& from, const std::string& to, int port) {
    this->m_SocketDescriptor = this->CreateSocket();
    sockaddr_in local{};
    local.sin_family = AF_INET;
    if (this->m_SocketDescriptor < 0 || inet_pton(AF_INET, from.c_str(), &local.sin_addr) != 1 ||
        ::bind(this->m_SocketDescriptor, reinterpret_cast<sockaddr*>(&local), sizeof local) != 0)
      return false;
    return this->Connect(this->m_SocketDescriptor, to.c_str(), port) == 0;
  }
};

int Fail(const std::string& what) {
  std::printf("ERROR %s\n", what.c_str());
  std::fflush(stdout);
  return 1;
}

// The next message of `type` (others are skipped), unpacked by upstream with its CRC check.
template <class M>
typename M::Pointer Receive(igtl::Socket* socket, const char* type) {
  int result = 0;
  auto message = rptest::UpstreamReceive<M>(socket, type, result, 2000);
  return message && (result & igtl::MessageHeader::UNPACK_BODY) ? message : nullptr;
}

}  // namespace

int main(int argc, char** argv) {
  std::string from = "127.0.0.1", to = "127.0.0.1";
  int port = 18944;
  std::vector<std::pair<std::string, std::string>> actions;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--from") from = value;
    else if (key == "--to") to = value;
    else if (key == "--port") port = std::atoi(value.c_str());
    else if (key == "--wait" || key == "--wait-change" || key == "--command" || key == "--sleep") actions.emplace_back(key, value);
    else return Fail("unknown argument " + key);
  }
  auto socket = BoundClientSocket::New();
  bool connected = false;
  for (int attempt = 0; attempt < 300 && !connected; ++attempt) {  // the server may still be starting
    connected = socket->ConnectFrom(from, to, port);
    if (!connected) {
      socket->CloseSocket();
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
  if (!connected) return Fail("cannot connect from " + from + " to " + to + ":" + std::to_string(port));
  socket->SetReceiveTimeout(5000);

  auto hello = igtl::StatusMessage::New();  // Slicer's first message: header v2 from now on
  hello->SetHeaderVersion(2);
  hello->SetDeviceName("Slicer");
  hello->SetCode(igtl::StatusMessage::STATUS_OK);
  hello->Pack();
  if (!socket->Send(hello->GetPackPointer(), hello->GetPackSize())) return Fail("cannot send STATUS");

  unsigned id = 100;
  double last[3] = {NAN, NAN, NAN};
  for (const auto& [action, value] : actions) {
    if (action == "--sleep") {
      std::this_thread::sleep_for(std::chrono::milliseconds(std::atoi(value.c_str())));
    } else if (action == "--wait" || action == "--wait-change") {
      const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(3);
      for (;;) {
        auto transform = Receive<igtl::TransformMessage>(socket, "TRANSFORM");
        if (!transform || std::chrono::steady_clock::now() > deadline) return Fail("no TRANSFORM " + value + " (" + action + ")");
        if (value != "*" && value != transform->GetDeviceName()) continue;
        igtl::Matrix4x4 m;
        transform->GetMatrix(m);
        const double moved = std::sqrt(std::pow(m[0][3] - last[0], 2) + std::pow(m[1][3] - last[1], 2) + std::pow(m[2][3] - last[2], 2));
        if (action == "--wait-change" && !(moved > 1.0)) continue;
        std::string status = "(none)";
        transform->GetMetaDataElement("TransformStatus", status);
        std::printf("TRANSFORM %s %s %.4f %.4f %.4f\n", transform->GetDeviceName(), status.c_str(), m[0][3], m[1][3], m[2][3]);
        for (int r = 0; r < 3; ++r) last[r] = m[r][3];
        break;
      }
    } else {
      auto command = igtl::CommandMessage::New();
      command->SetHeaderVersion(2);
      command->SetDeviceName("OpenIGTLinkRemote");
      command->SetCommandId(++id);
      command->SetCommandName("Command");
      command->SetCommandContent(value);
      command->SetMetaDataElement("MRMLNodeName", IANA_TYPE_US_ASCII, "OpenIGTLinkRemote");
      command->Pack();
      if (!socket->Send(command->GetPackPointer(), command->GetPackSize())) return Fail("cannot send COMMAND");
      auto reply = Receive<igtl::RTSCommandMessage>(socket, "RTS_COMMAND");
      if (!reply) return Fail("no RTS_COMMAND answered command " + std::to_string(id));
      std::string status, message;
      reply->GetMetaDataElement("Status", status);
      reply->GetMetaDataElement("Message", message);
      std::printf("REPLY %u %s %s\n", reply->GetCommandId(), status.c_str(), message.c_str());
    }
    std::fflush(stdout);
  }
  socket->CloseSocket();
  return 0;
}
