#include "rpSessionLog.h"

#include <chrono>

namespace rp {

bool SessionLogWriter::Start(HapticLogRing& ring, const std::string& path, std::vector<std::string> labelNames,
                             std::string& error) {
  if (this->Thread.joinable()) {
    error = "session log: already writing";
    return false;
  }
  this->File = path.empty() ? nullptr : std::fopen(path.c_str(), "w");
  if (!path.empty() && this->File == nullptr) {
    error = "session log: cannot write '" + path + "'";
    return false;
  }
  if (this->File) std::fprintf(this->File,
               "time_s,hip_x,hip_y,hip_z,proxy_x,proxy_y,proxy_z,force_x,force_y,force_z,tissue,contacts,"
               "tick_us,watchdog,clamped,elapsed_ms,energy_mJ,stall_limited\n");
  this->Ring = &ring;
  this->Names = std::move(labelNames);
  this->StopRequested.store(false);
  this->Written.store(0);
  this->Thread = std::thread(&SessionLogWriter::Run, this);
  return true;
}

bool SessionLogWriter::Drain() {
  HapticLogRecord r;
  bool any = false;
  while (this->Ring->TryPop(r)) {
    any = true;
    if (this->OnRecord) this->OnRecord(r);
    this->Written.fetch_add(1);
    if (this->File == nullptr) continue;
    const char* tissue = (r.Label >= 0 && static_cast<size_t>(r.Label) < this->Names.size())
                             ? this->Names[static_cast<size_t>(r.Label)].c_str()
                             : "";
    std::fprintf(this->File, "%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.5f,%.5f,%.5f,%s,%d,%.2f,%d,%d,%.3f,%.6f,%d\n", r.Time,
                 r.Hip.x, r.Hip.y, r.Hip.z, r.Proxy.x, r.Proxy.y, r.Proxy.z, r.Force.x, r.Force.y, r.Force.z, tissue,
                 r.Contacts, static_cast<double>(r.TickComputeUs), (r.Flags & 1u) ? 1 : 0, (r.Flags & 2u) ? 1 : 0,
                 1e3 * static_cast<double>(r.Elapsed), r.ObservedEnergy, (r.Flags & 4u) ? 1 : 0);
  }
  return any;
}

void SessionLogWriter::Run() {
  while (!this->StopRequested.load()) {
    if (!this->Drain()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  this->Drain();
}

void SessionLogWriter::Stop() {
  if (!this->Thread.joinable()) return;
  this->StopRequested.store(true);
  this->Thread.join();
  if (this->File) std::fclose(this->File);
  this->File = nullptr;
}

}  // namespace rp
