#ifndef qRPFixtureChoiceWidget_h
#define qRPFixtureChoiceWidget_h
// The Guidance group of the Haptics and Drilling panels (issue 38): which of the plan's virtual
// fixtures act on the tool — the trajectory to follow, axis guidance, depth stop, forbidden
// regions (the structures at risk), a surface constraint on a cut plane or a model — and a status
// line saying which fixtures act and, while the servo runs, what each does (engaged or not, its
// distance, its force): the read-out a surgeon needs. Every change is applied at once through the
// panel's apply function (its logic's SetPlanFixtures); when that refuses, the status line names
// the problem and the boxes go back to the fixtures in use. Its node lists follow the scene
// (nodes added or removed), and the fixtures follow their plan nodes (a trajectory dragged while
// they act is applied again within a quarter second); main thread only. Layout:
// qRPFixtureChoiceWidget.ui.
#include <functional>
#include <memory>
#include <string>

#include <QGroupBox>
#include <QString>

#include "rpPlanFixtures.h"

class QCheckBox;
class QComboBox;
class QTimer;
class vtkRPScene;
namespace Ui {
class qRPFixtureChoiceWidget;
}
namespace rp {
class SceneNodesWatch;
struct FixtureStatus;
}  // namespace rp

class qRPFixtureChoiceWidget : public QGroupBox {
  Q_OBJECT
 public:
  explicit qRPFixtureChoiceWidget(QWidget* parent = nullptr);
  ~qRPFixtureChoiceWidget() override;

  /// Applies a choice (the logic's SetPlanFixtures): false with `error` keeps the fixtures in use.
  using ApplyFunction = std::function<bool(const rp::PlanFixtureChoice& choice, std::string& error)>;
  /// The fixtures in use (the logic's GetPlanFixtures).
  using InUseFunction = std::function<std::shared_ptr<const rp::FixtureSet>()>;
  /// The scene whose plan nodes are listed (null: none), and the panel's logic's two calls.
  void Setup(vtkRPScene* scene, ApplyFunction apply, InUseFunction inUse);

  /// The choice as the boxes show it.
  rp::PlanFixtureChoice Choice() const;
  /// Applies the boxes' choice now (also done on every change); false when refused.
  bool ApplyChoice();
  /// Re-reads the trajectories, cut planes and models (also done by its timer when nodes come or go).
  void RefreshNodes();

  /// The status line: the fixtures in use and, while the servo runs, its latest reports (`running`
  /// null when stopped). The panel calls it from its display timer (and after stopping).
  void ShowFixtures(const rp::FixtureStatus* running);
  /// The status line, one line per fixture.
  static QString DescribeFixtures(const rp::FixtureSet* set, const rp::FixtureStatus* running);
  QString StatusText() const;

  QComboBox* TrajectoryComboBox() const;
  QComboBox* SurfaceComboBox() const;
  QCheckBox* AxisCheckBox() const;
  QCheckBox* DepthCheckBox() const;
  QCheckBox* ForbiddenCheckBox() const;
  QCheckBox* SurfaceCheckBox() const;

 signals:
  /// A choice was applied (the fixtures in use changed).
  void FixturesChanged();

 private:
  void OnChanged();
  void SetBoxes(const rp::PlanFixtureChoice& choice);
  /// Changes when a plan node (trajectory, cut plane, model) is modified.
  unsigned long PlanSignature() const;

  std::unique_ptr<Ui::qRPFixtureChoiceWidget> UI;
  vtkRPScene* Scene = nullptr;  // not owned: the host's scene outlives its panels
  std::unique_ptr<rp::SceneNodesWatch> Watch;
  QTimer* WatchTimer;
  ApplyFunction Apply;
  InUseFunction InUse;
  rp::PlanFixtureChoice Applied;  // the choice in use (the boxes go back to it when one is refused)
  unsigned long AppliedSignature = 0;  // the plan nodes as they were when it was applied
  QString Refusal;  // why the last choice was refused ("" when it was applied)
};

#endif
