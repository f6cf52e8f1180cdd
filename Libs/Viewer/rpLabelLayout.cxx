#include "rpLabelLayout.h"

#include <algorithm>

namespace rp {

namespace {

struct Rect {
  double X0, Y0, X1, Y1;
};

double OverlapArea(const Rect& a, const Rect& b) {
  const double w = std::min(a.X1, b.X1) - std::max(a.X0, b.X0);
  const double h = std::min(a.Y1, b.Y1) - std::max(a.Y0, b.Y0);
  return w > 0 && h > 0 ? w * h : 0.0;
}

}  // namespace

std::vector<LabelPlacement> PlaceLabels(const std::vector<LabelBox>& labels, const double viewport[4], double gap) {
  std::vector<LabelPlacement> placements(labels.size());
  std::vector<Rect> placed;
  placed.reserve(labels.size());
  for (size_t i = 0; i < labels.size(); ++i) {
    const LabelBox& label = labels[i];
    const double w = label.Size[0], h = label.Size[1];
    const double ax = label.Anchor[0], ay = label.Anchor[1];
    // Candidates: the four corners around the point, then rows stacked above and below it on
    // either side (a column of labels beside a cluster of points).
    std::vector<std::pair<double, double>> candidates = {
        {ax + gap, ay + gap * 0.5}, {ax + gap, ay - h - gap * 0.5}, {ax - w - gap, ay + gap * 0.5}, {ax - w - gap, ay - h - gap * 0.5}};
    for (int k = 1; k <= 12; ++k) {
      const double up = ay + gap * 0.5 + k * (h + 1), down = ay - h - gap * 0.5 - k * (h + 1);
      candidates.insert(candidates.end(), {{ax + gap, up}, {ax + gap, down}, {ax - w - gap, up}, {ax - w - gap, down}});
    }
    double bestOverlap = -1;
    Rect best{};
    for (const auto& [x, y] : candidates) {
      // Keep inside the viewport (shifting along the edge rather than dropping the candidate).
      const double x0 = std::clamp(x, viewport[0], std::max(viewport[0], viewport[2] - w));
      const double y0 = std::clamp(y, viewport[1], std::max(viewport[1], viewport[3] - h));
      const Rect rect{x0, y0, x0 + w, y0 + h};
      double overlap = 0;
      for (const Rect& other : placed) overlap += OverlapArea(rect, other);
      if (bestOverlap < 0 || overlap < bestOverlap) {
        bestOverlap = overlap;
        best = rect;
      }
      if (overlap == 0) break;
    }
    placed.push_back(best);
    placements[i].Position[0] = best.X0;
    placements[i].Position[1] = best.Y0;
    placements[i].Overlaps = bestOverlap > 0;
  }
  return placements;
}

}  // namespace rp
