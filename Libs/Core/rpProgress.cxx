#include "rpProgress.h"

#include <algorithm>

namespace rp {

TerminalProgress::TerminalProgress(std::string stage, bool quiet, std::FILE* out)
    : Stage(std::move(stage)), Quiet(quiet), Out(out) {}

void TerminalProgress::Report(double fraction, const std::string& message) {
  if (this->Quiet) return;
  const int percent = static_cast<int>(std::clamp(fraction, 0.0, 1.0) * 100.0 + 0.5);
  if (percent == this->LastPercent && message == this->LastMessage) return;
  this->LastPercent = percent;
  this->LastMessage = message;
  std::fprintf(this->Out, "[%s] %3d%% %s\n", this->Stage.c_str(), percent, message.c_str());
  std::fflush(this->Out);
}

ProgressCallback TerminalProgress::Callback() {
  return [this](double f, const std::string& m) { this->Report(f, m); };
}

}  // namespace rp
