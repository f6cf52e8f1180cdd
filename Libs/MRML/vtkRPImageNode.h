#ifndef vtkRPImageNode_h
#define vtkRPImageNode_h
// Base of nodes that hold a 3D image in RAS: the vtkImageData has origin 0 and spacing 1 and
// the IJK-to-RAS matrix carries spacing, directions and origin (Slicer's convention).
#include <vtkSmartPointer.h>

#include "vtkRPTransformableNode.h"

#include <vtkImageData.h>
#include <vtkMatrix4x4.h>

class vtkRPImageNode : public vtkRPTransformableNode {
 public:
  vtkTypeMacro(vtkRPImageNode, vtkRPTransformableNode);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  vtkImageData* GetImageData() const { return this->ImageData; }
  /// Takes the image; its origin and spacing are reset to 0 and 1 (geometry lives in IJKToRAS;
  /// use SetImageDataKeepGeometry to move a vtkImageData's own origin/spacing into IJKToRAS).
  void SetImageData(vtkImageData* image);
  void SetImageDataKeepGeometry(vtkImageData* image);

  vtkMatrix4x4* GetIJKToRASMatrix() const { return this->IJKToRAS; }
  void SetIJKToRASMatrix(const vtkMatrix4x4* ijkToRAS);
  void GetRASToIJKMatrix(vtkMatrix4x4* rasToIJK) const;
  /// Builds IJKToRAS from spacing, origin (RAS) and direction columns (RAS unit vectors).
  void SetGeometry(const double spacing[3], const double originRAS[3], const double directions[3][3]);
  void GetSpacing(double spacing[3]) const;
  void GetOrigin(double originRAS[3]) const;
  /// RAS bounds of the voxel centres.
  void GetRASBounds(double bounds[6]) const;

  void WriteProperties(PropertyMap& properties) const override;
  void ReadProperties(const PropertyMap& properties) override;

 protected:
  vtkRPImageNode();
  ~vtkRPImageNode() override;

 private:
  vtkRPImageNode(const vtkRPImageNode&) = delete;
  void operator=(const vtkRPImageNode&) = delete;
  vtkSmartPointer<vtkImageData> ImageData;
  vtkSmartPointer<vtkMatrix4x4> IJKToRAS;
};

#endif
