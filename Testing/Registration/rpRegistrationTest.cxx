// What must be registered: every file format (node storages and data readers), every tracker
// kind (pose sources) and every OpenIGTLink command. Each library or module lists its own in one
// place (rpStorageFormats.cxx, rpPoseSourceKinds.cxx, rpIgtlCommands.cxx' BuiltInCommands; the
// imaging readers through RegisterImagingReaders, called by each module that reads DICOM through
// the loader when it is set up); a line dropped from a list, a renamed class or a module that no
// longer calls its Register...() would lose one without a word. This test names each one, so a
// registration that drops out fails here. A new format, tracker or command adds its line here
// (README "Extending RoboPlan"). Nothing registers when a library loads: no static registrar.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <vtkNew.h>

#include "rpDataLoader.h"
#include "rpIgtlCommands.h"
#include "rpImagingReaders.h"
#include "rpModuleManager.h"
#include "rpNodeStorage.h"
#include "rpPoseSource.h"
#include "vtkRPScene.h"

namespace {

std::vector<std::string> Sorted(std::vector<std::string> items) {
  std::sort(items.begin(), items.end());
  return items;
}

bool Contains(const std::vector<std::string>& items, const std::string& item) {
  return std::find(items.begin(), items.end(), item) != items.end();
}

TEST(Registration, EveryNodeFileFormatHasItsStorage) {
  const struct {
    const char* NodeClass;
    std::vector<std::string> Extensions;
  } expected[] = {
      {"vtkRPScalarVolumeNode", {".nrrd", ".nii.gz", ".nhdr", ".nii", ".mha", ".mhd"}},
      {"vtkRPSegmentationNode", {".seg.nrrd"}},
      {"vtkRPModelNode", {".vtp", ".vtk", ".stl", ".ply", ".obj"}},
      {"vtkRPFiducialListNode", {".mrk.json", ".fcsv"}},
      {"vtkRPLinearTransformNode", {".tfm", ".txt", ".h5"}},
  };
  for (const auto& format : expected) {
    const auto registered = rp::ExtensionsForNodeClass(format.NodeClass);
    for (const auto& extension : format.Extensions)
      EXPECT_TRUE(Contains(registered, extension)) << format.NodeClass << " " << extension << " is not registered";
  }
}

// What the modules that read DICOM through the loader do when they are set up (and the viewer):
// the imaging readers are reached through rp::LoadPath only, so nothing else registers them.
TEST(Registration, EveryDataReaderIsRegisteredOnce) {
  ASSERT_TRUE(rp::RegisterImagingReaders());
  ASSERT_TRUE(rp::RegisterImagingReaders());  // idempotent: still once each
  std::vector<std::string> names;
  for (const auto& reader : rp::GetDataReaders()) names.push_back(reader->Description());
  for (const char* name : {"RoboPlan scene", "3D Slicer scene", "Node file", "DICOM", "DICOM SEG / RTSTRUCT"})
    EXPECT_EQ(std::count(names.begin(), names.end(), name), 1) << name;
}

TEST(Registration, EachKindOfPathFindsItsReader) {
  ASSERT_TRUE(rp::RegisterImagingReaders());
  const std::string folder = ROBOPLAN_TEST_OUTPUT_DIR;  // exists: the test's own output folder
  const struct {
    std::string Path;
    const char* Reader;
  } expected[] = {{"knee.rpscene", "RoboPlan scene"}, {"ct.nrrd", "Node file"}, {"bones.seg.nrrd", "Node file"},
                  {"femur.vtp", "Node file"},         {"landmarks.mrk.json", "Node file"},
                  {"MRToCT.tfm", "Node file"},        {"plan.mrml", "3D Slicer scene"},
                  {"plan.mrb", "3D Slicer scene"},    {folder, "DICOM"}};
  for (const auto& path : expected) {
    const rp::DataReader* reader = rp::FindDataReader(path.Path);
    ASSERT_NE(reader, nullptr) << path.Path;
    EXPECT_EQ(reader->Description(), path.Reader) << path.Path;
  }
  EXPECT_EQ(rp::FindDataReader("notes.unknown-extension"), nullptr);
}

TEST(Registration, EveryTrackerKindIsRegistered) {
  std::vector<std::string> kinds;
  for (const auto& entry : rp::PoseSourceRegistry::Entries()) kinds.push_back(entry.Kind);
  for (const char* kind : {"serial", "tcp", "igtl", "simulator", "replay"})
    EXPECT_TRUE(Contains(kinds, kind)) << kind << " not in " << ::testing::PrintToString(Sorted(kinds));
}

TEST(Registration, EveryNodeStorageIsRegisteredOnce) {
  std::vector<std::string> classes;
  for (const auto& storage : rp::GetNodeStorages()) classes.push_back(storage->NodeClassForFiles());
  for (const char* nodeClass : {"vtkRPScalarVolumeNode", "vtkRPSegmentationNode", "vtkRPModelNode",
                                "vtkRPFiducialListNode", "vtkRPLinearTransformNode"})
    EXPECT_EQ(std::count(classes.begin(), classes.end(), nodeClass), 1) << nodeClass;
}

TEST(Registration, EveryOpenIGTLinkCommandIsRegisteredWithItsAccess) {
  const struct {
    const char* Name;
    rp::IgtlCommandAccess Access;
  } expected[] = {{"RequestChannelIds", rp::IgtlCommandAccess::ReadOnly},
                  {"RequestDeviceIds", rp::IgtlCommandAccess::ReadOnly},
                  {"StartRecording", rp::IgtlCommandAccess::ChangesState},
                  {"StopRecording", rp::IgtlCommandAccess::ChangesState},
                  {"GetTransform", rp::IgtlCommandAccess::ReadOnly},
                  {"UpdateTransform", rp::IgtlCommandAccess::ChangesState}};
  for (const auto& command : expected) {
    rp::IgtlCommandAccess access{};
    ASSERT_TRUE(rp::IgtlCommandAccessOf(command.Name, access)) << command.Name;
    EXPECT_EQ(access, command.Access) << command.Name;
  }
  EXPECT_EQ(rp::IgtlCommandNames().size(), std::size(expected));
}

// Set up alone (with its dependencies) as `roboplan <command>` sets it up, in a process of its own,
// the module that owns `command`: 0 when the DICOM reader is then registered (it reads DICOM
// through the loader), 1 when not, 3 when it was registered before (the check could not fail).
int DicomReaderAfterSettingUp(const std::string& command) {
  const std::string folder = ROBOPLAN_TEST_OUTPUT_DIR;  // exists: a folder is the DICOM reader's
  if (rp::FindDataReader(folder)) return 3;
  rp::ModuleManager manager;
  vtkNew<vtkRPScene> scene;
  manager.DiscoverModules({ROBOPLAN_BINARY_DIR "/lib/roboplan-modules"});
  if (!manager.LoadCommand(command, scene)) {
    for (const auto& failure : manager.GetFailures()) std::fprintf(stderr, "%s: %s\n", failure.Path.c_str(), failure.Reason.c_str());
    return 4;
  }
  const rp::DataReader* reader = rp::FindDataReader(folder);
  return reader && reader->Description() == "DICOM" ? 0 : 1;
}

struct ModuleCase {
  const char* Command;  // the module is the one that owns it
  int Expected;         // 0: registers the imaging readers; 1: does not (reads no DICOM)
};

void PrintTo(const ModuleCase& c, std::ostream* os) { *os << "roboplan " << c.Command; }

class ModuleRegistration : public ::testing::TestWithParam<ModuleCase> {};

// Each module whose work reads DICOM through the loader calls RegisterImagingReaders in its
// Setup (<Name>Module.cxx): a module that forgets fails here. Each case runs in a fresh process
// (a death test, "threadsafe": the child starts this program anew), so nothing registered by
// another test or module is there. Tracking reads no DICOM and registers nothing: the control
// that the check can fail. (Demo also gets them from its dependencies.)
TEST_P(ModuleRegistration, TheModulesThatReadDicomRegisterTheImagingReaders) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const ModuleCase c = GetParam();
  EXPECT_EXIT(std::exit(DicomReaderAfterSettingUp(c.Command)), ::testing::ExitedWithCode(c.Expected), "")
      << "roboplan " << c.Command << "'s module";
}

INSTANTIATE_TEST_SUITE_P(Modules, ModuleRegistration,
                         ::testing::Values(ModuleCase{"dicom", 0}, ModuleCase{"mesh", 0}, ModuleCase{"drill", 0},
                                           ModuleCase{"plan", 0}, ModuleCase{"demo", 0},
#ifdef ROBOPLAN_REGISTRATION_TEST_VIEWER
                                           ModuleCase{"screenshot", 0},
#endif
                                           ModuleCase{"track", 1}),
                         [](const ::testing::TestParamInfo<ModuleCase>& info) { return std::string(info.param.Command); });

}  // namespace
