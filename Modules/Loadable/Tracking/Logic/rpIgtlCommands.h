#pragma once
// PlusServer's remote commands, as Slicer's OpenIGTLinkRemote sends them: a `COMMAND` message
// (OpenIGTLink v3) or the older `STRING` named `CMD_<uid>`, both holding PLUS's command XML
// `<Command Name="StartRecording" OutputFilename="x.igs.mha" />`. The server answers a COMMAND
// with `RTS_COMMAND` (same id, `Status`/`Message` metadata) and a CMD_ string with the STRING
// `ACK_<uid>` holding `<CommandReply Status="SUCCESS|FAIL" Message="..." />`.
//
// A command is one function and one line in the list of commands (BuiltInCommands in
// rpIgtlCommands.cxx) that says whether it only reads or changes state / writes files; it acts
// on the server only through IgtlCommandTarget. A command that changes state runs only for a caller the server allows
// (its --command-clients); any other caller gets a FAIL reply naming why. Commands are rare
// control messages: parsing them allocates (the pose stream does not).
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

/// What a command may do. A new command that changes what clients see, or writes a file, is
/// ChangesState: only allowed clients may run it.
enum class IgtlCommandAccess { ReadOnly, ChangesState };

/// Who sent a command: the server fills it per connection.
struct IgtlCommandCaller {
  std::string Address;          // "127.0.0.2:40312"
  bool MayChangeState = false;  // in the server's allow-list
  std::string AllowedClients;   // the allow-list, for the refusal ("127.0.0.0/8")
};

/// What commands act on (the OpenIGTLink server implements it).
class IgtlCommandTarget {
 public:
  virtual ~IgtlCommandTarget() = default;
  virtual std::vector<std::string> ChannelIds() const = 0;
  virtual std::vector<std::string> DeviceIds() const = 0;
  /// `requested`: the client's OutputFilename. `message`: the reply (the file recorded to) or why not.
  virtual bool StartRecording(const std::string& requested, std::string& message) = 0;
  /// Ends the recording. `message`: the reply (frames and the file written) or why it failed.
  virtual bool StopRecording(std::string& message) = 0;
  /// A transform by PLUS name ("StylusTipToReference"): row-major 4x4 and its status.
  virtual bool GetTransform(const std::string& name, double m[16], ToolState& state, std::string& error) = 0;
  virtual bool UpdateTransform(const std::string& name, const double m[16], std::string& error) = 0;
};

using IgtlCommandHandler = IgtlCommandReply (*)(const IgtlCommandRequest& request, IgtlCommandTarget& target);

/// A command beside the built-in ones (BuiltInCommands), by a host at start-up.
bool RegisterIgtlCommand(const char* name, IgtlCommandAccess access, IgtlCommandHandler handler);
/// The registered command names, sorted.
std::vector<std::string> IgtlCommandNames();
/// The access a registered command declared (false when `name` is not registered).
bool IgtlCommandAccessOf(const std::string& name, IgtlCommandAccess& access);

/// Parses PLUS's command XML; false with a message for anything else.
bool ParseIgtlCommand(const std::string& xml, IgtlCommandRequest& request, std::string& error);
/// Parses, checks that `caller` may run it, and runs; an unknown command, bad XML or a caller not
/// allowed is a FAIL reply naming it. `request` (optional) receives what was parsed, for the log.
IgtlCommandReply RunIgtlCommand(const std::string& xml, IgtlCommandTarget& target, const IgtlCommandCaller& caller,
                                IgtlCommandRequest* request = nullptr);
/// The session log's line for a command: "command from <address>: <Name> <attributes> -> SUCCESS|FAIL: <message>"
/// (control characters escaped, long values cut).
std::string CommandLogLine(const IgtlCommandCaller& caller, const IgtlCommandRequest& request, const IgtlCommandReply& reply);
/// `<CommandReply Status="SUCCESS" Message="..." />` (attribute text escaped).
std::string CommandReplyXml(const IgtlCommandReply& reply);
/// "SUCCESS" or "FAIL".
const char* CommandStatusName(const IgtlCommandReply& reply);

}  // namespace rp

