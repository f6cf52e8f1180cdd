#pragma once
// Internal to RoboPlanImaging: DCMTK set-up shared by the DICOM reader and writer.
namespace rp {
/// Registers DCMTK's decoders (JPEG, JPEG-LS, RLE) once and quiets its logger.
void InitializeDcmtk();
}  // namespace rp
