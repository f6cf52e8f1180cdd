#include "rpCLIDescriptors.h"

#include <algorithm>
#include <cctype>
#include <sstream>

#include <nlohmann/json.hpp>

#include "rpArgParser.h"

#ifndef ROBOPLAN_VERSION
#define ROBOPLAN_VERSION "0"
#endif

namespace rp {
namespace {

using Spec = ArgParser::Spec;

bool Described(const Spec& s) { return s.Name != "json"; }

// Slicer's names and longflags: letters, digits and '_' only.
std::string Identifier(const std::string& name) {
  std::string id = name;
  for (char& c : id)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return id;
}

std::string Label(const std::string& name) {
  std::string label = name;
  std::replace(label.begin(), label.end(), '-', ' ');
  if (!label.empty()) label[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(label[0])));
  return label;
}

std::string Escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string Join(const std::vector<std::string>& items, const std::string& separator) {
  std::string out;
  for (size_t i = 0; i < items.size(); ++i) out += (i ? separator : "") + items[i];
  return out;
}

std::string Bounds(const Spec& s) {
  std::string text;
  if (s.Minimum) text += std::string(s.MinimumExclusive ? "> " : ">= ") + nlohmann::json(*s.Minimum).dump();
  if (s.Maximum)
    text += std::string(text.empty() ? "" : ", ") + (s.MaximumExclusive ? "< " : "<= ") + nlohmann::json(*s.Maximum).dump();
  return text;
}

// A parameter's description: its help, and what the tag cannot say (exclusive bounds, units).
std::string Description(const Spec& s) {
  std::string text = s.HelpText;
  if (const std::string bounds = Bounds(s); !bounds.empty()) text += " (" + bounds + ")";
  if (s.Repeatable) text += " (repeatable)";
  if (s.Required && !s.IsPositional) text += " (required)";
  return text;
}

// The Slicer parameter tag and its attributes for one declaration.
std::string SlicerTag(const Spec& s, std::string& attributes) {
  const std::string extensions =
      s.Extensions.empty() ? "" : " fileExtensions=\"" + Escape(Join(s.Extensions, ",")) + "\"";
  const std::string multiple = s.Repeatable || s.Variadic ? " multiple=\"true\"" : "";
  attributes.clear();
  if (s.IsFlag) return "boolean";
  switch (s.Type) {
    case ArgType::Integer: attributes = multiple; return "integer";
    case ArgType::Number: attributes = multiple; return "double";
    case ArgType::Point: attributes = multiple + " coordinateSystem=\"ras\""; return "point";
    case ArgType::Integers: return "integer-vector";
    case ArgType::Numbers: return "double-vector";
    case ArgType::Choice: return "string-enumeration";
    case ArgType::Directory: attributes = multiple; return "directory";
    case ArgType::File:
      switch (s.Kind) {
        case FileKind::Image: attributes = " type=\"scalar\"" + multiple + extensions; return "image";
        case FileKind::LabelMap: attributes = " type=\"label\"" + multiple + extensions; return "image";
        case FileKind::Transform: attributes = " type=\"linear\"" + multiple + extensions; return "transform";
        case FileKind::Model: attributes = " type=\"model\"" + multiple + extensions; return "geometry";
        case FileKind::Points:
        case FileKind::Any: attributes = multiple + extensions; return "file";
      }
      break;
    case ArgType::Text: attributes = multiple; return "string";
  }
  return "string";
}

bool IsFileLike(const Spec& s) { return s.IsPositional || s.Type == ArgType::File || s.Type == ArgType::Directory; }

void WriteSlicerParameter(std::ostringstream& out, const Spec& s, int& index) {
  std::string attributes;
  const std::string tag = SlicerTag(s, attributes);
  out << "    <" << tag << attributes << ">\n"
      << "      <name>" << Identifier(s.Name) << "</name>\n";
  if (s.IsPositional)
    out << "      <index>" << index++ << "</index>\n";
  else
    out << "      <longflag>" << Identifier(s.Name) << "</longflag>\n";
  out << "      <description>" << Escape(Description(s)) << "</description>\n"
      << "      <label>" << Escape(Label(s.Name)) << "</label>\n";
  if (s.IsFlag)
    out << "      <default>false</default>\n";
  else if (s.Default)
    out << "      <default>" << Escape(*s.Default) << "</default>\n";
  if (s.IO != Channel::None) out << "      <channel>" << (s.IO == Channel::Output ? "output" : "input") << "</channel>\n";
  if ((s.Type == ArgType::Integer || s.Type == ArgType::Number) && (s.Minimum || s.Maximum)) {
    // Slicer's constraints are inclusive: an exclusive integer bound moves by one.
    out << "      <constraints>\n";
    if (s.Minimum)
      out << "        <minimum>" << *s.Minimum + (s.MinimumExclusive && s.Type == ArgType::Integer ? 1 : 0)
          << "</minimum>\n";
    if (s.Maximum)
      out << "        <maximum>" << *s.Maximum - (s.MaximumExclusive && s.Type == ArgType::Integer ? 1 : 0)
          << "</maximum>\n";
    out << "        <step>" << (s.Type == ArgType::Integer ? "1" : "0.01") << "</step>\n"
        << "      </constraints>\n";
  }
  for (const auto& choice : s.Choices) out << "      <element>" << Escape(choice) << "</element>\n";
  out << "    </" << tag << ">\n";
}

}  // namespace

std::string SlicerExecutionModelXML(const ArgParser& parser) {
  std::ostringstream out;
  out << "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<executable>\n"
      << "  <category>RoboPlan</category>\n"
      << "  <title>RoboPlan " << Escape(parser.CommandName()) << "</title>\n"
      << "  <description>" << Escape(parser.Summary()) << "</description>\n"
      << "  <version>" << ROBOPLAN_VERSION << "</version>\n"
      << "  <documentation-url></documentation-url>\n"
      << "  <license></license>\n"
      << "  <contributor>RoboPlan</contributor>\n";
  int index = 0;
  // Inputs and outputs first (positionals, files, folders), then the parameters.
  for (bool io : {true, false}) {
    std::vector<const Spec*> group;
    for (const auto& s : parser.Specs())
      if (Described(s) && IsFileLike(s) == io) group.push_back(&s);
    if (group.empty()) continue;
    out << "  <parameters>\n"
        << "    <label>" << (io ? "Inputs and outputs" : "Parameters") << "</label>\n"
        << "    <description>" << (io ? "Files and folders read and written" : "How the command works")
        << "</description>\n";
    // Slicer numbers the positionals in declaration order.
    for (const Spec* s : group) WriteSlicerParameter(out, *s, index);
    out << "  </parameters>\n";
  }
  out << "</executable>\n";
  return out.str();
}

std::string BoutiquesDescriptor(const ArgParser& parser) {
  using json = nlohmann::json;
  json inputs = json::array(), outputs = json::array();
  std::string commandLine = "roboplan " + parser.CommandName();
  for (const auto& s : parser.Specs()) {
    if (!Described(s)) continue;
    std::string key = Identifier(s.Name);
    std::transform(key.begin(), key.end(), key.begin(), [](unsigned char c) { return std::toupper(c); });
    key = "[" + key + "]";
    commandLine += " " + key;
    json input = {{"id", Identifier(s.Name)}, {"name", Label(s.Name)}, {"description", Description(s)},
                  {"value-key", key}, {"optional", !s.Required}};
    if (!s.IsPositional) input["command-line-flag"] = "--" + s.Name;
    if (s.IsFlag) {
      input["type"] = "Flag";
    } else if (s.Type == ArgType::Integer || s.Type == ArgType::Number) {
      input["type"] = "Number";
      input["integer"] = s.Type == ArgType::Integer;
      if (s.Minimum) {
        input["minimum"] = *s.Minimum;
        input["exclusive-minimum"] = s.MinimumExclusive;
      }
      if (s.Maximum) {
        input["maximum"] = *s.Maximum;
        input["exclusive-maximum"] = s.MaximumExclusive;
      }
    } else if (s.Type == ArgType::File && s.IO == Channel::Input) {
      input["type"] = "File";
    } else if (s.Type == ArgType::Directory && s.IO == Channel::Input) {
      input["type"] = "File";  // Boutiques has no folder type: a folder is a File
    } else {
      input["type"] = "String";  // text, points, lists, choices, and the paths of outputs
    }
    if (!s.Choices.empty()) input["value-choices"] = s.Choices;
    if (s.Default && !s.IsFlag) {
      if (s.Type == ArgType::Integer)
        input["default-value"] = std::stol(*s.Default);
      else if (s.Type == ArgType::Number)
        input["default-value"] = std::stod(*s.Default);
      else
        input["default-value"] = *s.Default;
    }
    if (s.Repeatable || s.Variadic) {
      input["list"] = true;
      // `--seed a --seed b`: the separator repeats the flag (positionals: a space).
      input["list-separator"] = s.IsPositional ? " " : " --" + s.Name + " ";
      if (input.contains("default-value")) input["default-value"] = json::array({input["default-value"]});
    }
    inputs.push_back(input);
    if (s.IO == Channel::Output) {
      outputs.push_back({{"id", Identifier(s.Name) + "_output"},
                         {"name", Label(s.Name)},
                         {"description", s.HelpText},
                         {"path-template", key},
                         {"optional", !s.Required}});
    }
  }
  json doc = {{"name", "roboplan " + parser.CommandName()},
              {"tool-version", ROBOPLAN_VERSION},
              {"schema-version", "0.5"},
              {"description", parser.Summary()},
              {"author", "RoboPlan"},
              {"command-line", commandLine},
              {"inputs", inputs},
              {"error-codes", json::array({{{"code", 1}, {"description", "the work failed (the message names why)"}},
                                           {{"code", 2}, {"description", "bad arguments"}}})},
              {"tags", {{"domain", json::array({"medical imaging", "surgical planning"})}}}};
  if (!outputs.empty()) doc["output-files"] = outputs;
  return doc.dump(2) + "\n";
}

}  // namespace rp
