#pragma once
// Runs the main job's stages in order with progress on the terminal, times each one, records
// it in the report, and stops at the first failure (everything done so far stays on disk).
#include <functional>
#include <string>

#include "rpReport.h"

namespace rp {

class StageRunner {
 public:
  StageRunner(Report& report, int stageCount, bool quiet);

  /// Runs `work` unless an earlier stage failed. A stage fails by throwing (std::exception:
  /// its what() is the message shown and recorded). Returns true when the stage succeeded.
  bool Run(const std::string& name, const std::function<void()>& work);
  bool Failed() const { return this->HasFailed; }
  const std::string& FailureMessage() const { return this->Failure; }
  /// Progress line inside the current stage.
  void Progress(double fraction, const std::string& message);

 private:
  Report& Target;
  int StageCount, StageIndex = 0;
  bool Quiet, HasFailed = false;
  std::string Current, Failure, LastMessage;
  int LastPercent = -1;
};

}  // namespace rp
