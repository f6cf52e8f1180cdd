#include "rpDicomCommon.h"

#include <cstdlib>
#include <mutex>
#include <string>

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dcrledrg.h>
#include <dcmtk/dcmdata/dctk.h>
#include <dcmtk/dcmjpeg/djdecode.h>
#include <dcmtk/oflog/oflog.h>

namespace rp {

void InitializeDcmtk() {
  static std::once_flag once;
  std::call_once(once, []() {
    DJDecoderRegistration::registerCodecs();
    DcmRLEDecoderRegistration::registerCodecs();
    // Elements written as UN (e.g. by gdcmconv from an implicit-VR file: RescaleIntercept,
    // PixelSpacing...) are read with their dictionary VR, or their values would be lost.
    dcmEnableUnknownVRConversion.set(OFTrue);
    // DCMTK logs parser warnings on stderr; our messages say what went wrong instead.
    // ROBOPLAN_DCMTK_LOG=1 shows DCMTK's own warnings and errors (e.g. which attribute of a SEG
    // it finds missing).
    const char* log = std::getenv("ROBOPLAN_DCMTK_LOG");
    OFLog::configure(log && *log && std::string(log) != "0" ? OFLogger::WARN_LOG_LEVEL : OFLogger::FATAL_LOG_LEVEL);
    // Unregistered at exit, so the codec list is not reported as a leak.
    std::atexit([]() {
      DcmRLEDecoderRegistration::cleanup();
      DJDecoderRegistration::cleanup();
    });
  });
}

}  // namespace rp
