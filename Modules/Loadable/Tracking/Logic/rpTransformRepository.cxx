#include "rpTransformRepository.h"

#include <cctype>
#include <cmath>
#include <queue>

#include <Eigen/LU>

namespace rp {

const char* TransformStatusName(TransformStatus status) {
  switch (status) {
    case TransformStatus::OK: return "OK";
    case TransformStatus::Missing: return "MISSING";
    case TransformStatus::Invalid: return "INVALID";
  }
  return "INVALID";
}

bool SplitTransformName(const std::string& name, std::string& from, std::string& to, std::string& error) {
  size_t found = std::string::npos;
  int candidates = 0;
  for (size_t i = 1; i + 2 < name.size(); ++i) {
    if (name[i] == 'T' && name[i + 1] == 'o' && std::isupper(static_cast<unsigned char>(name[i + 2]))) {
      found = i;
      ++candidates;
    }
  }
  if (candidates != 1) {
    error = "transform name '" + name + "' " +
            (candidates == 0 ? std::string("is not FromToTo (no 'To' before a capital letter)")
                             : "is ambiguous (" + std::to_string(candidates) + " ways to split it at 'To')");
    return false;
  }
  from = name.substr(0, found);
  to = name.substr(found + 2);
  return true;
}

int TransformRepository::FindFrame(const std::string& name) const {
  const auto it = this->FrameIds.find(name);
  return it == this->FrameIds.end() ? -1 : it->second;
}

int TransformRepository::FrameId(const std::string& name) {
  const int found = this->FindFrame(name);
  if (found >= 0) return found;
  this->FrameNames.push_back(name);
  this->Adjacent.emplace_back();
  const int id = static_cast<int>(this->FrameNames.size() - 1);
  this->FrameIds.emplace(name, id);
  return id;
}

TransformRepository::Path TransformRepository::Search(int from, int to) const {
  // Breadth-first from `to`, so that the steps come out in the order they multiply:
  // FromToTo = AToTo · BToA · ... · FromToB.
  Path path;
  const size_t n = this->FrameNames.size();
  std::vector<int> viaEdge(n, -1), previous(n, -1);
  std::vector<bool> seen(n, false);
  std::queue<int> open;
  open.push(to);
  seen[static_cast<size_t>(to)] = true;
  while (!open.empty()) {
    const int frame = open.front();
    open.pop();
    if (frame == from) break;
    for (const auto& [edge, other] : this->Adjacent[static_cast<size_t>(frame)]) {
      if (seen[static_cast<size_t>(other)]) continue;
      seen[static_cast<size_t>(other)] = true;
      viaEdge[static_cast<size_t>(other)] = edge;
      previous[static_cast<size_t>(other)] = frame;
      open.push(other);
    }
  }
  if (!seen[static_cast<size_t>(from)]) return path;
  path.Connected = true;
  // Walk from `from` back to `to`; each step maps the current frame into the previous one.
  std::vector<Step> reversed;
  for (int frame = from; frame != to; frame = previous[static_cast<size_t>(frame)]) {
    const Edge& e = this->Edges[static_cast<size_t>(viaEdge[static_cast<size_t>(frame)])];
    reversed.push_back({viaEdge[static_cast<size_t>(frame)], e.From != frame});
  }
  path.Steps.assign(reversed.rbegin(), reversed.rend());
  return path;
}

bool TransformRepository::Connected(int a, int b) const { return a == b || this->Search(a, b).Connected; }

void TransformRepository::StructureChanged() {
  for (size_t p = 0; p < this->Paths.size(); ++p)
    this->Paths[p] = this->Search(this->PathEnds[p].first, this->PathEnds[p].second);
  const size_t n = this->FrameNames.size();
  std::vector<int> cache(n * n, -1);
  const size_t old = this->CacheSide;
  for (size_t a = 0; a < old; ++a)
    for (size_t b = 0; b < old; ++b) cache[a * n + b] = this->PairCache[a * old + b];
  this->PairCache.swap(cache);
  this->CacheSide = n;
}

int TransformRepository::AddEdge(const std::string& from, const std::string& to, const Eigen::Matrix4d& m,
                                 TransformStatus s, bool fixed, std::string& error) {
  const std::string name = from + "To" + to;
  if (from.empty() || to.empty() || from == to) {
    error = "transform '" + name + "' must join two different named frames";
    return -1;
  }
  const int a = this->FindFrame(from), b = this->FindFrame(to);
  if (a >= 0 && b >= 0 && this->Connected(a, b)) {
    error = "transform '" + name + "' is already defined or computable from the others (" + from + " and " + to +
            " are connected): a second path would make the answer depend on the path";
    return -1;
  }
  if (!m.allFinite() || std::abs(m.determinant()) < 1e-12) {
    error = "transform '" + name + "' has a matrix that cannot be inverted";
    return -1;
  }
  Edge e{this->FrameId(from), this->FrameId(to), m, m.inverse(), s, fixed};
  this->Edges.push_back(e);
  const int id = static_cast<int>(this->Edges.size() - 1);
  this->Adjacent[static_cast<size_t>(e.From)].push_back({id, e.To});
  this->Adjacent[static_cast<size_t>(e.To)].push_back({id, e.From});
  this->StructureChanged();
  return id;
}

bool TransformRepository::SetFixed(const std::string& from, const std::string& to, const Eigen::Matrix4d& matrix,
                                   std::string& error) {
  return this->AddEdge(from, to, matrix, TransformStatus::OK, true, error) >= 0;
}

bool TransformRepository::Update(const std::string& from, const std::string& to, const Eigen::Matrix4d& matrix,
                                 std::string& error) {
  const int a = this->FindFrame(from), b = this->FindFrame(to);
  if (a < 0 || b < 0 || !this->Connected(a, b)) return this->SetFixed(from, to, matrix, error);
  for (Edge& e : this->Edges) {
    const bool forward = e.From == a && e.To == b, backward = e.From == b && e.To == a;
    if (!forward && !backward) continue;
    if (!e.Fixed) {
      error = "transform '" + from + "To" + to + "' comes from the tracker";
      return false;
    }
    if (!matrix.allFinite() || std::abs(matrix.determinant()) < 1e-12) {
      error = "transform '" + from + "To" + to + "' has a matrix that cannot be inverted";
      return false;
    }
    e.Matrix = forward ? matrix : Eigen::Matrix4d(matrix.inverse());
    e.Inverse = e.Matrix.inverse();
    return true;
  }
  error = "transform '" + from + "To" + to + "' is computed from others (" + from + " and " + to +
          " are connected through stored transforms): set one of those";
  return false;
}

int TransformRepository::DeclareLive(const std::string& from, const std::string& to, std::string& error) {
  return this->AddEdge(from, to, Eigen::Matrix4d::Identity(), TransformStatus::Missing, false, error);
}

void TransformRepository::SetLive(int edge, const Eigen::Matrix4d& matrix, TransformStatus status) noexcept {
  if (edge < 0 || static_cast<size_t>(edge) >= this->Edges.size()) return;
  Edge& e = this->Edges[static_cast<size_t>(edge)];
  if (e.Fixed) return;
  e.Status = status;
  if (status == TransformStatus::OK && matrix.allFinite()) {
    e.Matrix = matrix;
    e.Inverse = matrix.inverse();
  }
}

int TransformRepository::Prepare(const std::string& from, const std::string& to) {
  const int a = this->FindFrame(from), b = this->FindFrame(to);
  if (a < 0 || b < 0) return -1;
  const size_t n = this->FrameNames.size();
  int& cached = this->PairCache[static_cast<size_t>(a) * n + static_cast<size_t>(b)];
  if (cached >= 0) return cached;
  this->PathEnds.push_back({a, b});
  this->Paths.push_back(this->Search(a, b));
  cached = static_cast<int>(this->Paths.size() - 1);
  return cached;
}

bool TransformRepository::Evaluate(int path, Eigen::Matrix4d& matrix, TransformStatus& status) const noexcept {
  matrix.setIdentity();
  if (path < 0 || static_cast<size_t>(path) >= this->Paths.size() || !this->Paths[static_cast<size_t>(path)].Connected) {
    status = TransformStatus::Invalid;
    return false;
  }
  status = TransformStatus::OK;
  for (const Step& step : this->Paths[static_cast<size_t>(path)].Steps) {
    const Edge& e = this->Edges[static_cast<size_t>(step.Edge)];
    matrix = matrix * (step.Inverted ? e.Inverse : e.Matrix);
    if (e.Status != TransformStatus::OK && status == TransformStatus::OK) status = e.Status;
  }
  return status == TransformStatus::OK;
}

bool TransformRepository::Get(const std::string& from, const std::string& to, Eigen::Matrix4d& matrix,
                              TransformStatus& status) {
  return this->Evaluate(this->Prepare(from, to), matrix, status);
}

bool TransformRepository::Get(const std::string& transformName, Eigen::Matrix4d& matrix, TransformStatus& status) {
  std::string from, to, error;
  if (!SplitTransformName(transformName, from, to, error)) {
    matrix.setIdentity();
    status = TransformStatus::Invalid;
    return false;
  }
  return this->Get(from, to, matrix, status);
}

std::string TransformRepository::Describe(int path) const {
  if (path < 0 || static_cast<size_t>(path) >= this->Paths.size() || !this->Paths[static_cast<size_t>(path)].Connected) return {};
  std::string text;
  for (const Step& step : this->Paths[static_cast<size_t>(path)].Steps) {
    const Edge& e = this->Edges[static_cast<size_t>(step.Edge)];
    text += (text.empty() ? "" : " * ") + this->FrameNames[static_cast<size_t>(e.From)] + "To" +
            this->FrameNames[static_cast<size_t>(e.To)] + (step.Inverted ? "^-1" : "");
  }
  return text.empty() ? "identity" : text;
}

std::vector<TransformRepository::StoredTransform> TransformRepository::Stored() const {
  std::vector<StoredTransform> out;
  for (const Edge& e : this->Edges)
    out.push_back({this->FrameNames[static_cast<size_t>(e.From)], this->FrameNames[static_cast<size_t>(e.To)], e.Fixed});
  return out;
}

}  // namespace rp
