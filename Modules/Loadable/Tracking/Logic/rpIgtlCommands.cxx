#include "rpIgtlCommands.h"

#include <cstdio>
#include <sstream>

#include <vtkXMLDataElement.h>

#include "rpXmlDocument.h"

namespace rp {

namespace {

struct RegisteredCommand {
  IgtlCommandAccess Access;
  IgtlCommandHandler Handler;
};
std::map<std::string, RegisteredCommand> BuiltInCommands();
std::map<std::string, RegisteredCommand>& Registry() {
  static std::map<std::string, RegisteredCommand> registry = BuiltInCommands();
  return registry;
}

std::string Join(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : ",") + s;
  return out;
}

std::string Escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '"': out += "&quot;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      default: out += c;
    }
  }
  return out;
}

IgtlCommandReply Fail(const std::string& message) { return {false, message}; }

// ---- the commands: one function each, and one line in BuiltInCommands

IgtlCommandReply RequestChannelIds(const IgtlCommandRequest&, IgtlCommandTarget& target) {
  return {true, Join(target.ChannelIds())};
}

IgtlCommandReply RequestDeviceIds(const IgtlCommandRequest&, IgtlCommandTarget& target) {
  return {true, Join(target.DeviceIds())};
}

IgtlCommandReply StartRecording(const IgtlCommandRequest& request, IgtlCommandTarget& target) {
  std::string message;
  const bool started = target.StartRecording(request.Attribute("OutputFilename", "Recording.igs.mha"), message);
  return {started, message};
}

IgtlCommandReply StopRecording(const IgtlCommandRequest&, IgtlCommandTarget& target) {
  std::string message;
  const bool stopped = target.StopRecording(message);  // PLUS answers with the frames and the file written
  return {stopped, message};
}

IgtlCommandReply GetTransform(const IgtlCommandRequest& request, IgtlCommandTarget& target) {
  const std::string name = request.Attribute("TransformName");
  if (name.empty()) return Fail("GetTransform needs TransformName");
  double m[16];
  ToolState state = ToolState::Missing;
  std::string error;
  if (!target.GetTransform(name, m, state, error)) return Fail(error);
  std::ostringstream text;
  text.precision(10);
  for (int i = 0; i < 16; ++i) text << (i ? " " : "") << m[i];
  return {true, text.str()};
}

IgtlCommandReply UpdateTransform(const IgtlCommandRequest& request, IgtlCommandTarget& target) {
  const std::string name = request.Attribute("TransformName");
  std::istringstream in(request.Attribute("TransformValue"));
  double m[16];
  int n = 0;
  while (n < 16 && in >> m[n]) ++n;
  if (name.empty() || n != 16) return Fail("UpdateTransform needs TransformName and TransformValue (16 numbers, row-major)");
  std::string error;
  if (!target.UpdateTransform(name, m, error)) return Fail(error);
  return {true, "Transform " + name + " updated."};
}

// Every command the server answers, listed in one place, and whether it only reads or changes
// state / writes files.
std::map<std::string, RegisteredCommand> BuiltInCommands() {
  using Access = IgtlCommandAccess;
  return {{"RequestChannelIds", {Access::ReadOnly, RequestChannelIds}},
          {"RequestDeviceIds", {Access::ReadOnly, RequestDeviceIds}},
          {"StartRecording", {Access::ChangesState, StartRecording}},
          {"StopRecording", {Access::ChangesState, StopRecording}},
          {"GetTransform", {Access::ReadOnly, GetTransform}},
          {"UpdateTransform", {Access::ChangesState, UpdateTransform}}};
}

}  // namespace

std::string IgtlCommandRequest::Attribute(const std::string& key, const std::string& fallback) const {
  const auto it = this->Attributes.find(key);
  return it == this->Attributes.end() ? fallback : it->second;
}

bool RegisterIgtlCommand(const char* name, IgtlCommandAccess access, IgtlCommandHandler handler) {
  Registry()[name] = {access, handler};
  return true;
}

bool IgtlCommandAccessOf(const std::string& name, IgtlCommandAccess& access) {
  const auto it = Registry().find(name);
  if (it == Registry().end()) return false;
  access = it->second.Access;
  return true;
}

std::vector<std::string> IgtlCommandNames() {
  std::vector<std::string> names;
  for (const auto& entry : Registry()) names.push_back(entry.first);
  return names;
}

bool ParseIgtlCommand(const std::string& xml, IgtlCommandRequest& request, std::string& error) {
  vtkSmartPointer<vtkXMLDataElement> root = ParseXml(xml, "command", error);
  if (!root) return false;
  if (!root->GetName() || std::string(root->GetName()) != "Command" || !root->GetAttribute("Name")) {
    error = "expected <Command Name=\"...\" .../>";
    return false;
  }
  request.Name = root->GetAttribute("Name");
  request.Attributes.clear();
  for (int i = 0; i < root->GetNumberOfAttributes(); ++i)
    request.Attributes[root->GetAttributeName(i)] = root->GetAttributeValue(i) ? root->GetAttributeValue(i) : "";
  return true;
}

IgtlCommandReply RunIgtlCommand(const std::string& xml, IgtlCommandTarget& target, const IgtlCommandCaller& caller,
                                IgtlCommandRequest* parsed) {
  IgtlCommandRequest local;
  IgtlCommandRequest& request = parsed ? *parsed : local;
  request = {};
  std::string error;
  if (!ParseIgtlCommand(xml, request, error)) return Fail("bad command: " + error);
  const auto it = Registry().find(request.Name);
  if (it == Registry().end()) return Fail("unknown command " + request.Name + " (known: " + Join(IgtlCommandNames()) + ")");
  if (it->second.Access == IgtlCommandAccess::ChangesState && !caller.MayChangeState)
    return Fail(request.Name + " refused: client " + caller.Address +
                " may not change state or write files (commands that do are taken from " + caller.AllowedClients +
                " only: the server's --command-clients); the stream and read-only commands are open to it");
  return it->second.Handler(request, target);
}

std::string CommandLogLine(const IgtlCommandCaller& caller, const IgtlCommandRequest& request, const IgtlCommandReply& reply) {
  // A client chooses these bytes: no control character reaches the log, no value floods it.
  const auto printable = [](const std::string& text, size_t limit) {
    std::string out;
    for (unsigned char c : text.substr(0, limit)) {
      if (c >= 0x20 && c != 0x7F) {
        out += static_cast<char>(c);
      } else {
        char hex[8];
        std::snprintf(hex, sizeof hex, "\\x%02X", c);
        out += hex;
      }
    }
    return text.size() > limit ? out + "..." : out;
  };
  std::string line = "command from " + caller.Address + ": " + (request.Name.empty() ? "(unparsed)" : printable(request.Name, 64));
  for (const auto& [key, value] : request.Attributes)
    if (key != "Name") line += " " + printable(key, 64) + "=\"" + printable(value, 160) + "\"";
  return line + " -> " + CommandStatusName(reply) + ": " + printable(reply.Message, 400);
}

const char* CommandStatusName(const IgtlCommandReply& reply) { return reply.Success ? "SUCCESS" : "FAIL"; }

std::string CommandReplyXml(const IgtlCommandReply& reply) {
  return std::string("<CommandReply Status=\"") + CommandStatusName(reply) + "\" Message=\"" + Escape(reply.Message) + "\" />";
}

}  // namespace rp
