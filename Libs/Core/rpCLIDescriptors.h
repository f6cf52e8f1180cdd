#pragma once
// Descriptors of a `roboplan <command>` made from its ArgParser declarations, for the tools that
// run command-line programs for their users:
//  - the Slicer Execution Model XML (`--xml`) that 3D Slicer reads to list and run CLI modules
//    (and GenerateCLP compiles); longflags use '_' for '-' (Slicer accepts no '-' in them, the
//    parser accepts both spellings);
//  - the Boutiques descriptor (`--boutiques`, schema 0.5) used by CBRAIN, Nipype-style runners
//    and `bosh`. A repeatable option becomes a list whose separator repeats the flag.
// The built-in `--json` is left out of both: it only changes what is printed.
#include <string>

namespace rp {

class ArgParser;

std::string SlicerExecutionModelXML(const ArgParser& parser);
std::string BoutiquesDescriptor(const ArgParser& parser);

}  // namespace rp
