#include "rpPoseSourceKinds.h"

#include "rpIgtlClient.h"
#include "rpNdiTracker.h"
#include "rpSimulatedPolaris.h"
#include "rpTrackingRecording.h"

namespace rp {

std::vector<PoseSourceRegistry::Entry> BuiltInPoseSources() {
  return {
      {"serial", "NDI Polaris/Aurora on a serial port (Combined API)", "/dev/ttyUSB0", NdiTracker::Create},
      {"tcp", "NDI Polaris Vega/Lyra over Ethernet (Combined API, TCP)", "host:8765", NdiTracker::CreateTcp},
      {"igtl", "OpenIGTLink server (PLUS, Slicer, a scanner)", "127.0.0.1:18944", IgtlClient::Create},
      {"simulator", "simulated NDI Polaris on a pseudo-terminal (serial path, no hardware)", "",
       SimulatedPolaris::Create},
      {"replay", "a recording (roboplan track --record, or PLUS .igs.mha/.igs.nrrd) played back", "session.txt",
       RecordingPlayer::Create},
  };
}

}  // namespace rp
