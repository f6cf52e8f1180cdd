#include "rpIgtlCommands.h"

#include <cstdio>
#include <sstream>

#include <vtkXMLDataElement.h>

#include "rpXmlDocument.h"

namespace rp {

namespace {

std::map<std::string, IgtlCommandHandler>& Registry() {
  static std::map<std::string, IgtlCommandHandler> registry;
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

// ---- the commands: one function and one registration each

IgtlCommandReply RequestChannelIds(const IgtlCommandRequest&, IgtlCommandTarget& target) {
  return {true, Join(target.ChannelIds())};
}
RP_REGISTER_IGTL_COMMAND(RequestChannelIds, RequestChannelIds);

IgtlCommandReply RequestDeviceIds(const IgtlCommandRequest&, IgtlCommandTarget& target) {
  return {true, Join(target.DeviceIds())};
}
RP_REGISTER_IGTL_COMMAND(RequestDeviceIds, RequestDeviceIds);

IgtlCommandReply StartRecording(const IgtlCommandRequest& request, IgtlCommandTarget& target) {
  const std::string file = request.Attribute("OutputFilename", "Recording.igs.mha");
  std::string error;
  if (!target.StartRecording(file, error)) return Fail(error);
  return {true, "Recording to " + file + " started."};
}
RP_REGISTER_IGTL_COMMAND(StartRecording, StartRecording);

IgtlCommandReply StopRecording(const IgtlCommandRequest&, IgtlCommandTarget& target) {
  std::string file, error;
  if (!target.StopRecording(file, error)) return Fail(error);
  return {true, file};  // PLUS answers with the file written
}
RP_REGISTER_IGTL_COMMAND(StopRecording, StopRecording);

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
RP_REGISTER_IGTL_COMMAND(GetTransform, GetTransform);

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
RP_REGISTER_IGTL_COMMAND(UpdateTransform, UpdateTransform);

}  // namespace

std::string IgtlCommandRequest::Attribute(const std::string& key, const std::string& fallback) const {
  const auto it = this->Attributes.find(key);
  return it == this->Attributes.end() ? fallback : it->second;
}

bool RegisterIgtlCommand(const char* name, IgtlCommandHandler handler) {
  Registry()[name] = handler;
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

IgtlCommandReply RunIgtlCommand(const std::string& xml, IgtlCommandTarget& target) {
  IgtlCommandRequest request;
  std::string error;
  if (!ParseIgtlCommand(xml, request, error)) return Fail("bad command: " + error);
  const auto it = Registry().find(request.Name);
  if (it == Registry().end()) return Fail("unknown command " + request.Name + " (known: " + Join(IgtlCommandNames()) + ")");
  return it->second(request, target);
}

const char* CommandStatusName(const IgtlCommandReply& reply) { return reply.Success ? "SUCCESS" : "FAIL"; }

std::string CommandReplyXml(const IgtlCommandReply& reply) {
  return std::string("<CommandReply Status=\"") + CommandStatusName(reply) + "\" Message=\"" + Escape(reply.Message) + "\" />";
}

}  // namespace rp
