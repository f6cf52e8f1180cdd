#include "rpStageRunner.h"

#include <chrono>
#include <cstdio>
#include <exception>

namespace rp {

StageRunner::StageRunner(Report& report, int stageCount, bool quiet)
    : Target(report), StageCount(stageCount), Quiet(quiet) {}

bool StageRunner::Run(const std::string& name, const std::function<void()>& work) {
  ++this->StageIndex;
  if (this->HasFailed) return false;
  this->Current = name;
  this->LastPercent = -1;
  if (!this->Quiet) {
    std::fprintf(stderr, "[demo %d/%d] %s\n", this->StageIndex, this->StageCount, name.c_str());
    std::fflush(stderr);
  }
  const auto start = std::chrono::steady_clock::now();
  Report::StageRecord record;
  record.Name = name;
  try {
    work();
  } catch (const std::exception& e) {
    record.Ok = false;
    record.Message = e.what();
  }
  record.Seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  this->Target.AddStage(record);
  if (!record.Ok) {
    this->HasFailed = true;
    this->Failure = name + ": " + record.Message;
    std::fprintf(stderr, "[demo %d/%d] %s FAILED: %s\n", this->StageIndex, this->StageCount, name.c_str(),
                 record.Message.c_str());
  } else if (!this->Quiet) {
    std::fprintf(stderr, "[demo %d/%d] %s done in %.1f s\n", this->StageIndex, this->StageCount, name.c_str(),
                 record.Seconds);
  }
  std::fflush(stderr);
  return record.Ok;
}

void StageRunner::Progress(double fraction, const std::string& message) {
  if (this->Quiet) return;
  // One line per 10 % (or when the message changes) keeps the terminal readable.
  const int percent = static_cast<int>(fraction * 10 + 1e-9) * 10;
  if (percent == this->LastPercent && message == this->LastMessage) return;
  this->LastPercent = percent;
  this->LastMessage = message;
  std::fprintf(stderr, "    %3d%% %s\n", percent, message.c_str());
  std::fflush(stderr);
}

}  // namespace rp
