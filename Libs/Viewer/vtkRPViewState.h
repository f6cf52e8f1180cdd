#ifndef vtkRPViewState_h
#define vtkRPViewState_h
// The viewer's own interaction state, which is not scene state: the mouse mode and the fiducial
// list that clicks add points to. (What the views show — slice planes, layers, layout — lives
// in the scene's slice and layout nodes.) Views and displayable managers observe its ModifiedEvent.
#include <string>

#include <vtkObject.h>

class vtkRPViewState : public vtkObject {
 public:
  static vtkRPViewState* New();
  vtkTypeMacro(vtkRPViewState, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum InteractionMode { ModeNavigate = 0, ModePlaceFiducial };
  vtkGetMacro(InteractionMode, int);
  vtkSetClampMacro(InteractionMode, int, ModeNavigate, ModePlaceFiducial);

  /// Fiducial list that clicks add points to in ModePlaceFiducial ("" = create one).
  const std::string& GetActiveFiducialListID() const { return this->ActiveFiducialListID; }
  void SetActiveFiducialListID(const std::string& id);

 protected:
  vtkRPViewState() = default;
  ~vtkRPViewState() override = default;

 private:
  vtkRPViewState(const vtkRPViewState&) = delete;
  void operator=(const vtkRPViewState&) = delete;
  int InteractionMode = ModeNavigate;
  std::string ActiveFiducialListID;
};

#endif
