#pragma once
// Progress for long work, reported on the terminal as lines a user (or a log) can follow:
//   [mesh] 40% bone: smoothing
// Only prints when the integer percentage or the message changes; silent in --json mode.
#include <functional>
#include <ostream>
#include <string>

namespace rp {

/// A progress sink: fraction in [0,1] and a short message. Long operations take one of these.
using ProgressCallback = std::function<void(double fraction, const std::string& message)>;

class TerminalProgress {
 public:
  /// Lines on `out`: a command's error stream (rp::CommandContext::Err), where its messages go.
  TerminalProgress(std::string stage, bool quiet, std::ostream& out);
  void Report(double fraction, const std::string& message);
  ProgressCallback Callback();

 private:
  std::string Stage, LastMessage;
  int LastPercent = -1;
  bool Quiet;
  std::ostream& Out;
};

}  // namespace rp
