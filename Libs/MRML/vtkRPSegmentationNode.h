#ifndef vtkRPSegmentationNode_h
#define vtkRPSegmentationNode_h
// A segmentation: one labelmap (vtkImageData of integer labels, IJK-to-RAS as for volumes)
// and a segment table (ID, name, label value, colour, tissue class). Several tissues share one
// labelmap, as in a single-layer Slicer .seg.nrrd.
#include <string>
#include <vector>

#include "rpSegment.h"
#include "vtkRPImageNode.h"

class vtkRPSegmentationNode : public vtkRPImageNode {
 public:
  static vtkRPSegmentationNode* New();
  vtkTypeMacro(vtkRPSegmentationNode, vtkRPImageNode);
  void PrintSelf(ostream& os, vtkIndent indent) override;
  vtkRPNode* CreateNodeInstance() override;
  const char* GetNodeTagName() override { return "Segmentation"; }

  using Segment = rp::Segment;

  int GetNumberOfSegments() const { return static_cast<int>(this->Segments.size()); }
  const Segment& GetNthSegment(int n) const { return this->Segments.at(static_cast<size_t>(n)); }
  const std::vector<Segment>& GetSegments() const { return this->Segments; }
  /// Adds or replaces (same ID) a segment. Returns its index.
  int SetSegment(const Segment& segment);
  bool RemoveSegment(const std::string& segmentID);
  void RemoveAllSegments();
  const Segment* GetSegmentByID(const std::string& id) const;
  const Segment* GetSegmentByLabel(int labelValue) const;
  /// Smallest label value not used by any segment (>= 1).
  int GetUnusedLabelValue() const;
  /// Whether a labelmap may hold voxels of this VTK scalar type: integer labels only.
  static bool IsLabelScalarType(int vtkType);
  /// Reference role to the volume the segmentation was drawn on (Slicer's name for it): a DICOM
  /// SEG's or RTSTRUCT's referenced series. The views show that volume under the segmentation.
  static const char* ReferenceImageGeometryRole() { return "referenceImageGeometryRef"; }

  void WriteProperties(PropertyMap& properties) const override;
  void ReadProperties(const PropertyMap& properties) override;

 protected:
  vtkRPSegmentationNode() = default;
  ~vtkRPSegmentationNode() override = default;

 private:
  vtkRPSegmentationNode(const vtkRPSegmentationNode&) = delete;
  void operator=(const vtkRPSegmentationNode&) = delete;
  std::vector<Segment> Segments;
};

#endif
