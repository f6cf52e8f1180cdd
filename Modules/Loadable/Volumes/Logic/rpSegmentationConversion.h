#pragma once
// `roboplan convert` for segmentations (rpVolumesCommands.cxx declares the options):
//  - into a .seg.nrrd: a DICOM SEG or RTSTRUCT (with --reference: on that series' grid), the
//    segmentation a DICOM folder holds (read whole by the one loader, rp::LoadPath: a SEG on the
//    series it references; --series picks one of several), another .seg.nrrd, or a labelmap
//    volume (one segment per label value, named and coloured by --labels: rpLabelmapInput.h);
//  - from a .seg.nrrd into a DICOM SEG on the grid of --reference.
#include <optional>
#include <ostream>

namespace rp {

class ArgParser;

/// Runs the conversion when `in` → `out` is one of the above and returns the exit code; nothing
/// when it is a volume or scene conversion.
std::optional<int> ConvertSegmentation(const ArgParser& parser, std::ostream& out, std::ostream& err);

}  // namespace rp
