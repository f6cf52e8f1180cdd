// libFuzzer target: PLUS device-set configurations on arbitrary bytes, through the same path as
// `roboplan track --plus-config`: VTK's expat parser (rp::ParseXml), the configuration reader,
// its JSON report and the transform repository built from it with every served name asked for.
// Any input may be refused with a message; none may crash, hang or leak.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "rpPlusConfiguration.h"
#include "rpTransformRepository.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  rp::plus::Configuration configuration;
  std::string error;
  if (!rp::plus::ParseConfiguration(text, "/fuzz/PlusDeviceSet_Fuzz.xml", {}, configuration, error)) return 0;
  (void)rp::plus::ToJson(configuration).dump();
  (void)configuration.RefusedMessage();
  rp::TransformRepository repository;
  for (const auto& t : configuration.Transforms) {
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) m(r, c) = t.Matrix[4 * r + c];
    repository.SetFixed(t.From, t.To, m, error);
  }
  for (const auto& tracker : configuration.Trackers)
    for (const auto& tool : tracker.Tools) repository.DeclareLive(tool.Id, tracker.ToolReferenceFrame, error);
  for (const auto& name : configuration.OpenIGTLinkServer.TransformNames) {
    Eigen::Matrix4d m;
    rp::TransformStatus status;
    repository.Get(name.Name, m, status);
  }
  return 0;
}
