#pragma once
// One interface for everything that produces tool poses (a tracker over a serial port, an
// OpenIGTLink server, a recording, a simulated Polaris), and a registry keyed by the source
// kind, as PLUS's device factory: a new tracker is one class, one line in the list of kinds
// (BuiltInPoseSources, rpPoseSourceKinds.cxx) and its tests. `roboplan track` and the Tracking panel create and use sources only through
// this interface.
//
// A source runs its own I/O thread (WorkerThread), publishes into a ToolPoseTable (slot names
// are transform names, e.g. StylusToTracker) and, for image streams, an ImageTable; after
// each batch it notifies ReadyFd() so that the main thread can copy into the scene at once.
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "rpToolPose.h"
#include "rpWorkerThread.h"

namespace rp {

class ImageTable;

/// What to connect to. Kind: the registry key; Address: a serial port, HOST:PORT or a file;
/// ToolFiles: tool definitions (.json or .rom); Options: kind-specific settings by name.
struct PoseSourceConfig {
  std::string Kind;
  std::string Address;
  std::vector<std::string> ToolFiles;
  std::map<std::string, std::string> Options;

  std::string Option(const std::string& key, const std::string& fallback = "") const;
  /// A numeric option; throws std::invalid_argument naming the key and the text.
  double Number(const std::string& key, double fallback) const;
  /// HOST:PORT from Address; throws std::invalid_argument.
  std::pair<std::string, int> HostAndPort() const;
};

class PoseSource {
 public:
  virtual ~PoseSource() = default;
  /// Starts the I/O thread and returns at once (the thread connects, with back-off). False,
  /// with the reason, only when the source cannot run at all.
  virtual bool Start(std::string& error) = 0;
  /// Start for callers that watch Connected()/StatusText() rather than the error text (a
  /// subclass that declares Start(std::string&) brings this in with `using PoseSource::Start;`).
  bool Start() {
    std::string ignored;
    return this->Start(ignored);
  }
  virtual void Stop() = 0;
  virtual const ToolPoseTable& Poses() const = 0;
  /// Images the source streams (OpenIGTLink IMAGE), or nullptr.
  virtual const ImageTable* Images() const { return nullptr; }
  virtual bool Connected() const = 0;
  /// True once the source has nothing more to give (a recording played to its end); a live
  /// tracker never finishes.
  virtual bool Finished() const { return false; }
  /// One line for a status bar: "tracking", "connecting: cannot open /dev/ttyUSB0: ...".
  virtual std::string StatusText() const = 0;
  /// Counters and device facts (frames, CRC errors, reconnections, firmware ...).
  virtual nlohmann::json StatisticsJson() const = 0;
  /// Readable after the source published something (poll it, or use a QSocketNotifier).
  virtual int ReadyFd() const { return this->Ready.Fd(); }
  virtual void DrainReady() const { this->Ready.Drain(); }

 protected:
  ReadySignal Ready;  // the I/O thread calls Ready.Notify() after publishing a batch
};

/// Makes a source from a configuration; throws std::invalid_argument for a configuration that
/// cannot be right (a bad address or option) and std::runtime_error for one that fails (a tool
/// file that cannot be read).
using PoseSourceFactory = std::function<std::unique_ptr<PoseSource>(const PoseSourceConfig&)>;

class PoseSourceRegistry {
 public:
  struct Entry {
    std::string Kind, Description, AddressHint;
    PoseSourceFactory Factory;
  };
  /// A kind beside the module's own (BuiltInPoseSources lists those): a host's or a test's.
  /// False when the kind is taken.
  static bool Register(Entry entry);
  /// Throws as the factory does, and std::invalid_argument for an unknown kind.
  static std::unique_ptr<PoseSource> Create(const PoseSourceConfig& config);
  static std::vector<Entry> Entries();  // sorted by kind
};

}  // namespace rp
