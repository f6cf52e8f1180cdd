// What must be registered: every file format (node storages and data readers), every tracker
// kind (pose sources) and every OpenIGTLink command. Each library or module lists its own in one
// place (rpStorageFormats.cxx, rpPoseSourceKinds.cxx, rpIgtlCommands.cxx' BuiltInCommands; the
// imaging readers through RegisterImagingReaders at start-up); a line dropped from a list, or a
// renamed class, would lose one without a word. This test names each one, so a registration that
// drops out fails here. A new format, tracker or command adds its line here (README "Extending
// RoboPlan").
#include <algorithm>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <vtkNew.h>

#include "rpDataLoader.h"
#include "rpIgtlCommands.h"
#include "rpImagingReaders.h"
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

// What roboplanMain.cxx does at start-up: the imaging readers are reached through rp::LoadPath
// only, so nothing else makes the linker keep their library (without this call, none is there).
const bool imagingReaders = rp::RegisterImagingReaders();

TEST(Registration, EveryDataReaderIsRegisteredOnce) {
  ASSERT_TRUE(imagingReaders);
  std::vector<std::string> names;
  for (const auto& reader : rp::GetDataReaders()) names.push_back(reader->Description());
  for (const char* name : {"RoboPlan scene", "3D Slicer scene", "Node file", "DICOM", "DICOM SEG / RTSTRUCT"})
    EXPECT_EQ(std::count(names.begin(), names.end(), name), 1) << name;
}

TEST(Registration, EachKindOfPathFindsItsReader) {
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

}  // namespace
