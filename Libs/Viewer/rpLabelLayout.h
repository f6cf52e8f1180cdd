#pragma once
// Places text labels beside their points on screen so that no two overlap (fiducial labels in a
// view; greedy, in the order given): each label tries positions around its point — right/above,
// right/below, left/above, left/below, then stacked further up and down beside it — and takes
// the first that overlaps no label placed before and stays inside the viewport. When none is
// free (a crowded view), it takes the free-most of them; a label is never moved off its point's
// side of the viewport. Plain C++, so it is tested without rendering.
#include <vector>

namespace rp {

struct LabelBox {
  double Anchor[2] = {0, 0};  // the point, display pixels
  double Size[2] = {0, 0};    // the label's width and height, pixels
};

struct LabelPlacement {
  double Position[2] = {0, 0};  // lower-left corner, display pixels
  bool Overlaps = false;        // no free place was found
};

/// Viewport: xmin, ymin, xmax, ymax in display pixels. `gap`: pixels between a point and its label.
std::vector<LabelPlacement> PlaceLabels(const std::vector<LabelBox>& labels, const double viewport[4], double gap = 6);

}  // namespace rp
