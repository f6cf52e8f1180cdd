#pragma once
// The DataReaders Libs/Imaging contributes to the one loader (rpDataLoader.h): DICOM (a folder,
// a DICOMDIR or a DICOM file; rpDicomDataReader.cxx). They register when the library loads, but a
// program that reaches them only through rp::LoadPath references no symbol of this library, and a
// linker that drops unreferenced libraries (--as-needed, static builds) would lose them without
// a word. Hosts therefore call RegisterImagingReaders() at start-up (roboplanMain.cxx); it is
// idempotent. Testing/Registration/rpRegistrationTest.cxx checks the list.
namespace rp {

/// Registers the imaging readers once (later calls do nothing). Returns true.
bool RegisterImagingReaders();

}  // namespace rp
