#pragma once
// Telling a file that may be DICOM without DCMTK: what decides whether the DICOM library
// (libRoboPlanDicom.so, rpDicomEntries.h) is loaded at all, and which files its scan parses.
#include <string>

namespace rp {

/// A DICOM Part 10 file: a 128-byte preamble, then "DICM".
bool HasDicomMagic(const std::string& path);

/// What might be DICOM and is worth parsing: the magic, or a name ending .dcm or without
/// extension (raw datasets); other files (NRRD, models...) are not parsed as DICOM.
bool MaybeDicomFile(const std::string& path);

}  // namespace rp
