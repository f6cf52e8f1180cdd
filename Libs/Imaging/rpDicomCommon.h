#pragma once
// Internal to RoboPlanImaging: DCMTK set-up shared by the DICOM reader and writer.
namespace rp {
/// Registers DCMTK's decoders (JPEG, RLE) once and quiets its logger. DCMTK's JPEG-LS codec is
/// deliberately not used: see rpDicomJpegLsDecoder.h.
void InitializeDcmtk();
}  // namespace rp
