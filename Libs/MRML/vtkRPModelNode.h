#ifndef vtkRPModelNode_h
#define vtkRPModelNode_h
// A surface model in RAS: vtkPolyData + display (colour, opacity, visibility) + the tissue class
// the haptics and the viewer use. `Haptic` marks a model the haptic renderer touches; a tissue
// may have a display model and a separate (coarser) haptic model. `SliceIntersectionVisibility`
// is whether the slice views draw the model's outline where the slice cuts it (Slicer's display
// `visibility2D`); on by default. `Protection` flags the model a structure at risk (rpProtection.h).
#include <string>

#include <vtkSmartPointer.h>

#include "rpProtection.h"
#include "vtkRPTransformableNode.h"

#include <vtkPolyData.h>

class vtkRPModelNode : public vtkRPTransformableNode {
 public:
  static vtkRPModelNode* New();
  vtkTypeMacro(vtkRPModelNode, vtkRPTransformableNode);
  void PrintSelf(ostream& os, vtkIndent indent) override;
  vtkRPNode* CreateNodeInstance() override;
  const char* GetNodeTagName() override { return "Model"; }

  vtkPolyData* GetPolyData() const { return this->PolyData; }
  void SetPolyData(vtkPolyData* polyData);

  vtkGetVector3Macro(Color, double);
  vtkSetVector3Macro(Color, double);
  vtkGetMacro(Opacity, double);
  vtkSetClampMacro(Opacity, double, 0.0, 1.0);
  vtkGetMacro(Visibility, bool);
  vtkSetMacro(Visibility, bool);
  vtkBooleanMacro(Visibility, bool);
  vtkGetMacro(SliceIntersectionVisibility, bool);
  vtkSetMacro(SliceIntersectionVisibility, bool);
  vtkBooleanMacro(SliceIntersectionVisibility, bool);
  vtkGetMacro(Haptic, bool);
  vtkSetMacro(Haptic, bool);
  vtkBooleanMacro(Haptic, bool);
  const std::string& GetTissueClass() const { return this->TissueClass; }
  void SetTissueClass(const std::string& tissueClass);
  /// A structure at risk: protected, with a safety margin (planning, drilling and guidance).
  const rp::StructureProtection& GetProtection() const { return this->Protection; }
  void SetProtection(const rp::StructureProtection& protection);

  void WriteProperties(PropertyMap& properties) const override;
  void ReadProperties(const PropertyMap& properties) override;

 protected:
  vtkRPModelNode();
  ~vtkRPModelNode() override;

 private:
  vtkRPModelNode(const vtkRPModelNode&) = delete;
  void operator=(const vtkRPModelNode&) = delete;
  vtkSmartPointer<vtkPolyData> PolyData;
  double Color[3] = {0.9, 0.9, 0.9};
  double Opacity = 1.0;
  bool Visibility = true;
  bool SliceIntersectionVisibility = true;
  bool Haptic = false;
  std::string TissueClass;
  rp::StructureProtection Protection;
};

#endif
