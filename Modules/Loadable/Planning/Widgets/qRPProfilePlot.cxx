#include "qRPProfilePlot.h"

#include <algorithm>
#include <cmath>

#include <QPainter>
#include <QPainterPath>

qRPProfilePlot::qRPProfilePlot(QWidget* parent) : QWidget(parent) { this->setMinimumHeight(120); }

void qRPProfilePlot::SetProfile(const rp::TrajectoryFigures& figures, const std::vector<rp::BoneHURange>& ranges) {
  this->Figures = figures;
  this->Ranges = ranges;
  this->update();
}

void qRPProfilePlot::paintEvent(QPaintEvent*) {
  QPainter p(this);
  p.fillRect(this->rect(), Qt::white);
  const auto& profile = this->Figures.Profile;
  if (profile.size() < 2) {
    p.drawText(this->rect(), Qt::AlignCenter, "HU profile: place a trajectory on a CT");
    return;
  }
  const double lo = -1000, hi = std::max(1800.0, std::max_element(profile.begin(), profile.end(), [](auto& a, auto& b) {
                                                    return a.MaxHU < b.MaxHU;
                                                  })->MaxHU);
  const double d0 = profile.front().DepthMm, d1 = profile.back().DepthMm;
  const QRectF area = QRectF(this->rect()).adjusted(36, 6, -6, -18);
  auto x = [&](double depth) { return area.left() + area.width() * (depth - d0) / std::max(1e-9, d1 - d0); };
  auto y = [&](double hu) { return area.bottom() - area.height() * (std::clamp(hu, lo, hi) - lo) / (hi - lo); };
  // The bone ranges: cortical ivory, cancellous tan.
  const QColor tints[2] = {QColor(240, 232, 200), QColor(236, 212, 176)};
  for (size_t i = 0; i < this->Ranges.size(); ++i) {
    const double top = std::min(hi, this->Ranges[i].MaxHU);
    p.fillRect(QRectF(area.left(), y(top), area.width(), y(this->Ranges[i].MinHU) - y(top)), tints[std::min<size_t>(i, 1)]);
    p.setPen(QColor(150, 130, 90));
    p.drawText(QPointF(area.left() + 3, y(this->Ranges[i].MinHU) - 3), QString::fromStdString(this->Ranges[i].Tissue));
  }
  // The cross-section's range, then the axis.
  QPainterPath band, axis;
  for (size_t i = 0; i < profile.size(); ++i) {
    const QPointF top(x(profile[i].DepthMm), y(profile[i].MaxHU)), on(x(profile[i].DepthMm), y(profile[i].HU));
    if (i == 0) band.moveTo(top), axis.moveTo(on);
    else band.lineTo(top), axis.lineTo(on);
  }
  for (size_t i = profile.size(); i-- > 0;) band.lineTo(x(profile[i].DepthMm), y(profile[i].MinHU));
  band.closeSubpath();
  p.fillPath(band, QColor(90, 120, 200, 70));
  p.setPen(QPen(QColor(20, 30, 80), 1.5));
  p.drawPath(axis);
  if (this->Figures.Breach.Found) {
    p.setPen(QPen(QColor(200, 30, 30), 1.5, Qt::DashLine));
    p.drawLine(QPointF(x(this->Figures.Breach.DepthMm), area.top()), QPointF(x(this->Figures.Breach.DepthMm), area.bottom()));
  }
  p.setPen(Qt::black);
  p.drawRect(area);
  p.drawText(QPointF(2, area.top() + 10), QString::number(static_cast<int>(hi)));
  p.drawText(QPointF(2, area.bottom()), QString::number(static_cast<int>(lo)));
  p.drawText(QRectF(area.left(), area.bottom() + 2, area.width(), 16), Qt::AlignCenter,
             QString("depth %1 to %2 mm (HU: axis, cross-section range)").arg(d0, 0, 'f', 0).arg(d1, 0, 'f', 0));
}
