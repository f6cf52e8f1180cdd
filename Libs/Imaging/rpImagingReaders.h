#pragma once
// The DataReaders Libs/Imaging contributes to the one loader (rpDataLoader.h): DICOM (a folder,
// a DICOMDIR or a DICOM file; rpDicomDataReader.cxx) and DICOM SEG / RTSTRUCT
// (rpDicomSegmentationDataReader.cxx). They register when the library loads, but a
// program that reaches them only through rp::LoadPath references no symbol of this library, and a
// linker that drops unreferenced libraries (--as-needed, as RoboPlan links, or static builds)
// would lose them without a word. Such a host therefore calls RegisterImagingReaders() when it
// starts (the viewer module's Setup, Libs/Application/ViewerModule.cxx); it is idempotent. The
// modules whose commands read DICOM call this library's functions, so it loads with them.
// Testing/Registration/rpRegistrationTest.cxx checks the list.
namespace rp {

/// Registers the imaging readers once (later calls do nothing). Returns true.
bool RegisterImagingReaders();

/// The DICOM SEG / RTSTRUCT reader (rpDicomSegmentationDataReader.cxx); RegisterImagingReaders
/// calls it.
bool RegisterDicomSegmentationReader();

}  // namespace rp
