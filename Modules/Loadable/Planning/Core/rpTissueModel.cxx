#include "rpTissueModel.h"

#include <algorithm>
#include <cmath>

namespace rp {

void TissueModel::Prepare() {
  this->Names.clear();
  this->BoneByLabel.clear();
  this->TissueByLabel.clear();
  std::sort(this->BoneRanges.begin(), this->BoneRanges.end(),
            [](const BoneHURange& a, const BoneHURange& b) { return a.MinHU > b.MinHU; });
  if (this->HasLabels()) {
    int top = 0;
    for (const auto& s : this->Segments) top = std::max(top, s.Label);
    this->BoneByLabel.assign(static_cast<size_t>(top) + 1, 0);
    this->TissueByLabel.assign(static_cast<size_t>(top) + 1, -1);
    for (const auto& s : this->Segments) {
      if (s.Label < 0) continue;
      this->BoneByLabel[static_cast<size_t>(s.Label)] = s.IsBone ? 1 : 0;
      this->TissueByLabel[static_cast<size_t>(s.Label)] = static_cast<int>(this->Names.size());
      this->Names.push_back(s.Name);
    }
    this->Names.push_back("no segment");
  } else {
    for (const auto& range : this->BoneRanges) this->Names.push_back(range.Tissue);
    this->Names.push_back("outside bone");
  }
}

double TissueModel::BoneIndicator(const Vec3& p) const noexcept {
  if (this->HasLabels()) {
    const auto& bone = this->BoneByLabel;
    return this->Labels.Indicator(p, [&bone](double v) {
      return v >= 0 && v < static_cast<double>(bone.size()) && bone[static_cast<size_t>(v)] != 0;
    });
  }
  if (this->HasCT()) return this->CT.Trilinear(p) >= this->BoneThresholdHU ? 1.0 : 0.0;
  return 0.0;
}

int TissueModel::BoneRangeOf(double hu) const noexcept {
  for (size_t i = 0; i < this->BoneRanges.size(); ++i)
    if (hu >= this->BoneRanges[i].MinHU && hu < this->BoneRanges[i].MaxHU) return static_cast<int>(i);
  return -1;
}

int TissueModel::TissueIndex(const Vec3& p) const noexcept {
  const int rest = static_cast<int>(this->Names.size()) - 1;
  if (this->HasLabels()) {
    const double v = this->Labels.Nearest(p, -1);
    if (v < 0 || v >= static_cast<double>(this->TissueByLabel.size())) return rest;
    const int index = this->TissueByLabel[static_cast<size_t>(v)];
    return index < 0 ? rest : index;
  }
  const int range = this->HasCT() ? this->BoneRangeOf(this->CT.Trilinear(p)) : -1;
  return range < 0 ? rest : range;
}

double TissueModel::StepMm() const noexcept {
  double spacing = HUGE_VAL;
  if (this->HasCT()) spacing = std::min(spacing, this->CT.MinimumSpacing());
  if (this->HasLabels()) spacing = std::min(spacing, this->Labels.MinimumSpacing());
  return std::isfinite(spacing) ? std::min(0.25, spacing / 4) : 0.25;
}

bool TissueModel::Contains(const Vec3& p) const noexcept {
  if (this->HasCT()) return this->CT.Inside(p);
  return this->HasLabels() && this->Labels.Inside(p);
}

}  // namespace rp
