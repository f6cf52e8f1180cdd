#pragma once
// The session log of `roboplan track`: who connected to the served port, every command (client
// address, command, result), refusals and recording problems, one line each. Lines come from
// the server thread and the main thread; each goes at once to the log file (`--log`, appended,
// time-stamped, flushed: a killed run keeps its log) and waits for the main thread to echo it
// on the terminal (Echo), so no other thread writes to the terminal's stream.
#include <cstdio>
#include <deque>
#include <mutex>
#include <ostream>
#include <string>

namespace rp {

class TrackingLog {
 public:
  TrackingLog() = default;
  ~TrackingLog();
  TrackingLog(const TrackingLog&) = delete;
  TrackingLog& operator=(const TrackingLog&) = delete;

  /// Appends to `path` from now on. False with `error`.
  bool Open(const std::string& path, std::string& error);
  /// Any thread.
  void Add(const std::string& line);
  /// Main thread: writes the lines added since the last call ("track: <line>").
  void Echo(std::ostream& out);

 private:
  static constexpr size_t MaxPending = 10000;  // lines waiting for Echo (the file gets every line)
  std::mutex Mutex;
  std::FILE* File = nullptr;
  std::deque<std::string> Pending;
  size_t NotEchoed = 0;
};

}  // namespace rp
