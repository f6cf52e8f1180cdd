#pragma once
// Named coordinate frames and the transforms between them, as PLUS's transform repository
// (vtkIGSIOTransformRepository): "FromToTo" transforms are stored once each (fixed ones from a
// configuration's CoordinateDefinitions, live ones from a tracker), and any frame pair that the
// stored transforms connect can be asked for: StylusTipToReference = (ReferenceToTracker)^-1 ·
// StylusToTracker · StylusTipToStylus, found by a search through the graph and composed with
// inverses where a link runs the other way. As in PLUS, a transform that would make a second
// path between two frames already connected is refused (the answer must not depend on the path).
//
// Each answer has a status: OK (every link valid), MISSING (connected, but a live link has no
// valid pose now: a tool out of view, or not seen yet) or INVALID (the frames are not connected,
// or a name is unknown or malformed). Plain C++ and Eigen; one thread owns an instance. Building
// (Declare*, SetFixed, Prepare) allocates; the hot path does not: SetLive(edge, ...) and
// Evaluate(path, ...) on prepared ids, and Get(from, to, ...) once a pair has been asked for.
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace rp {

enum class TransformStatus { OK = 0, Missing, Invalid };
const char* TransformStatusName(TransformStatus status);  // "OK", "MISSING", "INVALID"

/// "StylusTipToReference" → {"StylusTip", "Reference"}: split at the one "To" followed by a
/// capital letter (PLUS's rule). False with `error` when there is no such split or more than one.
bool SplitTransformName(const std::string& name, std::string& from, std::string& to, std::string& error);

class TransformRepository {
 public:
  /// A fixed transform (e.g. StylusTipToStylus from CoordinateDefinitions), valid for good.
  bool SetFixed(const std::string& from, const std::string& to, const Eigen::Matrix4d& matrix, std::string& error);
  /// PLUS's UpdateTransform: a stored fixed transform gets a new matrix (given either way round), a
  /// new one is added as SetFixed adds it; a live (tracker) transform or one computed through
  /// others is refused with `error`, as PLUS refuses to set a computed transform.
  bool Update(const std::string& from, const std::string& to, const Eigen::Matrix4d& matrix, std::string& error);
  /// A live transform (e.g. StylusToTracker from a tracker): an edge id for SetLive, MISSING
  /// until its first valid pose. -1 with `error` when it would close a loop.
  int DeclareLive(const std::string& from, const std::string& to, std::string& error);
  /// Hot path: the newest pose of a live edge (status OK, or MISSING with the last matrix kept).
  void SetLive(int edge, const Eigen::Matrix4d& matrix, TransformStatus status) noexcept;

  /// A path id for a frame pair (-1 when a frame name is unknown: Evaluate then says INVALID).
  int Prepare(const std::string& from, const std::string& to);
  /// Hot path: compose a prepared path. True when the status is OK.
  bool Evaluate(int path, Eigen::Matrix4d& matrix, TransformStatus& status) const noexcept;
  /// By names; allocation-free after the first call for a pair. True when OK.
  bool Get(const std::string& from, const std::string& to, Eigen::Matrix4d& matrix, TransformStatus& status);
  /// "StylusTipToReference" at once (INVALID for a name that does not split).
  bool Get(const std::string& transformName, Eigen::Matrix4d& matrix, TransformStatus& status);

  /// The chain a prepared path composes, e.g. "ReferenceToTracker^-1 * StylusToTracker *
  /// StylusTipToStylus" ("" when not connected).
  std::string Describe(int path) const;

  bool HasFrame(const std::string& name) const { return this->FrameIds.count(name) != 0; }
  const std::vector<std::string>& Frames() const { return this->FrameNames; }
  /// Every stored transform as "FromToTo", fixed ones marked.
  struct StoredTransform {
    std::string From, To;
    bool Fixed;
  };
  std::vector<StoredTransform> Stored() const;

 private:
  struct Edge {
    int From, To;
    Eigen::Matrix4d Matrix, Inverse;
    TransformStatus Status;
    bool Fixed;
  };
  struct Step {
    int Edge;
    bool Inverted;
  };
  struct Path {
    bool Connected = false;
    std::vector<Step> Steps;  // from the To end: result = M(step0) · M(step1) · ...
  };
  int FrameId(const std::string& name);  // registering it
  int FindFrame(const std::string& name) const;
  bool Connected(int a, int b) const;
  int AddEdge(const std::string& from, const std::string& to, const Eigen::Matrix4d& m, TransformStatus s, bool fixed,
              std::string& error);
  Path Search(int from, int to) const;
  void StructureChanged();

  std::vector<std::string> FrameNames;
  std::unordered_map<std::string, int> FrameIds;
  std::vector<Edge> Edges;
  std::vector<std::vector<std::pair<int, int>>> Adjacent;  // per frame: (edge, other frame)
  std::vector<std::pair<int, int>> PathEnds;               // per path: (from, to) frame ids
  std::vector<Path> Paths;
  std::vector<int> PairCache;  // CacheSide^2 (the frame count), path id or -1
  size_t CacheSide = 0;
};

}  // namespace rp
