#include "rpArgParser.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

#include "rpCLIDescriptors.h"

namespace rp {
namespace {

std::vector<std::string> Split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, separator)) parts.push_back(part);
  if (!text.empty() && text.back() == separator) parts.emplace_back();
  return parts;
}

bool ParseNumber(const std::string& text, double& value) {
  char* end = nullptr;
  errno = 0;
  value = std::strtod(text.c_str(), &end);
  return !text.empty() && *end == '\0' && errno != ERANGE && std::isfinite(value);
}

bool ParseInteger(const std::string& text, double& value) {
  char* end = nullptr;
  errno = 0;
  const long n = std::strtol(text.c_str(), &end, 10);
  value = static_cast<double>(n);
  return !text.empty() && *end == '\0' && errno != ERANGE;
}

std::string NumberText(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", v);
  return buffer;
}

// "≥ 1 and ≤ 100000", "> 0 and ≤ 1", or "".
std::string RangeText(const ArgParser::Spec& s) {
  std::string text;
  if (s.Minimum) text = (s.MinimumExclusive ? "> " : ">= ") + NumberText(*s.Minimum);
  if (s.Maximum) text += (text.empty() ? "" : " and ") + std::string(s.MaximumExclusive ? "< " : "<= ") + NumberText(*s.Maximum);
  return text;
}

std::string TypeText(const ArgParser::Spec& s) {
  switch (s.Type) {
    case ArgType::Integer: return "an integer";
    case ArgType::Number: return "a number";
    case ArgType::Point: return "a point x,y,z";
    case ArgType::Integers: return "comma-separated integers";
    case ArgType::Numbers: return "comma-separated numbers";
    default: return "";
  }
}

}  // namespace

ArgParser::ArgParser(std::string command, std::string summary)
    : Command(std::move(command)), SummaryText(std::move(summary)) {
  this->Flag("json", "print machine-readable results (JSON) on standard output");
}

ArgParser& ArgParser::Option(const std::string& name, const std::string& valueName,
                             const std::string& help, std::optional<std::string> defaultValue) {
  Spec s;
  s.Name = name;
  s.ValueName = valueName;
  s.HelpText = help;
  s.Default = std::move(defaultValue);
  this->Declared.push_back(s);
  return *this;
}

ArgParser& ArgParser::Flag(const std::string& name, const std::string& help) {
  Spec s;
  s.Name = name;
  s.HelpText = help;
  s.IsFlag = true;
  this->Declared.push_back(s);
  return *this;
}

ArgParser& ArgParser::Positional(const std::string& name, const std::string& help, bool required,
                                 bool variadic) {
  Spec s;
  s.Name = name;
  s.HelpText = help;
  s.IsPositional = true;
  s.Required = required;
  s.Variadic = variadic;
  this->Declared.push_back(s);
  return *this;
}

ArgParser::Spec& ArgParser::Last() { return this->Declared.back(); }

ArgParser& ArgParser::Integer() {
  this->Last().Type = ArgType::Integer;
  return *this;
}
ArgParser& ArgParser::Number() {
  this->Last().Type = ArgType::Number;
  return *this;
}
ArgParser& ArgParser::Point() {
  this->Last().Type = ArgType::Point;
  return *this;
}
ArgParser& ArgParser::Integers() {
  this->Last().Type = ArgType::Integers;
  return *this;
}
ArgParser& ArgParser::Numbers() {
  this->Last().Type = ArgType::Numbers;
  return *this;
}
ArgParser& ArgParser::OneOf() {
  Spec& s = this->Last();
  s.Type = ArgType::Choice;
  s.Choices = Split(s.ValueName, '|');
  return *this;
}
ArgParser& ArgParser::AtLeast(double minimum) {
  this->Last().Minimum = minimum;
  this->Last().MinimumExclusive = false;
  return *this;
}
ArgParser& ArgParser::GreaterThan(double minimum) {
  this->Last().Minimum = minimum;
  this->Last().MinimumExclusive = true;
  return *this;
}
ArgParser& ArgParser::AtMost(double maximum) {
  this->Last().Maximum = maximum;
  this->Last().MaximumExclusive = false;
  return *this;
}
ArgParser& ArgParser::LessThan(double maximum) {
  this->Last().Maximum = maximum;
  this->Last().MaximumExclusive = true;
  return *this;
}
ArgParser& ArgParser::Input(FileKind kind, std::vector<std::string> extensions) {
  Spec& s = this->Last();
  s.Type = ArgType::File;
  s.Kind = kind;
  s.IO = Channel::Input;
  s.Extensions = std::move(extensions);
  return *this;
}
ArgParser& ArgParser::Output(FileKind kind, std::vector<std::string> extensions) {
  this->Input(kind, std::move(extensions));
  this->Last().IO = Channel::Output;
  return *this;
}
ArgParser& ArgParser::InputFolder() {
  this->Last().Type = ArgType::Directory;
  this->Last().IO = Channel::Input;
  return *this;
}
ArgParser& ArgParser::OutputFolder() {
  this->Last().Type = ArgType::Directory;
  this->Last().IO = Channel::Output;
  return *this;
}
ArgParser& ArgParser::Required() {
  this->Last().Required = true;
  return *this;
}
ArgParser& ArgParser::Repeatable() {
  this->Last().Repeatable = true;
  return *this;
}

const ArgParser::Spec* ArgParser::Find(const std::string& name) const {
  std::string dashed = name;  // Slicer passes `--fre_threshold` for `--fre-threshold`
  std::replace(dashed.begin(), dashed.end(), '_', '-');
  for (const auto& s : this->Declared) {
    if (!s.IsPositional && (s.Name == name || s.Name == dashed)) return &s;
  }
  return nullptr;
}

std::string ArgParser::Check(const Spec& spec, const std::string& value) const {
  const std::string what = spec.IsPositional ? "<" + spec.Name + ">" : "--" + spec.Name;
  auto inRange = [&](double v) -> std::string {
    const bool below = spec.Minimum && (spec.MinimumExclusive ? v <= *spec.Minimum : v < *spec.Minimum);
    const bool above = spec.Maximum && (spec.MaximumExclusive ? v >= *spec.Maximum : v > *spec.Maximum);
    if (below || above) return what + " must be " + RangeText(spec) + " (got " + NumberText(v) + ")";
    return {};
  };
  double v = 0;
  switch (spec.Type) {
    case ArgType::Integer:
      if (!ParseInteger(value, v)) return what + ": '" + value + "' is not an integer";
      return inRange(v);
    case ArgType::Number:
      if (!ParseNumber(value, v)) return what + ": '" + value + "' is not a number";
      return inRange(v);
    case ArgType::Point:
    case ArgType::Integers:
    case ArgType::Numbers: {
      const auto parts = Split(value, ',');
      if (parts.empty()) return what + " needs " + TypeText(spec);
      if (spec.Type == ArgType::Point && parts.size() != 3)
        return what + ": '" + value + "' is not a point x,y,z (three comma-separated numbers)";
      for (const auto& part : parts) {
        const bool ok = spec.Type == ArgType::Integers ? ParseInteger(part, v) : ParseNumber(part, v);
        if (!ok) return what + ": '" + value + "' is not " + TypeText(spec);
        if (auto error = inRange(v); !error.empty()) return error;
      }
      return {};
    }
    case ArgType::Choice:
      if (std::find(spec.Choices.begin(), spec.Choices.end(), value) == spec.Choices.end())
        return what + ": '" + value + "' is not one of " + spec.ValueName;
      return {};
    case ArgType::File:
    case ArgType::Directory:
      if (value.empty()) return what + " needs a path";
      return {};
    case ArgType::Text:
      return {};
  }
  return {};
}

std::optional<int> ArgParser::ParseCommand(const std::vector<std::string>& args, std::ostream& out,
                                           std::ostream& err) {
  if (this->Parse(args)) return std::nullopt;
  if (this->HelpRequested()) {
    out << this->Usage();
    return 0;
  }
  err << "roboplan " << this->Command << ": " << this->ErrorText << "\n\n" << this->Usage();
  return 2;
}

bool ArgParser::Parse(const std::vector<std::string>& args) {
  this->Values.clear();
  this->ErrorText.clear();
  this->Asked = Request::None;
  std::vector<std::string> positionals;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--help" || a == "-h") this->Asked = Request::Help;
    if (a == "--xml") this->Asked = Request::SlicerXML;
    if (a == "--boutiques") this->Asked = Request::Boutiques;
    if (this->Asked != Request::None) return false;
    if (a.size() > 2 && a.compare(0, 2, "--") == 0) {
      std::string name = a.substr(2), value;
      bool hasInlineValue = false;
      if (auto eq = name.find('='); eq != std::string::npos) {
        value = name.substr(eq + 1);
        name = name.substr(0, eq);
        hasInlineValue = true;
      }
      const Spec* spec = this->Find(name);
      if (!spec) {
        this->ErrorText = "unknown option '--" + name + "'";
        return false;
      }
      if (spec->IsFlag) {
        if (hasInlineValue) {
          this->ErrorText = "option '--" + name + "' takes no value";
          return false;
        }
        this->Values[spec->Name].push_back("1");
        continue;
      }
      if (!hasInlineValue) {
        if (i + 1 >= args.size()) {
          this->ErrorText = "option '--" + name + "' needs a value <" + spec->ValueName + ">";
          return false;
        }
        value = args[++i];
      }
      if (std::string error = this->Check(*spec, value); !error.empty()) {
        this->ErrorText = error;
        return false;
      }
      this->Values[spec->Name].push_back(value);
    } else {
      positionals.push_back(a);
    }
  }
  size_t next = 0;
  for (const auto& s : this->Declared) {
    if (!s.IsPositional) continue;
    if (next >= positionals.size()) {
      if (s.Required) {
        this->ErrorText = "missing argument <" + s.Name + ">";
        return false;
      }
      continue;
    }
    const size_t end = s.Variadic ? positionals.size() : next + 1;
    for (; next < end; ++next) {
      if (std::string error = this->Check(s, positionals[next]); !error.empty()) {
        this->ErrorText = error;
        return false;
      }
      this->Values[s.Name].push_back(positionals[next]);
    }
  }
  if (next < positionals.size()) {
    this->ErrorText = "unexpected argument '" + positionals[next] + "'";
    return false;
  }
  for (const auto& s : this->Declared) {
    if (!s.IsPositional && s.Required && !this->Values.count(s.Name)) {
      this->ErrorText = "--" + s.Name + " <" + s.ValueName + "> is required";
      return false;
    }
  }
  return true;
}

std::string ArgParser::Usage() const {
  switch (this->Asked) {
    case Request::SlicerXML: return SlicerExecutionModelXML(*this);
    case Request::Boutiques: return BoutiquesDescriptor(*this);
    default: return this->HelpText();
  }
}

std::string ArgParser::HelpText() const {
  std::ostringstream out;
  out << "usage: roboplan " << this->Command;
  for (const auto& s : this->Declared) {
    if (!s.IsPositional) continue;
    out << (s.Required ? " <" : " [") << s.Name << (s.Variadic ? "..." : "")
        << (s.Required ? ">" : "]");
  }
  for (const auto& s : this->Declared) {
    if (!s.IsPositional && s.Required) out << " --" << s.Name << " <" << s.ValueName << ">";
  }
  out << " [options]\n\n" << this->SummaryText << "\n";
  bool anyPositional = false;
  for (const auto& s : this->Declared) anyPositional |= s.IsPositional;
  if (anyPositional) {
    out << "\narguments:\n";
    for (const auto& s : this->Declared) {
      if (s.IsPositional) out << "  " << s.Name << "\n      " << s.HelpText << "\n";
    }
  }
  out << "\noptions:\n";
  for (const auto& s : this->Declared) {
    if (s.IsPositional) continue;
    out << "  --" << s.Name;
    if (!s.IsFlag) out << " <" << s.ValueName << ">";
    out << "\n      " << s.HelpText;
    std::vector<std::string> notes;
    if (s.Required) notes.push_back("required");
    if (s.Default) notes.push_back("default: " + *s.Default);
    if (const std::string range = RangeText(s); !range.empty()) notes.push_back(range);
    if (s.Repeatable) notes.push_back("repeatable");
    for (size_t i = 0; i < notes.size(); ++i) out << (i ? ", " : " (") << notes[i] << (i + 1 == notes.size() ? ")" : "");
    out << "\n";
  }
  out << "  --help\n      show this help\n"
         "  --xml, --boutiques\n      print this command's Slicer Execution Model XML or Boutiques JSON descriptor\n";
  return out.str();
}

bool ArgParser::Has(const std::string& name) const { return this->Values.count(name) > 0; }

std::string ArgParser::Get(const std::string& name) const {
  auto it = this->Values.find(name);
  if (it != this->Values.end() && !it->second.empty()) return it->second.back();
  for (const auto& s : this->Declared) {
    if (s.Name == name && s.Default) return *s.Default;
  }
  return {};
}

std::vector<std::string> ArgParser::GetAll(const std::string& name) const {
  auto it = this->Values.find(name);
  return it == this->Values.end() ? std::vector<std::string>{} : it->second;
}

double ArgParser::GetDouble(const std::string& name) const {
  const std::string v = this->Get(name);
  char* end = nullptr;
  errno = 0;
  const double d = std::strtod(v.c_str(), &end);
  if (v.empty() || *end != '\0' || errno == ERANGE) {
    throw std::invalid_argument("--" + name + ": '" + v + "' is not a number");
  }
  return d;
}

long ArgParser::GetInt(const std::string& name) const {
  const std::string v = this->Get(name);
  char* end = nullptr;
  errno = 0;
  const long n = std::strtol(v.c_str(), &end, 10);
  if (v.empty() || *end != '\0' || errno == ERANGE) {
    throw std::invalid_argument("--" + name + ": '" + v + "' is not an integer");
  }
  return n;
}

std::vector<double> ArgParser::GetDoubles(const std::string& name, size_t expectedCount) const {
  const std::string v = this->Get(name);
  std::vector<double> out;
  std::stringstream ss(v);
  std::string item;
  while (std::getline(ss, item, ',')) {
    char* end = nullptr;
    const double d = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0') {
      throw std::invalid_argument("--" + name + ": '" + v + "' is not a comma-separated list of numbers");
    }
    out.push_back(d);
  }
  if (expectedCount && out.size() != expectedCount) {
    throw std::invalid_argument("--" + name + ": expected " + std::to_string(expectedCount) +
                                " comma-separated numbers, got '" + v + "'");
  }
  return out;
}

std::vector<std::array<double, 3>> ArgParser::GetPoints(const std::string& name) const {
  std::vector<std::array<double, 3>> points;
  for (const std::string& value : this->GetAll(name)) {
    const auto parts = Split(value, ',');
    std::array<double, 3> p{};
    if (parts.size() != 3 || !ParseNumber(parts[0], p[0]) || !ParseNumber(parts[1], p[1]) ||
        !ParseNumber(parts[2], p[2]))
      throw std::invalid_argument("--" + name + " '" + value + "': expected x,y,z");
    points.push_back(p);
  }
  return points;
}

}  // namespace rp
