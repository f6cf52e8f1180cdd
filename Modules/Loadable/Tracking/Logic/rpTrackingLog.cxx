#include "rpTrackingLog.h"

#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>

namespace rp {

namespace {
std::string LocalTime() {
  const auto now = std::chrono::system_clock::now();
  const std::time_t seconds = std::chrono::system_clock::to_time_t(now);
  const long millis = static_cast<long>(std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000);
  std::tm local{};
  localtime_r(&seconds, &local);
  char text[40];
  const size_t n = std::strftime(text, sizeof text, "%Y-%m-%d %H:%M:%S", &local);
  std::snprintf(text + n, sizeof text - n, ".%03ld", millis);
  return text;
}
}  // namespace

TrackingLog::~TrackingLog() {
  if (this->File) std::fclose(this->File);
}

bool TrackingLog::Open(const std::string& path, std::string& error) {
  std::lock_guard<std::mutex> lock(this->Mutex);
  if (this->File) std::fclose(this->File);
  this->File = std::fopen(path.c_str(), "ae");
  if (!this->File) {
    error = "cannot write the session log " + path + ": " + std::strerror(errno);
    return false;
  }
  return true;
}

void TrackingLog::Add(const std::string& line) {
  std::lock_guard<std::mutex> lock(this->Mutex);
  if (this->File) {
    std::fprintf(this->File, "%s %s\n", LocalTime().c_str(), line.c_str());
    std::fflush(this->File);
  }
  if (this->Pending.size() < MaxPending) this->Pending.push_back(line);
  else ++this->NotEchoed;
}

void TrackingLog::Echo(std::ostream& out) {
  std::deque<std::string> lines;
  size_t notEchoed = 0;
  {
    std::lock_guard<std::mutex> lock(this->Mutex);
    lines.swap(this->Pending);
    notEchoed = this->NotEchoed;
    this->NotEchoed = 0;
  }
  for (const std::string& line : lines) out << "track: " << line << "\n";
  if (notEchoed) out << "track: " << notEchoed << " more log lines not shown here (in the --log file)\n";
}

}  // namespace rp
