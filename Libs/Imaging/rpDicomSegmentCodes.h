#pragma once
// The segment codes (SNOMED CT, "SCT") a DICOM SEG gets for a segment, as dcmqi and 3D Slicer's
// terminology write them: the knee's bones by name (a whole word of the segment's ID or name),
// other bone by tissue class, anything else generic Tissue. Plain C++ (no DCMTK), in
// RoboPlanImaging: the SEG writer and reader (libRoboPlanDicomObjects.so, loaded on first use)
// and the labelmap input (a segment's tissue class by its name) share it.
#include <string>

namespace rp {

struct DicomSegmentCode {
  const char* Key;  // matched against the segment's ID and name (lower case); "" = generic
  const char* CategoryValue;
  const char* CategoryMeaning;
  const char* TypeValue;
  const char* TypeMeaning;
  const char* TissueClass;
};

/// The code a segment with this ID, name and tissue class is written with.
const DicomSegmentCode& DicomSegmentCodeFor(const std::string& id, const std::string& name,
                                            const std::string& tissueClass);

/// The tissue class of a SEG segment's property type code value; "" when it is none of ours.
std::string DicomTissueClassOfType(const std::string& typeValue);

}  // namespace rp
