#include "rpProgress.h"

#include <algorithm>
#include <cstdio>

namespace rp {

TerminalProgress::TerminalProgress(std::string stage, bool quiet, std::ostream& out)
    : Stage(std::move(stage)), Quiet(quiet), Out(out) {}

void TerminalProgress::Report(double fraction, const std::string& message) {
  if (this->Quiet) return;
  const int percent = static_cast<int>(std::clamp(fraction, 0.0, 1.0) * 100.0 + 0.5);
  if (percent == this->LastPercent && message == this->LastMessage) return;
  this->LastPercent = percent;
  this->LastMessage = message;
  char percentText[8];
  std::snprintf(percentText, sizeof percentText, "%3d%%", percent);
  this->Out << "[" << this->Stage << "] " << percentText << " " << message << std::endl;
}

ProgressCallback TerminalProgress::Callback() {
  return [this](double f, const std::string& m) { this->Report(f, m); };
}

}  // namespace rp
