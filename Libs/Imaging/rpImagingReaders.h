#pragma once
// The DataReaders Libs/Imaging contributes to the one loader (rpDataLoader.h): DICOM (a folder,
// a DICOMDIR or a DICOM file; rpDicomDataReader.cxx) and DICOM SEG / RTSTRUCT
// (rpDicomSegmentationDataReader.cxx), registered by RegisterImagingReaders(). A program that
// reaches them only through rp::LoadPath references no symbol of this library, and a linker that
// drops unreferenced libraries (--as-needed, as RoboPlan links, or static builds) would lose a
// registration made only when the library loads; so a host calls RegisterImagingReaders() when it
// starts (the viewer module's Setup, Libs/Application/ViewerModule.cxx). It is idempotent; the
// library still also calls it when it loads (rpDicomDataReader.cxx), so that the modules whose
// commands read DICOM, and tests linking it directly, need no call of their own.
// Testing/Registration/rpRegistrationTest.cxx checks the list.
namespace rp {

/// Registers the imaging readers once (later calls do nothing). Returns true.
bool RegisterImagingReaders();

/// The DICOM reader RegisterImagingReaders registers (for a caller that asks the loader which
/// reader a path goes to, as rp::ReadVolume does).
class DataReader;
const DataReader* GetDicomDataReader();

/// The DICOM SEG / RTSTRUCT reader (rpDicomSegmentationDataReader.cxx); RegisterImagingReaders
/// calls it.
bool RegisterDicomSegmentationReader();

}  // namespace rp
