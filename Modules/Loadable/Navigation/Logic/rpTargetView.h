#pragma once
// The target ("bull's-eye") view of navigation systems and the volume re-sliced along and across
// the plan (issue 38), drawn offscreen by VTK into one picture of three panes (the panel shows it;
// `roboplan`-free tests check it pixel by pixel):
//   target view  the plan seen from the entry towards the target (the trajectory's frame, see the
//                Navigation README: its x to the screen's right, its −y up): the target at the
//                centre with rings (1, 2, 5 mm), the tool tip (green dot) at its offset from the
//                axis, the tool's own axis projected (cyan: from where it crosses the entry plane,
//                a yellow diamond — the entry error — to where it would reach the target's depth,
//                a cyan cross — where it would arrive), and the depth to target written below;
//   along        the volume in the plane containing the axis (the trajectory's x to the right, the
//                entry up), at the tip's depth: the plan (red), the tool's axis and tip projected;
//   across       the volume in the plane normal to the axis at the tip's depth, oriented as the
//                target view: the axis at the centre (red cross), the tip.
#include <string>

#include <vtkSmartPointer.h>

#include "rpGuidanceReadout.h"

class vtkImageData;
class vtkMatrix4x4;
class vtkRenderWindow;
class vtkRPScalarVolumeNode;

namespace rp {

/// Where the target view draws a read-out (mm in the trajectory's x, y; the target and the entry at 0).
struct TargetViewGeometry {
  bool Valid = false;
  double Tip[2] = {0, 0};
  bool Crosses = false;                 // the tool's axis crosses the entry and target planes
  double EntryCrossing[2] = {0, 0};     // the tool's axis at the entry's depth (the entry error)
  double TargetCrossing[2] = {0, 0};    // ... at the target's depth (where it would arrive)
};
TargetViewGeometry ComputeTargetViewGeometry(const GuidanceReadout& readout, double planLengthMm,
                                             const Vec3& forward = Vec3{0, 0, -1});

/// The re-sliced views' planes (SliceToRAS, as rpVolumeReslice takes them) at the tip's depth.
void AlongAxisSliceToRAS(const TrajectoryAxis& plan, const GuidanceReadout& readout, vtkMatrix4x4* sliceToRAS);
void AcrossAxisSliceToRAS(const TrajectoryAxis& plan, const GuidanceReadout& readout, vtkMatrix4x4* sliceToRAS);

class TargetViewPicture {
 public:
  struct Options {
    int PaneSize = 240;                 // pixels, each pane square
    double HalfWidthMm = 7;             // the target view: centre to its edge
    double RingsMm[3] = {1, 2, 5};
    double SliceFieldMm = 60;           // the re-sliced views' field of view
    double SliceSpacingMm = 0.5;
  };
  TargetViewPicture() = default;
  explicit TargetViewPicture(const Options& options) : Opts(options) {}

  /// Draws the read-out against the plan (the slices from `volume`, or a message without one).
  /// False with `error` when there is nothing to draw (no valid read-out) or no display to draw on.
  bool Render(const TrajectoryAxis& plan, const GuidanceReadout& readout, vtkRPScalarVolumeNode* volume,
              std::string& error);
  /// The picture: RGB, 3 × PaneSize by PaneSize, VTK's order (row 0 at the bottom).
  vtkImageData* GetImage() const { return this->Image; }
  bool WritePNG(const std::string& path, std::string& error) const;
  /// The picture's pixel (column, row from the bottom) of a target-view point (mm).
  void TargetViewToPixel(const double xy[2], double pixel[2]) const;
  const Options& GetOptions() const { return this->Opts; }

  static constexpr double TipColour[3] = {0.1, 1.0, 0.1};

 private:
  Options Opts;
  vtkSmartPointer<vtkRenderWindow> Window;
  vtkSmartPointer<vtkImageData> Image;
};

}  // namespace rp
