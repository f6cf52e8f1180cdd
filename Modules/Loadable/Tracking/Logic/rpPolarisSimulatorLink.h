#pragma once
// The cable of a simulated NDI Polaris (rpPolarisSimulator.h): a pseudo-terminal (optionally
// behind a symlink that survives a replug, with a unix datagram socket `<link>.break` for the
// serial break) or a TCP listener on 127.0.0.1 serving one host at a time, as a Polaris
// Vega/Lyra does. The faults a cable and a busy device show are injected here: unplugged,
// replies dropped, corrupted (the CRC only) or delayed. Send and Poll run on the simulator
// thread; the rest on any thread.
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>

#include "rpPolarisSimulatorTools.h"

namespace rp {

class PolarisSimulatorLink {
 public:
  explicit PolarisSimulatorLink(const PolarisSimulatorOptions& options) : Opts(options) {}
  ~PolarisSimulatorLink() { this->Close(); }
  PolarisSimulatorLink(const PolarisSimulatorLink&) = delete;
  PolarisSimulatorLink& operator=(const PolarisSimulatorLink&) = delete;

  /// The pty (and its link and break socket), or the TCP listener. False with `error`.
  bool Open(std::string& error);
  void Close();
  bool Tcp() const { return this->Opts.TcpPort >= 0; }
  /// What a driver opens: the link when one was given, the pty slave otherwise; over TCP
  /// "127.0.0.1:PORT".
  std::string PortPath() const;
  std::string SlavePath() const;
  /// The TCP port served (after Open), 0 on a pty.
  int TcpPort() const { return this->BoundPort.load(); }

  /// Pulls the cable: closes the pty (the host reads EIO) and removes the link; over TCP closes
  /// the connection and stops listening (connections are refused until Replug).
  void Unplug();
  /// Plugs it back: a new pty (the link re-pointed) or the same TCP port listening again.
  bool Replug(std::string& error);
  bool Unplugged() const { return this->IsUnplugged; }

  void CorruptNextReplies(int count) { this->CrcFaults += count; }
  void DropNextReplies(int count) { this->Drops += count; }
  void SetReplyDelay(int milliseconds) { this->DelayMs = milliseconds; }
  void DeliverBreak() { this->BreakPending = true; }
  /// Whether a break arrived (DeliverBreak or the break socket) since the last call.
  bool TakeBreak() { return this->BreakPending.exchange(false); }

  /// Waits up to `timeoutMs` for the host: a new TCP host, or the TCP host hanging up, calls
  /// `newHost` (what it sent before is void); what the host sent goes to `received`.
  void Poll(int timeoutMs, const std::function<void()>& newHost,
            const std::function<void(const char*, size_t)>& received);
  /// A reply to the host, through the injected faults (`ascii`: its CRC is the 4 hex digits
  /// before the final CR; else the binary frame's last two bytes).
  void Send(uint8_t* data, size_t length, bool ascii);

 private:
  bool OpenPty(std::string& error);
  void ClosePty();
  bool OpenListener(std::string& error);
  bool OpenBreakSocket(std::string& error);
  void AcceptClient();

  const PolarisSimulatorOptions& Opts;
  std::atomic<bool> BreakPending{false}, IsUnplugged{false};
  std::atomic<int> CrcFaults{0}, Drops{0}, DelayMs{0};
  mutable std::mutex Mutex;  // guards the fds and paths against Unplug/Replug (not hot)
  int MasterFd = -1, KeepSlaveFd = -1, BreakSocketFd = -1, ListenFd = -1;  // MasterFd: the TCP client over TCP
  std::atomic<int> BoundPort{0};
  std::string Slave;
};

}  // namespace rp
