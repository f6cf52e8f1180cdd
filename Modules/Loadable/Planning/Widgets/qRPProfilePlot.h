#ifndef qRPProfilePlot_h
#define qRPProfilePlot_h
// The HU profile of a plan in the Planning panel, drawn with QPainter at display rate: the CT
// number on the axis (dark) and the cross-section's range (a band) against depth, over the bone
// ranges of materials.json (cortical, cancellous: tinted bands), with the breach's depth marked.
#include <QWidget>

#include "rpTrajectoryFigures.h"

class qRPProfilePlot : public QWidget {
  Q_OBJECT
 public:
  explicit qRPProfilePlot(QWidget* parent = nullptr);
  void SetProfile(const rp::TrajectoryFigures& figures, const std::vector<rp::BoneHURange>& ranges);
  QSize sizeHint() const override { return {320, 160}; }

 protected:
  void paintEvent(QPaintEvent* event) override;

 private:
  rp::TrajectoryFigures Figures;
  std::vector<rp::BoneHURange> Ranges;
};

#endif
