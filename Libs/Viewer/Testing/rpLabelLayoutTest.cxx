// Label layout: labels of points that crowd together never overprint and stay in the view.
#include <gtest/gtest.h>

#include "rpLabelLayout.h"

namespace {
bool Overlap(const rp::LabelPlacement& a, const rp::LabelPlacement& b, const rp::LabelBox& sa, const rp::LabelBox& sb) {
  return a.Position[0] < b.Position[0] + sb.Size[0] && b.Position[0] < a.Position[0] + sa.Size[0] &&
         a.Position[1] < b.Position[1] + sb.Size[1] && b.Position[1] < a.Position[1] + sa.Size[1];
}
}  // namespace

TEST(LabelLayout, ALoneLabelSitsRightOfAndAboveItsPoint) {
  const double viewport[4] = {0, 0, 400, 300};
  rp::LabelBox box;
  box.Anchor[0] = 100;
  box.Anchor[1] = 100;
  box.Size[0] = 60;
  box.Size[1] = 16;
  const auto placed = rp::PlaceLabels({box}, viewport, 6);
  ASSERT_EQ(placed.size(), 1u);
  EXPECT_DOUBLE_EQ(placed[0].Position[0], 106);
  EXPECT_DOUBLE_EQ(placed[0].Position[1], 103);
  EXPECT_FALSE(placed[0].Overlaps);
}

TEST(LabelLayout, TwelvePointsOnOneSpotGetTwelveSeparateLabels) {
  const double viewport[4] = {0, 0, 400, 300};
  std::vector<rp::LabelBox> boxes(12);
  for (size_t i = 0; i < boxes.size(); ++i) {
    boxes[i].Anchor[0] = 200 + 0.5 * double(i);  // a cluster of landmarks a pixel apart
    boxes[i].Anchor[1] = 150;
    boxes[i].Size[0] = 40 + 5.0 * double(i % 3);
    boxes[i].Size[1] = 15;
  }
  const auto placed = rp::PlaceLabels(boxes, viewport);
  ASSERT_EQ(placed.size(), boxes.size());
  for (size_t i = 0; i < placed.size(); ++i) {
    EXPECT_FALSE(placed[i].Overlaps) << i;
    EXPECT_GE(placed[i].Position[0], 0);
    EXPECT_LE(placed[i].Position[0] + boxes[i].Size[0], 400);
    EXPECT_LE(placed[i].Position[1] + boxes[i].Size[1], 300);
    // Beside its point: within a few label heights.
    EXPECT_LT(std::abs(placed[i].Position[1] - boxes[i].Anchor[1]), 8 * 16.0);
    for (size_t j = 0; j < i; ++j) EXPECT_FALSE(Overlap(placed[i], placed[j], boxes[i], boxes[j])) << i << " over " << j;
  }
}

TEST(LabelLayout, LabelsAtTheEdgeStayInsideTheView) {
  const double viewport[4] = {100, 50, 300, 250};  // a view in the lower middle of the window
  rp::LabelBox right, top;
  right.Anchor[0] = 298;
  right.Anchor[1] = 60;
  right.Size[0] = right.Size[1] = 20;
  top.Anchor[0] = 105;
  top.Anchor[1] = 249;
  top.Size[0] = 80;
  top.Size[1] = 20;
  const auto placed = rp::PlaceLabels({right, top}, viewport);
  EXPECT_LE(placed[0].Position[0] + 20, 300);
  EXPECT_GE(placed[0].Position[1], 50);
  EXPECT_LE(placed[1].Position[1] + 20, 250);
  EXPECT_GE(placed[1].Position[0], 100);
}

TEST(LabelLayout, AViewTooSmallForAllSaysSo) {
  const double viewport[4] = {0, 0, 50, 20};
  std::vector<rp::LabelBox> boxes(3);
  for (auto& box : boxes) {
    box.Anchor[0] = 25;
    box.Anchor[1] = 10;
    box.Size[0] = 45;
    box.Size[1] = 15;
  }
  const auto placed = rp::PlaceLabels(boxes, viewport);
  EXPECT_FALSE(placed[0].Overlaps);
  EXPECT_TRUE(placed[2].Overlaps);
}
