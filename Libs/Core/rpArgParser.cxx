#include "rpArgParser.h"

#include <cerrno>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace rp {

ArgParser::ArgParser(std::string command, std::string summary)
    : Command(std::move(command)), Summary(std::move(summary)) {
  this->Flag("json", "print machine-readable results (JSON) on standard output");
}

ArgParser& ArgParser::Option(const std::string& name, const std::string& valueName,
                             const std::string& help, std::optional<std::string> defaultValue) {
  Spec s;
  s.Name = name;
  s.ValueName = valueName;
  s.HelpText = help;
  s.Default = std::move(defaultValue);
  this->Specs.push_back(s);
  return *this;
}

ArgParser& ArgParser::Flag(const std::string& name, const std::string& help) {
  Spec s;
  s.Name = name;
  s.HelpText = help;
  s.IsFlag = true;
  this->Specs.push_back(s);
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
  this->Specs.push_back(s);
  return *this;
}

const ArgParser::Spec* ArgParser::Find(const std::string& name) const {
  for (const auto& s : this->Specs) {
    if (s.Name == name && !s.IsPositional) return &s;
  }
  return nullptr;
}

bool ArgParser::Parse(const std::vector<std::string>& args) {
  this->Values.clear();
  this->ErrorText.clear();
  std::vector<std::string> positionals;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--help" || a == "-h") {
      this->Help = true;
      return false;
    }
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
        this->Values[name].push_back("1");
        continue;
      }
      if (!hasInlineValue) {
        if (i + 1 >= args.size()) {
          this->ErrorText = "option '--" + name + "' needs a value <" + spec->ValueName + ">";
          return false;
        }
        value = args[++i];
      }
      this->Values[name].push_back(value);
    } else {
      positionals.push_back(a);
    }
  }
  size_t next = 0;
  for (const auto& s : this->Specs) {
    if (!s.IsPositional) continue;
    if (next >= positionals.size()) {
      if (s.Required) {
        this->ErrorText = "missing argument <" + s.Name + ">";
        return false;
      }
      continue;
    }
    if (s.Variadic) {
      while (next < positionals.size()) this->Values[s.Name].push_back(positionals[next++]);
    } else {
      this->Values[s.Name].push_back(positionals[next++]);
    }
  }
  if (next < positionals.size()) {
    this->ErrorText = "unexpected argument '" + positionals[next] + "'";
    return false;
  }
  return true;
}

std::string ArgParser::Usage() const {
  std::ostringstream out;
  out << "usage: roboplan " << this->Command;
  for (const auto& s : this->Specs) {
    if (!s.IsPositional) continue;
    out << (s.Required ? " <" : " [") << s.Name << (s.Variadic ? "..." : "")
        << (s.Required ? ">" : "]");
  }
  out << " [options]\n\n" << this->Summary << "\n";
  bool anyPositional = false;
  for (const auto& s : this->Specs) anyPositional |= s.IsPositional;
  if (anyPositional) {
    out << "\narguments:\n";
    for (const auto& s : this->Specs) {
      if (s.IsPositional) out << "  " << s.Name << "\n      " << s.HelpText << "\n";
    }
  }
  out << "\noptions:\n";
  for (const auto& s : this->Specs) {
    if (s.IsPositional) continue;
    out << "  --" << s.Name;
    if (!s.IsFlag) out << " <" << s.ValueName << ">";
    out << "\n      " << s.HelpText;
    if (s.Default) out << " (default: " << *s.Default << ")";
    out << "\n";
  }
  out << "  --help\n      show this help\n";
  return out.str();
}

bool ArgParser::Has(const std::string& name) const { return this->Values.count(name) > 0; }

std::string ArgParser::Get(const std::string& name) const {
  auto it = this->Values.find(name);
  if (it != this->Values.end() && !it->second.empty()) return it->second.back();
  for (const auto& s : this->Specs) {
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

}  // namespace rp
