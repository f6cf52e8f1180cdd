#pragma once
// PlusServer's remote commands, as Slicer's OpenIGTLinkRemote sends them: a `COMMAND` message
// (OpenIGTLink v3) or the older `STRING` named `CMD_<uid>`, both holding PLUS's command XML
// `<Command Name="StartRecording" OutputFilename="x.igs.mha" />`. The server answers a COMMAND
// with `RTS_COMMAND` (same id, `Status`/`Message` metadata) and a CMD_ string with the STRING
// `ACK_<uid>` holding `<CommandReply Status="SUCCESS|FAIL" Message="..." />`.
//
// A command is one function and one registration line (RP_REGISTER_IGTL_COMMAND); it acts on
// the server only through IgtlCommandTarget. Commands are rare control messages: parsing them
// allocates (the pose stream does not).
#include <map>
#include <string>
#include <vector>

#include "rpToolPose.h"

namespace rp {

struct IgtlCommandRequest {
  std::string Name;
  std::map<std::string, std::string> Attributes;  // the Command element's attributes
  std::string Attribute(const std::string& key, const std::string& fallback = "") const;
};

struct IgtlCommandReply {
  bool Success = true;
  std::string Message;
};

/// What commands act on (the OpenIGTLink server implements it).
class IgtlCommandTarget {
 public:
  virtual ~IgtlCommandTarget() = default;
  virtual std::vector<std::string> ChannelIds() const = 0;
  virtual std::vector<std::string> DeviceIds() const = 0;
  virtual bool StartRecording(const std::string& file, std::string& error) = 0;
  /// Writes the recording; `file` gets its name.
  virtual bool StopRecording(std::string& file, std::string& error) = 0;
  /// A transform by PLUS name ("StylusTipToReference"): row-major 4x4 and its status.
  virtual bool GetTransform(const std::string& name, double m[16], ToolState& state, std::string& error) = 0;
  virtual bool UpdateTransform(const std::string& name, const double m[16], std::string& error) = 0;
};

using IgtlCommandHandler = IgtlCommandReply (*)(const IgtlCommandRequest& request, IgtlCommandTarget& target);

bool RegisterIgtlCommand(const char* name, IgtlCommandHandler handler);
/// The registered command names, sorted.
std::vector<std::string> IgtlCommandNames();

/// Parses PLUS's command XML; false with a message for anything else.
bool ParseIgtlCommand(const std::string& xml, IgtlCommandRequest& request, std::string& error);
/// Parses and runs; an unknown command or bad XML is a FAIL reply naming it.
IgtlCommandReply RunIgtlCommand(const std::string& xml, IgtlCommandTarget& target);
/// `<CommandReply Status="SUCCESS" Message="..." />` (attribute text escaped).
std::string CommandReplyXml(const IgtlCommandReply& reply);
/// "SUCCESS" or "FAIL".
const char* CommandStatusName(const IgtlCommandReply& reply);

}  // namespace rp

#define RP_REGISTER_IGTL_COMMAND(name, handler) \
  static const bool rpIgtlCommandRegistered_##name = ::rp::RegisterIgtlCommand(#name, handler)
