#ifndef qRPSliceFollowCheckBox_h
#define qRPSliceFollowCheckBox_h
// "Slices follow <tool>": a check box that makes the scene's slice nodes follow a node's tip
// (vtkRPSliceNode::SetAllSlicesFollow), so a module panel drives the views without a view
// pointer. Ticked before the node exists, it applies when the node appears; when the slices
// are made to follow something else (another module, the Data panel) it unticks; unticking
// stops only its own following. The panel calls Refresh() from its display-rate timer.
#include <string>

#include <QCheckBox>

#include <vtkWeakPointer.h>

#include "vtkRPScene.h"

class qRPSliceFollowCheckBox : public QCheckBox {
  Q_OBJECT
 public:
  explicit qRPSliceFollowCheckBox(const QString& text, QWidget* parent = nullptr);
  /// For a panel's .ui file (a promoted QCheckBox: uic constructs it with its parent, then sets the text).
  explicit qRPSliceFollowCheckBox(QWidget* parent = nullptr) : qRPSliceFollowCheckBox(QString(), parent) {}

  void SetScene(vtkRPScene* scene);
  /// The node whose tip the slices follow when ticked ("" while it does not exist).
  void SetFollowNodeID(const std::string& id);
  const std::string& GetFollowNodeID() const { return this->NodeID; }
  /// True when every slice node follows this box's node.
  bool IsFollowing() const;
  /// Applies a pending tick, or unticks when the slices follow something else.
  void Refresh();

 private:
  void OnToggled(bool on);
  vtkWeakPointer<vtkRPScene> Scene;
  std::string NodeID;
  bool Pending = false;
};

#endif
