#pragma once
// Helpers shared by the Tracking tests and benchmark: waiting with a deadline, free loopback
// ports, a test pose, and for upstream OpenIGTLink peers: the example programs run as child
// processes (output captured in a file, killed by pid at the end) and the matrices they print.
#include <sys/types.h>

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "rpIgtlClient.h"
#include "rpIgtlProtocol.h"
#include "rpToolPose.h"

namespace rp {
namespace test {

/// The newest pose in a table's slot `name` (a default pose when absent); count: poses so far.
ToolPose Newest(const ToolPoseTable& table, const std::string& name, uint64_t* count = nullptr);
/// Client options for a loopback peer on `port`, reconnecting quickly (tests).
IgtlClient::Options LoopbackClientOptions(int port);

bool WaitFor(const std::function<bool()>& condition, double seconds);
int FreePort();
/// A rotation of 0.7 rad about (1,1,1)/√3 and the translation (12.5 + shift, -40.25, -1500.5),
/// row-major 4x4.
void TestMatrix(double m[16], double shift = 0);
/// True when a socket listens on TCP `port` (read from /proc/net: no connection is made, since
/// upstream's example servers serve one connection at a time).
bool PortListening(int port);

/// A raw OpenIGTLink client for tests on loopback: its socket bound to `from` first when given
/// (127.0.0.2 stands for another machine), whole messages read with a deadline.
class IgtlTestClient {
 public:
  explicit IgtlTestClient(int port, const char* from = nullptr, const char* to = "127.0.0.1");
  ~IgtlTestClient();
  IgtlTestClient(const IgtlTestClient&) = delete;
  IgtlTestClient& operator=(const IgtlTestClient&) = delete;
  bool Connected() const { return this->IsConnected; }
  bool Send(const std::vector<uint8_t>& message);
  /// The next message of `type` within `seconds` (keep-alives, poses and others passed over).
  bool Next(const char* type, igtl::Header& header, std::vector<uint8_t>& body, double seconds = 5);
  /// A COMMAND (header v2, as Slicer sends it) and its RTS_COMMAND's Status and Message metadata.
  bool Command(const std::string& xml, std::string& status, std::string& message);

 private:
  bool ReadExactly(uint8_t* data, size_t size, double deadline);
  int Fd = -1;
  bool IsConnected = false;
  uint32_t Id = 0;
};

/// One upstream example program run as a child process; stdout and stderr go to one file.
class ChildProcess {
 public:
  ChildProcess() = default;
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;
  ~ChildProcess();
  bool Start(const std::vector<std::string>& arguments, const std::string& outputFile, std::string& error);
  /// Waits for the child to end on its own; false on timeout.
  bool WaitExit(double seconds);
  /// SIGKILL and reap (no-op when it has ended).
  void Kill();
  bool Running();
  int ExitStatus() const { return this->Status; }
  std::string Output() const;

 private:
  pid_t Pid = -1;
  int Status = -1;
  std::string OutputFile;
};

/// The "=============" blocks of igtl::PrintMatrix (4 rows of 4 numbers), in order.
std::vector<std::array<double, 16>> PrintedMatrices(const std::string& output);
/// Number of occurrences of `needle` in `text`.
size_t Count(const std::string& text, const std::string& needle);

}  // namespace test
}  // namespace rp
