#ifndef qRPLandmarkRegistrationPanel_h
#define qRPLandmarkRegistrationPanel_h
// The LandmarkRegistration module's Qt panel (seed 3.2.2, patient registration): choose the
// "from" (physical, tracker) and "to" (image, RAS) fiducial lists and the output transform
// (e.g. TrackerToRAS), collect physical points with the tracked stylus tip, and see every pair
// with its residual (coloured against the FRE threshold) and leave-one-out residual, FRE, the
// FRE expected from FLE, the predicted TRE at a target, and accepted/rejected with the reason.
// "Apply to tools" puts the tracker's tools under the accepted output so they move in image
// space. The panel only edits scene nodes and the logic; the logic recomputes when a point moves.
// The layout is qRPLandmarkRegistrationPanel.ui.
#include <QWidget>

#include <string>

#include <vtkWeakPointer.h>

#include "ui_qRPLandmarkRegistrationPanel.h"
#include "vtkRPFiducialListNode.h"
#include "vtkRPLandmarkRegistrationLogic.h"
#include "vtkRPScene.h"

class vtkObject;
class vtkRPLinearTransformNode;

/// The widgets (Ui::qRPLandmarkRegistrationPanel) are private: the accessors below are the
/// panel's interface.
class qRPLandmarkRegistrationPanel : public QWidget, private Ui::qRPLandmarkRegistrationPanel {
  Q_OBJECT
 public:
  /// Columns of the pair table.
  enum Column { LabelColumn = 0, FromColumn, ToColumn, ResidualColumn, LeaveOneOutColumn, NumberOfColumns };

  qRPLandmarkRegistrationPanel(vtkRPLandmarkRegistrationLogic* logic, vtkRPScene* scene, QWidget* parent = nullptr);
  ~qRPLandmarkRegistrationPanel() override;

  /// Selects nodes in the combos by name (as a user would); false when not found.
  bool SelectFromList(const QString& name);
  bool SelectToList(const QString& name);
  bool SelectOutputTransform(const QString& name);
  bool SelectToolTransform(const QString& name);
  /// The target follows the first point of this fiducial list (in the "to" list's coordinates).
  bool SelectTargetList(const QString& name);
  /// Creates a new output transform node (named `name`, made unique) and selects it.
  vtkRPLinearTransformNode* CreateOutputTransform(const QString& name = "TrackerToRAS");

  /// Adds the chosen tool's tip, in the "from" list's own coordinates, to the "from" list, with
  /// the label of the next unmatched "to" point. False with the reason in StatusText().
  bool CollectPoint();
  /// When the registration is accepted, puts the roots of the tracked tools (the chosen tool's
  /// chain and every other "...ToTracker" transform) and the "from" list under the output.
  bool ApplyToTools();
  /// Registers now (the "Register" button).
  bool Register();

  QString StatusText() const;
  QString FREText() const;
  QString TREText() const;
  QTableWidget* PairTable() const { return this->Table; }
  QPushButton* CollectButton() const { return this->CollectPointButton; }
  QPushButton* RegisterButton() const { return this->RegisterPushButton; }
  QPushButton* ApplyButton() const { return this->ApplyToolsButton; }
  QPushButton* RemoveButton() const { return this->RemovePointButton; }
  QDoubleSpinBox* ThresholdSpinBox() const { return this->Threshold; }
  QDoubleSpinBox* FLESpinBox() const { return this->Fle; }
  QComboBox* ModeComboBox() const { return this->Mode; }
  QDoubleSpinBox* TargetSpinBox(int axis) const { return this->Target[axis]; }
  QCheckBox* TargetCheckBox() const { return this->UseTarget; }
  /// "Jump slices to the selected point" (on by default): selecting a row moves the scene's
  /// slice nodes through its image point (or, without one, its registered physical point).
  QCheckBox* JumpSlicesCheckBox() const { return this->JumpSlices; }
  /// Jumps the slices to the selected row's point now; false when no row or point.
  bool JumpSlicesToSelectedPoint();

  /// Rebuilds the combos from the scene and the table/labels from the logic (public for tests).
  void UpdateNodeCombos();
  void UpdateResults();

 private:
  vtkRPFiducialListNode* FromList() const;
  vtkRPFiducialListNode* ToList() const;
  vtkRPLinearTransformNode* OutputTransform() const;
  vtkRPLinearTransformNode* ToolTransform() const;
  void OnInputsChanged();
  void OnSettingsChanged();
  void OnTargetChanged();
  void OnTargetFromSelectedRow();
  void OnRemoveSelectedPoint();
  void OnSceneChanged(vtkObject*, unsigned long, void*);
  void OnLogicOrListModified(vtkObject*, unsigned long, void*);
  void OnTargetListModified(vtkObject*, unsigned long, void*);
  void ObserveLists();
  void SetStatus(const QString& text, bool error);

  vtkWeakPointer<vtkRPLandmarkRegistrationLogic> Logic;
  vtkWeakPointer<vtkRPScene> Scene;
  QDoubleSpinBox* Target[3];  // TargetRSpin, TargetASpin, TargetSSpin
  unsigned long SceneTags[4] = {0, 0, 0, 0};
  unsigned long LogicTag = 0;
  vtkWeakPointer<vtkRPFiducialListNode> ObservedFrom;
  vtkWeakPointer<vtkRPFiducialListNode> ObservedTo;
  vtkWeakPointer<vtkRPFiducialListNode> ObservedTargetList;
  unsigned long FromTag = 0, ToTag = 0, TargetListTag = 0;
  bool UpdatingWidgets = false;
};

#endif
