#pragma once
// Internal to RoboPlanDicom: DCMTK set-up shared by the DICOM reader and writer, and the guard
// that keeps exceptions inside their API.
#include <exception>
#include <new>
#include <string>

namespace rp {
/// Registers DCMTK's decoders (JPEG, RLE) once and quiets its logger. DCMTK's JPEG-LS codec is
/// deliberately not used: see rpDicomJpegLsDecoder.h.
void InitializeDcmtk();

/// Runs `work` (returning success): running out of memory, or any other exception, becomes
/// `error` ("out of memory <doing> <path>", "<path>: <what>") and false, so a reader or writer
/// never throws past its API.
template <typename Work>
bool Guarded(const char* doing, const std::string& path, std::string& error, Work&& work) {
  try {
    return work();
  } catch (const std::bad_alloc&) {
    error = std::string("out of memory ") + doing + " " + path;
  } catch (const std::exception& e) {
    error = path + ": " + e.what();
  }
  return false;
}
}  // namespace rp
