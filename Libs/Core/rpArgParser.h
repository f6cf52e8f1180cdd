#pragma once
// Minimal, strict command-line parser shared by every `roboplan <subcommand>`.
// Options are declared first; parse() refuses unknown options, missing values and missing
// positionals with a message that names the problem. `--help` and `--json` are built in.
//
// Declarations may say what a value is (Integer(), Number(), Point(), OneOf(), Input()/Output()
// files, ranges, Required()): Parse() then checks it, and the same declarations are written out
// as a Slicer Execution Model XML descriptor (`--xml`) and a Boutiques descriptor
// (`--boutiques`), so neither can drift from the options the command accepts.
#include <array>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace rp {

/// What a value is. Parse() refuses a value that is not one; the descriptors carry it.
enum class ArgType {
  Text,       // anything
  Integer,    // one integer
  Number,     // one finite number
  Point,      // x,y,z in RAS mm
  Integers,   // comma-separated integers
  Numbers,    // comma-separated numbers
  Choice,     // one of the words of the value name ("rigid|similarity")
  File,       // a path (see FileKind)
  Directory,  // a folder
};
/// What a file holds (the parameter tag Slicer gives it).
enum class FileKind { Any, Image, LabelMap, Transform, Model, Points };
/// Whether the command reads or writes a file or folder.
enum class Channel { None, Input, Output };

class ArgParser {
 public:
  /// One declared argument: what --help, Parse() and the descriptors are made from.
  struct Spec {
    std::string Name, ValueName, HelpText;
    std::optional<std::string> Default;
    bool IsFlag = false, IsPositional = false, Required = false, Variadic = false, Repeatable = false;
    ArgType Type = ArgType::Text;
    std::vector<std::string> Choices;
    std::optional<double> Minimum, Maximum;  // bounds of Integer/Number (and each element of a list)
    bool MinimumExclusive = false, MaximumExclusive = false;
    FileKind Kind = FileKind::Any;
    Channel IO = Channel::None;
    std::vector<std::string> Extensions;  // with the dot: ".nrrd"
  };
  /// What the user asked for instead of running the command.
  enum class Request { None, Help, SlicerXML, Boutiques };

  ArgParser(std::string command, std::string summary);

  /// An option taking a value: `--name value` or `--name=value` (also `--na_me`: Slicer's
  /// longflags allow no '-'). Repeatable options keep all.
  ArgParser& Option(const std::string& name, const std::string& valueName, const std::string& help,
                    std::optional<std::string> defaultValue = std::nullopt);
  /// A flag: `--name`.
  ArgParser& Flag(const std::string& name, const std::string& help);
  /// A positional argument. Optional ones must come last; `variadic` takes the rest.
  ArgParser& Positional(const std::string& name, const std::string& help, bool required = true,
                        bool variadic = false);

  // What the argument declared last is (checked by Parse(), written into the descriptors).
  ArgParser& Integer();
  ArgParser& Number();
  ArgParser& Point();
  ArgParser& Integers();
  ArgParser& Numbers();
  /// One of the '|'-separated words of the value name.
  ArgParser& OneOf();
  ArgParser& AtLeast(double minimum);
  ArgParser& GreaterThan(double minimum);
  ArgParser& AtMost(double maximum);
  ArgParser& LessThan(double maximum);
  ArgParser& Input(FileKind kind, std::vector<std::string> extensions = {});
  ArgParser& Output(FileKind kind, std::vector<std::string> extensions = {});
  ArgParser& InputFolder();
  ArgParser& OutputFolder();
  /// An option that must be given (positionals are required unless declared otherwise).
  ArgParser& Required();
  /// An option that may be given several times (GetAll()).
  ArgParser& Repeatable();

  /// Returns false on error (Error() says why) or when --help, --xml or --boutiques was asked
  /// (HelpRequested(): print Usage() and exit 0).
  bool Parse(const std::vector<std::string>& args);
  /// Parse() for a `roboplan <command>`: nothing when the command should run; else its exit
  /// code after printing — 0 with Usage() on `out` (--help, --xml, --boutiques), 2 with
  /// "roboplan <command>: <error>" and the usage on `err`.
  std::optional<int> ParseCommand(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

  bool HelpRequested() const { return this->Asked != Request::None; }
  Request Requested() const { return this->Asked; }
  const std::string& Error() const { return this->ErrorText; }
  /// The help text, or the descriptor asked for with --xml / --boutiques.
  std::string Usage() const;
  std::string HelpText() const;

  bool Has(const std::string& name) const;  // option given, flag set, or positional present
  std::string Get(const std::string& name) const;  // value or default ("" when absent)
  std::vector<std::string> GetAll(const std::string& name) const;
  double GetDouble(const std::string& name) const;  // throws std::invalid_argument naming option
  long GetInt(const std::string& name) const;
  /// "x,y,z" → 3 doubles; throws std::invalid_argument naming the option.
  std::vector<double> GetDoubles(const std::string& name, size_t expectedCount = 0) const;
  /// Every value of a (repeatable) Point() option as x, y, z; throws std::invalid_argument
  /// naming the option for a value that is not one.
  std::vector<std::array<double, 3>> GetPoints(const std::string& name) const;
  bool Json() const { return this->Has("json"); }

  const std::string& CommandName() const { return this->Command; }
  const std::string& Summary() const { return this->SummaryText; }
  /// The declared arguments, built-ins (--json) first.
  const std::vector<Spec>& Specs() const { return this->Declared; }

 private:
  const Spec* Find(const std::string& name) const;
  Spec& Last();
  /// Empty when `value` fits the declaration, else the reason.
  std::string Check(const Spec& spec, const std::string& value) const;

  std::string Command, SummaryText, ErrorText;
  std::vector<Spec> Declared;
  std::map<std::string, std::vector<std::string>> Values;
  Request Asked = Request::None;
};

}  // namespace rp
