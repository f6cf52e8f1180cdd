#pragma once
// The segment table of a Slicer .seg.nrrd, from its header's key/value fields (Segment<N>_ID,
// _Name, _LabelValue, _Layer, _Color, _Tags), without ITK or VTK: what rpSegmentationIO builds
// the node from, and what the segmentation-header fuzzer feeds arbitrary fields. Never throws;
// a malformed field is false with `error` naming the file and the key.
#include <map>
#include <string>
#include <vector>

#include "rpSegment.h"

namespace rp {

/// The tag under which the tissue class travels in Segment<N>_Tags ("key:value|...").
constexpr const char* SegmentTissueTag = "RoboPlan.TissueClass";

struct SegmentationHeaderSegment {
  rp::Segment Segment;
  int Layer = 0;  // which labelmap of a multi-layer file
};

/// Segments described by the header fields, in index order.
bool ParseSegmentationHeader(const std::string& path, const std::map<std::string, std::string>& metadata,
                             std::vector<SegmentationHeaderSegment>& segments, std::string& error);

}  // namespace rp
