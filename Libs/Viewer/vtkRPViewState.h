#ifndef vtkRPViewState_h
#define vtkRPViewState_h
// What the views show, apart from the scene itself: the slice point (RAS) where the three slice
// views cut, the layout, which volumes are the background and foreground layers, and the
// interaction mode. Views and displayable managers observe its ModifiedEvent; navigation can
// drive the slice point (e.g. from a tracked tool tip) without knowing about the views.
#include <string>

#include <vtkObject.h>

class vtkRPViewState : public vtkObject {
 public:
  static vtkRPViewState* New();
  vtkTypeMacro(vtkRPViewState, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum Layout { LayoutFourUp = 0, LayoutOneUp3D, LayoutOneUpAxial, LayoutOneUpSagittal, LayoutOneUpCoronal };
  static const char* GetLayoutAsString(int layout);  // "4up", "3d", "axial", "sagittal", "coronal"
  static int GetLayoutFromString(const std::string& text);  // -1 when not recognised

  enum InteractionMode { ModeNavigate = 0, ModePlaceFiducial };

  vtkGetVector3Macro(SlicePointRAS, double);
  vtkSetVector3Macro(SlicePointRAS, double);
  vtkGetMacro(Layout, int);
  vtkSetClampMacro(Layout, int, LayoutFourUp, LayoutOneUpCoronal);
  vtkGetMacro(InteractionMode, int);
  vtkSetClampMacro(InteractionMode, int, ModeNavigate, ModePlaceFiducial);

  const std::string& GetBackgroundVolumeID() const { return this->BackgroundVolumeID; }
  void SetBackgroundVolumeID(const std::string& id);
  const std::string& GetForegroundVolumeID() const { return this->ForegroundVolumeID; }
  void SetForegroundVolumeID(const std::string& id);
  vtkGetMacro(ForegroundOpacity, double);
  vtkSetClampMacro(ForegroundOpacity, double, 0.0, 1.0);
  /// Fiducial list that clicks add points to in ModePlaceFiducial ("" = create one).
  const std::string& GetActiveFiducialListID() const { return this->ActiveFiducialListID; }
  void SetActiveFiducialListID(const std::string& id);
  /// Whether the three slices are drawn in the 3D view.
  vtkGetMacro(SlicesVisibleIn3D, bool);
  vtkSetMacro(SlicesVisibleIn3D, bool);

 protected:
  vtkRPViewState() = default;
  ~vtkRPViewState() override = default;

 private:
  vtkRPViewState(const vtkRPViewState&) = delete;
  void operator=(const vtkRPViewState&) = delete;
  double SlicePointRAS[3] = {0, 0, 0};
  int Layout = LayoutFourUp;
  int InteractionMode = ModeNavigate;
  std::string BackgroundVolumeID, ForegroundVolumeID, ActiveFiducialListID;
  double ForegroundOpacity = 0.5;
  bool SlicesVisibleIn3D = true;
};

#endif
