#include "rpPoseSource.h"
#include "rpPoseSourceKinds.h"

#include <algorithm>
#include <mutex>
#include <stdexcept>

namespace rp {

std::string PoseSourceConfig::Option(const std::string& key, const std::string& fallback) const {
  const auto it = this->Options.find(key);
  return it == this->Options.end() ? fallback : it->second;
}

double PoseSourceConfig::Number(const std::string& key, double fallback) const {
  const auto it = this->Options.find(key);
  if (it == this->Options.end()) return fallback;
  try {
    size_t used = 0;
    const double value = std::stod(it->second, &used);
    if (used == it->second.size()) return value;
  } catch (const std::exception&) {
  }
  throw std::invalid_argument(key + " must be a number, got '" + it->second + "'");
}

std::pair<std::string, int> PoseSourceConfig::HostAndPort() const {
  const size_t colon = this->Address.rfind(':');
  int port = 0;
  try {
    if (colon == std::string::npos || colon == 0) throw std::invalid_argument("");
    size_t used = 0;
    port = std::stoi(this->Address.substr(colon + 1), &used);
    if (used != this->Address.size() - colon - 1 || port <= 0 || port > 65535) throw std::invalid_argument("");
  } catch (const std::exception&) {
    throw std::invalid_argument("expected HOST:PORT, got '" + this->Address + "'");
  }
  return {this->Address.substr(0, colon), port};
}

namespace {
// The module's own kinds (rpPoseSourceKinds.cxx), then what a host registers.
struct Registry {
  std::mutex Mutex;
  std::vector<PoseSourceRegistry::Entry> Entries = BuiltInPoseSources();
};
Registry& TheRegistry() {
  static Registry registry;
  return registry;
}
}  // namespace

bool PoseSourceRegistry::Register(Entry entry) {
  Registry& r = TheRegistry();
  std::lock_guard<std::mutex> lock(r.Mutex);
  for (const Entry& e : r.Entries)
    if (e.Kind == entry.Kind) return false;
  r.Entries.push_back(std::move(entry));
  return true;
}

std::vector<PoseSourceRegistry::Entry> PoseSourceRegistry::Entries() {
  Registry& r = TheRegistry();
  std::lock_guard<std::mutex> lock(r.Mutex);
  std::vector<Entry> entries = r.Entries;
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.Kind < b.Kind; });
  return entries;
}

std::unique_ptr<PoseSource> PoseSourceRegistry::Create(const PoseSourceConfig& config) {
  PoseSourceFactory factory;
  std::string kinds;
  for (const Entry& e : Entries()) {
    if (e.Kind == config.Kind) factory = e.Factory;
    kinds += (kinds.empty() ? "" : ", ") + e.Kind;
  }
  if (!factory) throw std::invalid_argument("no pose source of kind '" + config.Kind + "' (known: " + kinds + ")");
  return factory(config);
}

}  // namespace rp
