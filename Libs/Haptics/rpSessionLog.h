#pragma once
// Writes the haptic session log (CSV: time, HIP, proxy, force, tissue in contact, tick time) on
// its own thread, draining the servo's SPSC ring, so file IO never reaches the servo thread.
#include <atomic>
#include <cstdio>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "rpHapticServo.h"

namespace rp {

class SessionLogWriter {
 public:
  ~SessionLogWriter() { this->Stop(); }
  /// Called on the writer thread for every record (e.g. statistics); set before Start.
  std::function<void(const HapticLogRecord&)> OnRecord;
  /// Opens `path` (empty: no file, records only go to OnRecord) and starts draining `ring`.
  /// `labelNames` maps material index → tissue name.
  bool Start(HapticLogRing& ring, const std::string& path, std::vector<std::string> labelNames, std::string& error);
  /// Drains what is left, closes the file, joins the thread.
  void Stop();
  uint64_t RecordsWritten() const { return this->Written.load(); }

 private:
  void Run();
  bool Drain();
  HapticLogRing* Ring = nullptr;
  std::FILE* File = nullptr;
  std::vector<std::string> Names;
  std::thread Thread;
  std::atomic<bool> StopRequested{false};
  std::atomic<uint64_t> Written{0};
};

}  // namespace rp
