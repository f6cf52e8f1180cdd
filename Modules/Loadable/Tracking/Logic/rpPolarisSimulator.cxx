#include "rpPolarisSimulator.h"

#include <algorithm>
#include <filesystem>

#include "rpResources.h"
#include "rpToolPose.h"

namespace rp {

std::vector<std::string> DefaultToolFiles() {
  std::vector<std::string> files;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(ResourcePath("Tools"), ec))
    if (entry.path().extension() == ".json") files.push_back(entry.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

PolarisSimulator::PolarisSimulator() : PolarisSimulator(Options()) {}

PolarisSimulator::PolarisSimulator(Options options)
    : Opts(std::move(options)),
      Link(this->Opts),
      Device(this->Opts, this->Tools, [this](uint8_t* data, size_t length, bool ascii) {
        this->Link.Send(data, length, ascii);
      }) {}

PolarisSimulator::~PolarisSimulator() { this->Stop(); }

bool PolarisSimulator::Start(std::string& error) {
  this->Stop();
  this->Device.PowerOn(SteadySeconds());
  if (!this->Link.Open(error)) return false;
  this->Worker.Start([this] { this->Run(); });
  return true;
}

void PolarisSimulator::Stop() {
  this->Worker.Stop();
  this->Link.Close();
}

void PolarisSimulator::Run() {
  bool wasUnplugged = false;
  while (!this->Worker.StopRequested()) {
    if (this->Link.Unplugged()) {
      wasUnplugged = true;
      this->Worker.Sleep(0.005);
      continue;
    }
    if (wasUnplugged) {  // a replugged device starts from power-on
      wasUnplugged = false;
      this->Device.PowerOnReset();
    }
    if (this->Link.TakeBreak()) this->Device.Break(this->Opts.AcceptBreak);
    this->Link.Poll(
        5, [this] { this->Device.ClearInput(); },
        [this](const char* data, size_t length) { this->Device.Receive(data, length); });
  }
}

}  // namespace rp
