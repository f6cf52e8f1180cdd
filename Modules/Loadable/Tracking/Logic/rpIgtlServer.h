#pragma once
// OpenIGTLink tracking server (`roboplan track --serve`): streams the newest poses of a
// ToolPoseTable to every connected client as TRANSFORM messages named as the table's slots
// (PLUS naming, e.g. StylusToTracker), and as TDATA/QTDATA to clients that ask with
// STT_TDATA/STT_QTDATA (answered RTS_*). Sends STATUS keep-alives when idle and answers
// GET_STATUS. Talks header v1 until a client sends a v2 header, then v3 framing with PLUS's
// TransformStatus and IGTL_DEVICE_NAME metadata. Binds 127.0.0.1 unless told otherwise
// (`BindAddress`: one interface's address, or 0.0.0.0 for all).
//
// A peer cannot take the others down: each client gets at most one read per loop turn, input
// is parsed in a fixed window (bodies we do not need are skipped as they stream by), a stream
// that loses the message boundary is closed, output a client does not read waits in a bounded
// queue and a client that stalls is dropped, and connections beyond MaxClients are refused.
// Memory is bounded by MaxClients × (input window + output queue).
//
// PlusServer's remote commands (rpIgtlCommands.h: COMMAND → RTS_COMMAND with Status/Message
// metadata, STRING CMD_<uid> → ACK_<uid>) act on this server: channel and device ids,
// StartRecording/StopRecording (a PLUS .igs.mha of every pose the server sends, streamed into
// the recording folder: rpPlusRecorder.h, rpRecordingFolder.h), and
// GetTransform/UpdateTransform through the TransformProvider (e.g. a transform repository that
// chains StylusTipToReference) and the fixed transforms clients set. A client's CLIENTINFO (PLUS's
// <ClientInfo> XML) replaces, for that client only, which message types and transform names it
// gets; names the server does not stream come from the TransformProvider.
//
// Messages of the main thread's (Options::Outbox: e.g. the navigation read-outs, a TRANSFORM
// ToolTipToTrajectory and a STRING GuidanceReadout) go to every client as soon as they are
// published (the outbox wakes the server's poll), to a client with CLIENTINFO only when its
// message types name their type.
//
// Who may do what: every client gets the stream and the read-only commands; the commands that
// change state or write files (UpdateTransform, StartRecording, StopRecording) run only for a
// client whose address is in `CommandClients` (loopback by default), any other gets a FAIL reply
// naming why. Each connection, refusal, command (client address, command, result) and recording
// problem is one line through `Log` (called on the server thread: the sink must be thread-safe).
// OpenIGTLink itself has no encryption and no authentication: an address is all we can check.
#include <array>
#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <cstdint>
#include <string>
#include <vector>

#include "rpIgtlCommands.h"
#include "rpIgtlOutbox.h"
#include "rpIgtlProtocol.h"
#include "rpNetworkAddress.h"
#include "rpPlusRecorder.h"
#include "rpRecordingFolder.h"
#include "rpToolPose.h"
#include "rpWorkerThread.h"

namespace rp {

/// A source of transforms between named frames (a transform repository): row-major From→To and
/// its status; false when it cannot compute it.
using TransformProvider = std::function<bool(const std::string& from, const std::string& to, double m[16], ToolState& state)>;

/// Sets From→To (row-major) in that source (PLUS's UpdateTransform); false with `error`.
using TransformUpdater = std::function<bool(const std::string& from, const std::string& to, const double m[16], std::string& error)>;

class IgtlServer : public IgtlCommandTarget {
 public:
  struct Options {
    std::string BindAddress = "127.0.0.1";  // an address of this machine; "0.0.0.0" (or "all"): every interface
    AddressAllowList CommandClients = AddressAllowList::Loopback();  // may change state or write files
    std::string RecordFolder = ".";         // StartRecording writes here (PLUS's OutputDirectory)
    std::function<void(const std::string&)> Log;  // session log lines (server thread)
    int Port = 18944;                   // 0: an ephemeral port (see Port())
    double SendHz = 60.0;               // TRANSFORM rate per tool (only fresh poses are sent)
    double KeepAliveSeconds = 0.25;     // STATUS(OK) after this much idle time
    bool SendInvalid = false;           // PLUS default: only valid transforms (v1 peers)
    int MaxClients = 32;                // more are refused (closed at once)
    size_t InputWindow = 64u << 10;     // the largest message we parse (control messages are tiny)
    size_t MaxQueuedOutput = 1u << 20;  // per client; beyond it messages to that client are dropped
    double StallSeconds = 2.0;          // a client that reads nothing this long is dropped
    int SocketSendBuffer = 64 << 10;    // kernel buffer per client: seconds of poses, not minutes
    std::string ChannelId = "TrackerStream";                // RequestChannelIds (PLUS's OutputChannel)
    std::vector<std::string> DeviceIds = {"TrackerDevice"};  // RequestDeviceIds
    TransformProvider Transforms;                           // GetTransform of chained names
    TransformUpdater UpdateTransforms;                      // UpdateTransform into it (else kept here)
    const IgtlOutbox* Outbox = nullptr;                     // the main thread's messages (not owned; outlives the server)
  };

  struct Statistics {
    uint64_t MessagesSent = 0, MessagesDropped = 0, Accepted = 0, Refused = 0;
    uint64_t DroppedMalformed = 0, DroppedStalled = 0, Closed = 0, BytesSkipped = 0, BytesReceived = 0;
  };

  IgtlServer(const ToolPoseTable& source, Options options);
  ~IgtlServer() override;
  /// Binds and starts the thread. False with a message naming the problem.
  bool Start(std::string& error);
  void Stop();
  int Port() const { return this->BoundPort.load(); }
  int ClientCount() const { return this->Clients.load(); }
  uint64_t MessagesSent() const { return this->Sent.load(); }
  Statistics GetStatistics() const;

  // IgtlCommandTarget (called on the server thread while it handles a command)
  std::vector<std::string> ChannelIds() const override { return {this->Opts.ChannelId}; }
  std::vector<std::string> DeviceIds() const override { return this->Opts.DeviceIds; }
  bool StartRecording(const std::string& requested, std::string& message) override;
  bool StopRecording(std::string& message) override;
  bool GetTransform(const std::string& name, double m[16], ToolState& state, std::string& error) override;
  bool UpdateTransform(const std::string& name, const double m[16], std::string& error) override;

 private:
  struct Client {
    int Fd = -1;
    IgtlCommandCaller Caller;  // its address and whether it may change state
    uint16_t Version = 1;
    bool TData = false, QtData = false;
    double TDataInterval = 0, NextTData = 0, LastSend = 0, StalledSince = 0;
    std::vector<uint8_t> Input;  // InputWindow bytes
    size_t InputUsed = 0;
    uint64_t Skip = 0;           // bytes of a body we do not keep, still to come
    std::vector<uint8_t> Queued; // output the client has not taken yet
    size_t QueuedSent = 0;
    // CLIENTINFO (PlusServer's): this client's own message types and transform names replace
    // the default (every served transform) for this client only.
    bool HasClientInfo = false, WantsTransforms = true, WantsStrings = true;
    std::vector<uint8_t> Wanted;  // per Source slot
    struct Extra {
      std::string Name, From, To;  // asked for but not served: computed by Opts.Transforms
    };
    std::vector<Extra> Extras;
  };
  void Run();
  void Accept();
  void Receive(Client& c, uint8_t* scratch, size_t scratchSize);
  void HandleInput(Client& c);
  void Flush(Client& c, double now);
  void Drop(Client& c, std::atomic<uint64_t>& reason, const char* why);
  void Note(const std::string& line) const;  // a line of the session log, when there is one
  bool Send(Client& c);  // the message in Writer
  void SendRts(Client& c, const char* type, double wall);
  void SendStatus(Client& c, double wall);
  void SendPoses(double now);
  void HandleCommand(Client& c, const igtl::Header& h, const igtl::Body& body, double wall);
  void HandleClientInfo(Client& c, const igtl::Body& body);
  void SendTransform(Client& c, const char* name, const double m[16], ToolState state, double wall);
  void SendExtras(Client& c, double wall);
  void SendOutbox(double wall);

  const ToolPoseTable& Source;
  Options Opts;
  int ListenFd = -1;
  WorkerThread Worker;
  std::atomic<int> BoundPort{0}, Clients{0};
  std::atomic<uint64_t> Sent{0}, Dropped{0}, Accepted{0}, Refused{0}, Malformed{0}, Stalled{0}, Closed{0}, Skipped{0},
      Received{0};
  // server thread only
  std::vector<Client> Connections;
  ToolPoseReader Reader;
  igtl::MessageWriter Writer;
  std::vector<int> Fresh, Valid;  // slots
  RecordingFolder Recordings;  // opened by Start
  PlusRecorder Recorder;       // while StartRecording is on
  std::map<std::string, std::vector<double>> FixedTransforms;  // UpdateTransform
  std::array<uint64_t, IgtlOutbox::MaxMessages> OutboxSent{};  // publish count of each outbox message sent
  IgtlOutbox::Message OutboxMessage;
};

}  // namespace rp
