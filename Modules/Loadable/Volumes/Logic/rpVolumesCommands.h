#pragma once
// The Volumes module's CLI subcommands (headless, testable in-process):
//   roboplan dicom <folder|DICOMDIR>                 list the image series found
//   roboplan convert <in> <out>                      DICOM / NRRD / NIfTI / MetaImage to each other
//   roboplan phantom --out <dir> [--size small|full] the knee phantom as DICOM series + truth
//   roboplan register-volumes <fixed> <moving> --out <transform>   rigid MI registration
//   roboplan compare-labels <segmentation> <truth>   Dice and surface distance per segment
// Exit codes: 0 ok, 1 the work failed (stderr names the problem), 2 bad arguments.
#include <ostream>
#include <string>
#include <vector>

namespace rp {

int RunDicomCommand(const std::vector<std::string>& arguments, std::ostream& out, std::ostream& err);
int RunConvertCommand(const std::vector<std::string>& arguments, std::ostream& out, std::ostream& err);
int RunPhantomCommand(const std::vector<std::string>& arguments, std::ostream& out, std::ostream& err);
int RunRegisterVolumesCommand(const std::vector<std::string>& arguments, std::ostream& out, std::ostream& err);
int RunCompareLabelsCommand(const std::vector<std::string>& arguments, std::ostream& out, std::ostream& err);

}  // namespace rp
