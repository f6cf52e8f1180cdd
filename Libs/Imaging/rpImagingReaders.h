#pragma once
// The DataReaders Libs/Imaging contributes to the one loader (rpDataLoader.h): DICOM (a folder,
// a DICOMDIR or a DICOM file; rpDicomDataReader.cxx) and DICOM SEG / RTSTRUCT
// (rpDicomSegmentationDataReader.cxx), registered by RegisterImagingReaders(). A program that
// reaches them only through rp::LoadPath references no symbol of this library, and a linker that
// drops unreferenced libraries (--as-needed, as RoboPlan links, or static builds) would lose a
// registration made when the library loads; so nothing registers at load: each owner that reads
// through the loader calls RegisterImagingReaders() when it starts, in the one place it registers
// its things — the viewer module's Setup (Libs/Application/ViewerModule.cxx) and the Setup of
// each module whose work reads DICOM through the loader (Volumes, SegmentationToMesh, Drilling,
// Planning, Demo: their <Name>Module.cxx); a test that reads DICOM through the loader without a
// module calls it too. It is idempotent.
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
