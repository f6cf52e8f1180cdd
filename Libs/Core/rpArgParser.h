#pragma once
// Minimal, strict command-line parser shared by every `roboplan <subcommand>`.
// Options are declared first; parse() refuses unknown options, missing values and missing
// positionals with a message that names the problem. `--help` and `--json` are built in.
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace rp {

class ArgParser {
 public:
  ArgParser(std::string command, std::string summary);

  /// An option taking a value: `--name value` or `--name=value`. Repeatable options keep all.
  ArgParser& Option(const std::string& name, const std::string& valueName, const std::string& help,
                    std::optional<std::string> defaultValue = std::nullopt);
  /// A flag: `--name`.
  ArgParser& Flag(const std::string& name, const std::string& help);
  /// A positional argument. Optional ones must come last; `variadic` takes the rest.
  ArgParser& Positional(const std::string& name, const std::string& help, bool required = true,
                        bool variadic = false);

  /// Returns false on error (Error() says why) or when --help was asked (HelpRequested()).
  bool Parse(const std::vector<std::string>& args);

  bool HelpRequested() const { return this->Help; }
  const std::string& Error() const { return this->ErrorText; }
  std::string Usage() const;

  bool Has(const std::string& name) const;  // option given, flag set, or positional present
  std::string Get(const std::string& name) const;  // value or default ("" when absent)
  std::vector<std::string> GetAll(const std::string& name) const;
  double GetDouble(const std::string& name) const;  // throws std::invalid_argument naming option
  long GetInt(const std::string& name) const;
  /// "x,y,z" → 3 doubles; throws std::invalid_argument naming the option.
  std::vector<double> GetDoubles(const std::string& name, size_t expectedCount = 0) const;
  bool Json() const { return this->Has("json"); }

 private:
  struct Spec {
    std::string Name, ValueName, HelpText;
    std::optional<std::string> Default;
    bool IsFlag = false, IsPositional = false, Required = false, Variadic = false;
  };
  const Spec* Find(const std::string& name) const;

  std::string Command, Summary, ErrorText;
  std::vector<Spec> Specs;
  std::map<std::string, std::vector<std::string>> Values;
  bool Help = false;
};

}  // namespace rp
