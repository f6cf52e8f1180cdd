#pragma once
// PLUS device-set configurations (PlusDeviceSet_*.xml), read into plain structs without opening
// any device: what RoboPlan can run of them (NDI trackers: NDITracker, PolarisTracker,
// AuroraTracker over a serial port or TCP, their tools and ROM files), the fixed transforms of
// CoordinateDefinitions, and the PlusOpenIGTLinkServer section (port, output channel, the
// default client's message types and transform/image/string names, SendValidTransformsOnly,
// keep-alive), and fCal's phantom registration settings (PhantomDefinition landmarks, the
// landmark registration and pivot calibration algorithms' frames and thresholds). Everything else is named in Refused with the reason (other devices: ultrasound,
// video, virtual mixers, other trackers; attributes we do not honour), so that one message can
// tell the user, and the rest still runs. The XML is read by rp::ParseXml (VTK's expat parser,
// as PLUS reads it); malformed XML is named with its line. No input makes it crash or hang.
//
// Paths as PLUS resolves them: a RomFile is taken relative to PLUS's DeviceSetConfigurationDirectory
// (vtkPlusConfig::GetDeviceSetConfigurationPath; PLUS's default is <PlusLibData>/ConfigFiles, the
// folder its launcher lists), an absolute path as it is. We try, in order: the directory the
// user names (--plus-config-dir, PLUS's DeviceSetConfigurationDirectory), the configuration
// file's own folder, then its parent folders (a file in ConfigFiles/Robarts/ or StableTest/
// finds ConfigFiles/NdiToolDefinitions as PLUS run from ConfigFiles does). SerialPort="N" is
// PLUS's 1-based port number; on Linux ndicapi maps it to /dev/ttyS0, /dev/ttyS1, /dev/ttyUSB0
// .. /dev/ttyUSB5 for N = 1..8 (PLUS probes ports when none is given; we do not, a port must be
// given).
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

class vtkXMLDataElement;

namespace rp {
namespace plus {

struct Tool {
  std::string Id;             // DataSource Id: the tool transform is <Id>To<ToolReferenceFrame>
  std::string PortName;       // as written, "" for a wireless tool
  int WiredPort = -1;         // PortName read as PLUS reads it (channel * 100 + port - 1), -1 wireless
  std::string RomFile;        // as written; with a PortName, a virtual SROM written over the tool's
  std::string RomPath;        // resolved, "" when none or not found
  std::vector<std::string> RomTried;  // paths tried when not found
};

struct NdiTracker {
  std::string Id, Type;                // Type: NDITracker, PolarisTracker, AuroraTracker
  std::string SerialPort;              // as written (PLUS's 1-based number)
  std::string SerialDevice;            // the Linux device ndicapi maps it to, "" when none
  int BaudRate = 0;                    // 0: not given
  std::string NetworkHostname;         // Vega/Lyra over TCP
  int NetworkPort = 8765;
  std::string ToolReferenceFrame = "Tracker";
  double AcquisitionRate = 0;          // Hz, 0: not given
  int MeasurementVolumeNumber = 0;
  std::vector<Tool> Tools;             // tools it will track (a ROM file found)
  bool Tcp() const { return !this->NetworkHostname.empty(); }
};

struct FixedTransform {
  std::string From, To;
  double Matrix[16];                   // row-major, as PLUS writes it
  double Error = -1;                   // mm, -1: not given
  std::string Date;
};

struct TransformName {
  std::string Name, From, To;
};

struct ImageName {
  std::string Name, EmbeddedTransformToFrame;
};

struct Server {
  bool Present = false;
  int ListeningPort = -1;
  std::string ListeningAddress;                // RoboPlan's attribute (PLUS listens on every interface): "" = 127.0.0.1
  std::string OutputChannelId;
  bool SendValidTransformsOnly = true;         // PLUS's default
  double KeepAliveIntervalSec = 0.25;          // PLUS's default (half its 0.5 s socket timeout)
  int MaxNumberOfIgtlMessagesToSend = 100;
  double MaxTimeSpentWithProcessingMs = 50;
  double DefaultClientSendTimeoutSec = 0.5;
  std::vector<std::string> MessageTypes;       // DefaultClientInfo
  std::vector<TransformName> TransformNames;
  std::vector<ImageName> ImageNames;
  std::vector<std::string> StringNames;
};

/// fCal's phantom registration settings (`roboplan phantom-registration` reads them from here):
/// PhantomDefinition/Geometry/Landmarks in their order, vtkPlusPhantomLandmarkRegistrationAlgo's
/// frames and detection settings, and vtkPlusPivotCalibrationAlgo's stylus frame, as written
/// (unset when absent or not a number; the defaults are the registration's).
struct PhantomLandmark {
  std::string Name;                    // "#N" (1-based) when the file names none
  double Position[3] = {0, 0, 0};      // Phantom coordinates, mm
};

struct PhantomRegistrationSettings {
  bool HasLandmarks = false;           // a PhantomDefinition/Geometry/Landmarks element
  std::vector<PhantomLandmark> Landmarks;
  std::string LandmarkProblem;         // the first landmark without Position="x y z" ("" when none)
  std::string PhantomFrame, ReferenceFrame, StylusTipFrame, StylusFrame;  // "" when not given
  std::optional<double> AcquisitionRate, FilterWindowTimeSec, DetectionTimeSec;
  std::optional<double> StylusShaftMinimumDisplacementThresholdMm, StylusTipMaximumDisplacementThresholdMm;
};

/// Something of the file RoboPlan does not set up, and why.
struct Refusal {
  std::string What, Why;
};

struct Configuration {
  std::string Source;                  // file path (or a name for text)
  std::string Version, Name, Description;
  std::vector<NdiTracker> Trackers;
  std::vector<FixedTransform> Transforms;
  Server OpenIGTLinkServer;
  PhantomRegistrationSettings PhantomRegistration;
  std::vector<Refusal> Refused;
  /// One message naming everything refused ("" when nothing was).
  std::string RefusedMessage() const;
};

/// Where RomFile paths are looked for besides the configuration's own folders.
struct ResolveOptions {
  std::string DeviceSetConfigurationDirectory;  // PLUS's setting; "" when not given
};

/// Reads a configuration file. False with `error` (unreadable file, malformed XML with its line,
/// not a PlusConfiguration); refusals are not errors.
bool ReadConfiguration(const std::string& path, const ResolveOptions& options, Configuration& configuration,
                       std::string& error);
/// The same from text; `source` names it and its folder anchors relative paths.
bool ParseConfiguration(const std::string& text, const std::string& source, const ResolveOptions& options,
                        Configuration& configuration, std::string& error);
/// From an element already parsed.
bool ReadConfigurationElement(vtkXMLDataElement* root, const std::string& source, const ResolveOptions& options,
                              Configuration& configuration, std::string& error);

/// A client's CLIENTINFO (PlusServer's <ClientInfo> XML, laid out as DefaultClientInfo): its
/// message types and transform, image and string names replace those in `info` (other fields
/// untouched). False with `error` for malformed XML or another root element.
bool ParseClientInfo(const std::string& xml, Server& info, std::string& error);

/// PLUS's SerialPort number → the Linux device ndicapi opens ("" when it has none).
std::string SerialDeviceForPort(int plusPortNumber);

nlohmann::json ToJson(const Configuration& configuration);

}  // namespace plus
}  // namespace rp
