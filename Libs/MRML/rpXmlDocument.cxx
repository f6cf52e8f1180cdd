#include "rpXmlDocument.h"

#include <fstream>
#include <sstream>

#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkNew.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLDataParser.h>

namespace rp {
namespace {

// vtkErrorMacro hands the message to an ErrorEvent observer instead of printing it.
void KeepMessage(vtkObject*, unsigned long, void* clientData, void* callData) {
  auto* messages = static_cast<std::string*>(clientData);
  if (messages->empty() && callData) *messages = static_cast<const char*>(callData);
}

// "Error parsing XML in stream at line 3, column 5, byte index 40: mismatched tag" (VTK's text,
// after the "ERROR: In <file>, line <n>" prefix of vtkErrorMacro) → "line 3, column 5: mismatched tag".
// Plain string search, not <regex> (GCC 12 warns inside <regex> under -fsanitize=address).
std::string ShortExpatMessage(const std::string& vtkMessage) {
  const std::size_t at = vtkMessage.find("at line ");
  const std::size_t column = vtkMessage.find(", column ", at);
  const std::size_t colon = vtkMessage.find(':', column);
  if (at != std::string::npos && column != std::string::npos && colon != std::string::npos) {
    const std::string line = vtkMessage.substr(at + 8, column - at - 8);
    const std::size_t columnEnd = vtkMessage.find_first_not_of("0123456789", column + 9);
    const std::string columnText = vtkMessage.substr(column + 9, columnEnd - column - 9);
    std::string reason = vtkMessage.substr(colon + 1);
    reason.erase(0, reason.find_first_not_of(' '));
    reason = reason.substr(0, reason.find('\n'));
    return "malformed XML at line " + line + ", column " + columnText + ": " + reason;
  }
  std::string text = vtkMessage;
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  return text.empty() ? "malformed XML" : text;
}

}  // namespace

vtkSmartPointer<vtkXMLDataElement> ParseXml(const std::string& text, const std::string& source, std::string& error) {
  if (text.find_first_not_of(" \t\r\n") == std::string::npos) {
    error = source + ": empty document (no XML element)";
    return nullptr;
  }
  vtkNew<vtkXMLDataParser> parser;
  std::string message;
  vtkNew<vtkCallbackCommand> observer;
  observer->SetCallback(KeepMessage);
  observer->SetClientData(&message);
  parser->AddObserver(vtkCommand::ErrorEvent, observer);
  parser->AddObserver(vtkCommand::WarningEvent, observer);
  std::istringstream stream(text);
  parser->SetStream(&stream);
  const int ok = parser->Parse();
  vtkXMLDataElement* root = parser->GetRootElement();
  if (!ok || !root) {
    error = source + ": " + ShortExpatMessage(message);
    return nullptr;
  }
  return root;  // the parser's reference goes with it; ours keeps the element alive
}

vtkSmartPointer<vtkXMLDataElement> ReadXmlFile(const std::string& path, std::string& error, std::size_t maxBytes) {
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    error = path + ": cannot open";
    return nullptr;
  }
  file.seekg(0, std::ios::end);
  const std::streamoff size = file.tellg();
  if (size < 0) {
    error = path + ": cannot read";
    return nullptr;
  }
  if (static_cast<std::size_t>(size) > maxBytes) {
    error = path + ": " + std::to_string(size) + " bytes, more than the " + std::to_string(maxBytes) +
            " an XML document may have here";
    return nullptr;
  }
  file.seekg(0);
  std::string text(static_cast<std::size_t>(size), '\0');
  if (!file.read(text.data(), size)) {
    error = path + ": cannot read";
    return nullptr;
  }
  return ParseXml(text, path, error);
}

}  // namespace rp
