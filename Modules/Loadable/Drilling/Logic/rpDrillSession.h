#pragma once
// An interactive drilling session (the viewer's): the 1 kHz servo loop and the 30 Hz display
// thread on a voxel bone the caller keeps (it outlives the session: drilling can stop and go on),
// driven from the main thread: Update() at display rate takes
// the newest bone mesh (to swap into the model node) and drains the drill path into the
// recording file. The device is any HapticDevice (the simulated one moved by the panel or the
// mouse, a tracked tool, the OpenHaptics device).
#include <memory>
#include <string>

#include <vtkSmartPointer.h>

#include "rpDrillDisplay.h"
#include "rpDrillRecording.h"
#include "rpHapticScene.h"
#include "rpServoLoop.h"

class vtkPolyData;

namespace rp {

class DrillSession {
 public:
  struct Options {
    DrillServoOptions Servo;
    DrillControl Control;
    ServoLoop::Options Loop;
    double DisplayHz = 30;
    std::string RecordPath;  // drill recording ("" none)
  };

  explicit DrillSession(HapticDevice& device);
  ~DrillSession();

  /// Drills `bone` (the protected structures' surface and the scene's other haptic models are
  /// optional): contours it, opens the device and starts both threads.
  bool Start(DrillVolume& bone, const TriangleMesh& protectedSurface, std::unique_ptr<HapticScene> others,
             const Options& options, std::string& error);
  /// Display-rate update (main thread): the newest bone mesh, or nullptr when unchanged.
  vtkSmartPointer<vtkPolyData> Update();
  void Stop();
  bool Running() const { return this->Loop.Running(); }

  DrillServo& Servo() { return *this->Task; }
  const DrillDisplay& Display() const { return *this->Frames; }
  const ServoLoop& Scheduler() const { return this->Loop; }
  /// The mesh of the whole bone as it was contoured at Start().
  vtkSmartPointer<vtkPolyData> InitialMesh() const { return this->FirstMesh; }
  /// Burr centres of the path recorded so far (decimated to 100 Hz, for pictures).
  const std::vector<Vec3>& Path() const { return this->PathPoints; }
  size_t Recorded() const { return this->Writer.Count(); }
  void SetRpm(double rpm) { this->Rpm = rpm; }

 private:
  HapticDevice& Device;
  std::unique_ptr<DrillServo> Task;
  std::unique_ptr<DrillDisplay> Frames;
  ServoLoop Loop;
  BVH ProtectedTree;
  DrillRecordWriter Writer;
  vtkSmartPointer<vtkPolyData> FirstMesh;
  std::vector<Vec3> PathPoints;
  double LastPathTime = -1, Rpm = 0;
};

}  // namespace rp
