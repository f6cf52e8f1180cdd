#pragma once
// OpenIGTLink tracking server: streams the newest poses of a ToolPoseTable (e.g. the serial
// driver's) to every connected client as TRANSFORM messages named as the table's slots (PLUS
// naming, e.g. StylusToTracker),
// and as TDATA/QTDATA to clients that asked with STT_TDATA/STT_QTDATA (answered RTS_*).
// Sends STATUS keep-alives when idle and answers GET_STATUS. Binds 127.0.0.1 unless told
// otherwise. Talks v1 headers until a client sends a v2 header (then v3 framing with
// TransformStatus and IGTL_DEVICE_NAME metadata), as PLUS does. Messages are built with the
// wire format of rpIgtlProtocol. One thread; nothing shared with callers except the pose table.
#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "rpIgtlProtocol.h"
#include "rpToolPose.h"

namespace rp {

class IgtlServer {
 public:
  struct Options {
    std::string BindAddress = "127.0.0.1";
    int Port = 18944;                  // 0: an ephemeral port (see Port())
    double SendHz = 60.0;              // TRANSFORM rate per tool (only fresh poses are sent)
    double KeepAliveSeconds = 0.25;    // STATUS(OK) after this much idle time
    bool SendInvalid = false;          // PLUS default: only valid transforms (v1 peers)
  };

  IgtlServer(const ToolPoseTable& source, Options options);
  ~IgtlServer();
  /// Binds and starts the thread. False with a message naming the problem.
  bool Start(std::string& error);
  void Stop();
  int Port() const { return this->BoundPort.load(); }
  int ClientCount() const { return this->Clients.load(); }
  uint64_t MessagesSent() const { return this->Sent.load(); }

 private:
  struct Client {
    int Fd = -1;
    uint16_t Version = 1;
    bool TData = false, QtData = false;
    double TDataInterval = 0, NextTData = 0, LastSend = 0;
    std::vector<uint8_t> Input;
  };
  void Run();
  bool Send(Client& c);  // the message in Writer
  void SendRts(Client& c, const char* type, double wall);
  void SendStatus(Client& c, double wall);
  void HandleInput(Client& c);
  void SendPoses(double now);

  const ToolPoseTable& Source;
  Options Opts;
  int ListenFd = -1;
  std::thread Thread;
  std::atomic<bool> StopRequested{false};
  std::atomic<int> BoundPort{0}, Clients{0};
  std::atomic<uint64_t> Sent{0};
  std::vector<Client> Connections;
  ToolPoseReader Reader;
  igtl::MessageWriter Writer;       // server thread only
  std::vector<int> Fresh, Valid;    // slots, server thread only
};

}  // namespace rp
