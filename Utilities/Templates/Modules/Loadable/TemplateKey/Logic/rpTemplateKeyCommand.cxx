#include "rpTemplateKeyCommand.h"

#include <nlohmann/json.hpp>
#include <vtkNew.h>

#include "rpArgParser.h"
#include "vtkRPScene.h"
#include "vtkRPTemplateKeyLogic.h"

namespace rp {

int RunTemplateKeySummaryCommand(const std::vector<std::string>& arguments, std::ostream& out, std::ostream& err) {
  // 1. Parse the options (declared once: --help, --json, --xml and --boutiques come from them).
  ArgParser parser("templatekey-summary", "Load scene and data files and count the nodes of each class.");
  parser.Positional("files", "scene or data files, or DICOM folders", true, true);
  if (const auto exitCode = parser.ParseCommand(arguments, out, err)) return *exitCode;
  // 2. Run the module's logic.
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPTemplateKeyLogic> logic;
  logic->SetScene(scene);
  std::string error;
  if (!logic->LoadFiles(parser.GetAll("files"), error)) {
    err << "roboplan templatekey-summary: " << error << "\n";
    return 1;
  }
  const std::map<std::string, int> counts = logic->CountNodesByClass();
  // 3. Report.
  if (parser.Json()) {
    out << nlohmann::json{{"ok", true}, {"nodes", counts}}.dump(2) << "\n";
  } else {
    for (const auto& [nodeClass, count] : counts) out << count << " " << nodeClass << "\n";
  }
  return 0;
}

}  // namespace rp
