// PLUS recordings and PLUS's phantom registration, against PLUS's own files
// (../shared/oracles/plus-data, PlusLibData): the recording of a stylus on eight landmarks, the
// configuration PLUS's vtkPhantomRegistrationLandmarkDetectionTest reads it with, and that test's
// baseline PhantomToReference. Skipped, naming the path, without them.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>

#include "rpPhantomRegistrationCommand.h"
#include "rpPlusPhantomRegistration.h"
#include "rpPlusSequenceFile.h"
#include "rpSharedData.h"
#include "rpTrackingRecording.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPScene.h"
#include "vtkRPTrackingLogic.h"

namespace {

const std::string PlusData = std::string(ROBOPLAN_SHARED_DATA_DIR) + "/../oracles/plus-data";
const std::string RecordingFile = PlusData + "/TestImages/EightLandmarkPointsTrackedForPhantomRegistration.igs.mha";
const std::string ConfigFile = PlusData + "/ConfigFiles/PlusDeviceSet_fCal_Sim_RecordPhantomLandmarks.xml";
const std::string ResultFile = PlusData + "/TestImages/PhantomRegistrationLandmarkDetection.results.xml";

std::string OutputPath(const std::string& name) {
  std::filesystem::create_directories(ROBOPLAN_TEST_OUTPUT_DIR);
  return std::string(ROBOPLAN_TEST_OUTPUT_DIR) + "/" + name;
}

void WriteText(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

std::string ReadError(const std::string& path) {
  try {
    rp::ReadPlusSequence(path, true);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(PlusSequenceFile, ReadsPlusRecordingOfEightLandmarksWithItsTransformsStatusesAndTimes) {
  RP_REQUIRE_SHARED_DATA(RecordingFile);
  const rp::PlusSequence s = rp::ReadPlusSequence(RecordingFile);
  ASSERT_EQ(s.Frames.size(), 1000u);
  ASSERT_EQ(s.TransformNames, (std::vector<std::string>{"ReferenceToTracker", "StylusToTracker"}));
  EXPECT_EQ(s.FrameBytes(), 0u);  // DimSize = 0 0 1000: tracking only
  const rp::PlusSequence::Transform& stylus = s.Frames[0].Transforms[1];
  EXPECT_TRUE(stylus.Present);
  EXPECT_EQ(stylus.State, rp::ToolState::OK);
  EXPECT_DOUBLE_EQ(stylus.Matrix[0], 0.6839311099507384);
  EXPECT_DOUBLE_EQ(stylus.Matrix[3], 315.55283203125);
  EXPECT_DOUBLE_EQ(stylus.Matrix[11], -36.05361328125);
  EXPECT_DOUBLE_EQ(s.Frames[0].Timestamp, 280.4611428572264);
  EXPECT_DOUBLE_EQ(s.Frames[999].Timestamp, 347.0668714287492);
  ASSERT_FALSE(s.Frames[0].Fields.empty());
  EXPECT_EQ(s.Frames[0].Fields[0], (std::pair<std::string, std::string>{"ImageStatus", "INVALID"}));
  bool orientation = false;
  for (const auto& [key, value] : s.Global) orientation |= key == "UltrasoundImageOrientation" && value == "XX";
  EXPECT_TRUE(orientation);
  // As a Recording (replay, pivot): one tool per transform, named as PLUS names it.
  const rp::Recording r = rp::Recording::Read(RecordingFile);
  EXPECT_EQ(r.Tools, s.TransformNames);
  EXPECT_EQ(r.Samples.size(), 2000u);
}

TEST(PlusSequenceFile, WritesMetaImageAndNrrdThatReadBackToTheSameNumbers) {
  RP_REQUIRE_SHARED_DATA(RecordingFile);
  const rp::PlusSequence s = rp::ReadPlusSequence(RecordingFile);
  for (const char* name : {"roundtrip.igs.mha", "roundtrip.igs.nrrd"}) {
    const std::string path = OutputPath(name);
    rp::WritePlusSequence(s, path);
    const rp::PlusSequence back = rp::ReadPlusSequence(path);
    ASSERT_EQ(back.Frames.size(), s.Frames.size()) << name;
    ASSERT_EQ(back.TransformNames, s.TransformNames) << name;
    for (size_t f = 0; f < s.Frames.size(); f += 97) {
      EXPECT_EQ(back.Frames[f].Timestamp, s.Frames[f].Timestamp) << name;
      for (size_t t = 0; t < 2; ++t)
        for (int i = 0; i < 16; ++i) EXPECT_EQ(back.Frames[f].Transforms[t].Matrix[i], s.Frames[f].Transforms[t].Matrix[i]) << name;
    }
  }
}

TEST(PlusSequenceFile, KeepsImagePixelsAndStatusesThroughAWriteAndRead) {
  rp::PlusSequence s;
  s.FrameSize = {3, 2};
  s.Global = {{"UltrasoundImageOrientation", "MF"}, {"UltrasoundImageType", "BRIGHTNESS"}};
  const int probe = s.AddTransform("ProbeToTracker");
  for (int f = 0; f < 2; ++f) {
    rp::PlusSequence::Frame frame;
    frame.Timestamp = 10.0 + f / 3.0;
    frame.Transforms.resize(1);
    frame.Transforms[probe].Present = true;
    frame.Transforms[probe].State = f == 0 ? rp::ToolState::OK : rp::ToolState::Missing;
    frame.Transforms[probe].Matrix[3] = 1.25 * f;
    s.Frames.push_back(frame);
  }
  for (int i = 0; i < 12; ++i) s.Pixels.push_back(static_cast<uint8_t>(i * 7));
  for (const char* name : {"image.igs.mha", "image.igs.nrrd"}) {
    const std::string path = OutputPath(name);
    rp::WritePlusSequence(s, path);
    const rp::PlusSequence back = rp::ReadPlusSequence(path, true);
    EXPECT_EQ(back.Pixels, s.Pixels) << name;
    EXPECT_EQ(back.FrameSize, s.FrameSize) << name;
    EXPECT_EQ(back.Frames[1].Transforms[0].State, rp::ToolState::Missing) << name;
    EXPECT_EQ(back.Frames[1].Transforms[0].Matrix[3], 1.25) << name;
    EXPECT_EQ(back.Global, s.Global) << name;
  }
}

TEST(PlusSequenceFile, RefusesMalformedFilesWithAMessageNamingTheProblem) {
  const std::string header = "ObjectType = Image\nNDims = 3\nDimSize = 0 0 2\nElementType = MET_UCHAR\n";
  const std::string path = OutputPath("bad.igs.mha");
  WriteText(path, header + "Seq_Frame0005_Timestamp = 1\nElementDataFile = LOCAL\n");
  EXPECT_NE(ReadError(path).find("beyond the 2 frames"), std::string::npos) << ReadError(path);
  WriteText(path, header + "Seq_Frame0000_StylusToTrackerTransform = 1 0 0\nElementDataFile = LOCAL\n");
  EXPECT_NE(ReadError(path).find("16 numbers"), std::string::npos) << ReadError(path);
  WriteText(path, "ObjectType = Image\nNDims = 3\nDimSize = 4 4 2\nElementType = MET_UCHAR\nElementDataFile = LOCAL\nabc");
  EXPECT_NE(ReadError(path).find("truncated"), std::string::npos) << ReadError(path);
  WriteText(path, header + "Seq_Frame99999999999999_Timestamp = 1\nElementDataFile = LOCAL\n");
  EXPECT_NE(ReadError(path).find("out of range"), std::string::npos) << ReadError(path);
  WriteText(path, "ObjectType = Image\nDimSize = 0 0 1\nElementType = MET_WHAT\nElementDataFile = LOCAL\n");
  EXPECT_NE(ReadError(path).find("MET_WHAT"), std::string::npos) << ReadError(path);
  WriteText(path, "NRRD0004\ntype: unsigned char\n");
  EXPECT_NE(ReadError(path).find("sizes"), std::string::npos) << ReadError(path);
  EXPECT_NE(ReadError(OutputPath("absent.igs.mha")).find("absent.igs.mha"), std::string::npos);
}

TEST(PlusPhantomRegistration, ReproducesPlusPhantomToReferenceWithinPlusOwnTestTolerance) {
  RP_REQUIRE_SHARED_DATA(PlusData);
  const rp::PlusPhantomConfiguration config = rp::PlusPhantomConfiguration::Read(ConfigFile);
  ASSERT_EQ(config.Landmarks.size(), 8u);
  EXPECT_DOUBLE_EQ(config.StylusTipToStylus(0, 3), 108.565);
  EXPECT_DOUBLE_EQ(config.MinimumLandmarkDistance(), 15.0);  // #5 (-34.3 45 15) and #8 (-34.3 45 0)
  const rp::PhantomRegistrationResult r = rp::RegisterPhantomFromRecording(rp::ReadPlusSequence(RecordingFile), config);
  ASSERT_TRUE(r.Ok) << r.Error;
  ASSERT_EQ(r.Landmarks.size(), 8u);
  Eigen::Matrix4d plus;
  double plusError = 0, mm = 0, deg = 0;
  ASSERT_TRUE(rp::ReadPlusCoordinateDefinition(ResultFile, "Phantom", "Reference", plus, plusError));
  rp::PoseDifference(r.PhantomToReference, plus, mm, deg);
  std::cout << "PLUS method: " << mm << " mm, " << deg << " deg from PLUS; error figure " << r.PlusErrorMm << " mm (PLUS "
            << plusError << "), FRE " << r.FRE << " mm, predicted TRE " << r.PredictedTREAtCentroid << " mm at the centroid, " << r.MaxPredictedTREAtLandmarks << " mm at the worst landmark (FLE " << r.EstimatedFLE << " mm)\n";
  // PLUS's vtkPhantomRegistrationLandmarkDetectionTest accepts 0.1 mm and 0.2 degrees against this
  // baseline; we are at 0.086 mm and 0.128 degrees (the 0.05/0.05 is not reached). ITK's
  // LandmarkBasedTransformInitializer (VersorRigid3D, what PLUS calls) on our eight landmarks gives
  // our transform to 1e-6 mm, and PLUS's frame filtering and first-two-frames rate change nothing
  // on this recording: the rest is in the baseline itself (written in 2014 by an earlier PLUS,
  // with a stylus calibration other than the configuration's).
  EXPECT_LT(mm, 0.1);
  EXPECT_LT(deg, 0.2);
  EXPECT_NEAR(r.PlusErrorMm, plusError, 0.005);  // the same mean landmark distance
  EXPECT_GE(r.FRE, r.PlusErrorMm);              // RMS ≥ mean
  EXPECT_GT(r.PredictedTREAtCentroid, 0);
  EXPECT_LT(r.PredictedTREAtCentroid, r.FRE);   // 8 well-spread landmarks: TRE at the centre < FLE
}

TEST(PlusPhantomRegistration, PivotPointsOfTheRestsGiveARegistrationCloseToPlus) {
  RP_REQUIRE_SHARED_DATA(PlusData);
  const rp::PlusPhantomConfiguration config = rp::PlusPhantomConfiguration::Read(ConfigFile);
  const rp::PhantomRegistrationResult pivot =
      rp::RegisterPhantomFromRecording(rp::ReadPlusSequence(RecordingFile), config, rp::LandmarkDetectionMethod::Pivot);
  ASSERT_TRUE(pivot.Ok) << pivot.Error;
  Eigen::Matrix4d plus;
  double plusError = 0, mm = 0, deg = 0;
  ASSERT_TRUE(rp::ReadPlusCoordinateDefinition(ResultFile, "Phantom", "Reference", plus, plusError));
  rp::PoseDifference(pivot.PhantomToReference, plus, mm, deg);
  std::cout << "pivot method: " << mm << " mm, " << deg << " deg from PLUS; FRE " << pivot.FRE << " mm, mean "
            << pivot.PlusErrorMm << " mm\n";
  // Each rest pivots only ~17 degrees (PLUS needs 30 mm at 100 mm up the shaft), too little for
  // a pivot point as good as the calibrated tip: the pivot method is within 2 mm / 3 degrees only.
  EXPECT_LT(mm, 2.0);
  EXPECT_LT(deg, 3.0);
}

TEST(PlusPhantomRegistration, DropsFramesThatRepeatTheLastTimeStampAsPlusReaderDoes) {
  RP_REQUIRE_SHARED_DATA(PlusData);
  const rp::PlusPhantomConfiguration config = rp::PlusPhantomConfiguration::Read(ConfigFile);
  const rp::PlusSequence original = rp::ReadPlusSequence(RecordingFile);
  rp::PlusSequence repeated = original;
  // PLUS reads with REQUIRE_UNIQUE_TIMESTAMP: a repeat of frame 0 (which would make the first-two-
  // frames rate infinite) and repeats inside rests (which would shift the detector's windows) are dropped.
  for (size_t f : {600u, 300u, 90u, 0u}) repeated.Frames.insert(repeated.Frames.begin() + f, repeated.Frames[f]);
  const rp::PhantomRegistrationResult a = rp::RegisterPhantomFromRecording(original, config);
  const rp::PhantomRegistrationResult b = rp::RegisterPhantomFromRecording(repeated, config);
  ASSERT_TRUE(a.Ok) << a.Error;
  ASSERT_TRUE(b.Ok) << b.Error;
  EXPECT_EQ(b.FramesSkipped, a.FramesSkipped + 4);
  EXPECT_TRUE(b.PhantomToReference.isApprox(a.PhantomToReference, 1e-12));
}

TEST(PlusPhantomRegistration, RefusesARecordingWithoutTheStylusNamingTheTransformsItHas) {
  RP_REQUIRE_SHARED_DATA(PlusData);
  rp::PlusPhantomConfiguration config = rp::PlusPhantomConfiguration::Read(ConfigFile);
  config.StylusFrame = "Needle";
  const rp::PhantomRegistrationResult r = rp::RegisterPhantomFromRecording(rp::ReadPlusSequence(RecordingFile), config);
  EXPECT_FALSE(r.Ok);
  EXPECT_NE(r.Error.find("NeedleToReference"), std::string::npos) << r.Error;
  EXPECT_NE(r.Error.find("StylusToTracker"), std::string::npos) << r.Error;
}

TEST(PhantomRegistrationCommand, ComparesWithPlusAndWritesTheConfigurationFCalWould) {
  RP_REQUIRE_SHARED_DATA(PlusData);
  const std::string out = OutputPath("PhantomRegistration.xml");
  std::ostringstream text, err;
  ASSERT_EQ(rp::RunPhantomRegistrationCommand({RecordingFile, "--plus-config", ConfigFile, "--compare", ResultFile, "--out", out, "--json"},
                                              text, err),
            0)
      << err.str();
  const nlohmann::json doc = nlohmann::json::parse(text.str());
  EXPECT_TRUE(doc["comparison"]["within"].get<bool>());
  EXPECT_EQ(doc["landmarks"].size(), 8u);
  Eigen::Matrix4d written;
  double error = 0;
  ASSERT_TRUE(rp::ReadPlusCoordinateDefinition(out, "Phantom", "Reference", written, error));
  EXPECT_NEAR(written(0, 3), doc["phantomToReference"][3].get<double>(), 1e-6);
  EXPECT_NEAR(error, doc["plusErrorMm"].get<double>(), 1e-6);
  Eigen::Matrix4d tip;
  ASSERT_TRUE(rp::ReadPlusCoordinateDefinition(out, "StylusTip", "Stylus", tip, error));  // the rest kept
  std::ostringstream none, noneErr;
  EXPECT_EQ(rp::RunPhantomRegistrationCommand({RecordingFile, "--plus-config", RecordingFile}, none, noneErr), 1);
  EXPECT_NE(noneErr.str().find("malformed XML"), std::string::npos) << noneErr.str();
}

// The Tracking logic's phantom registration (what the command runs through): the same result as
// the library's, PhantomToReference applied under the reference tool's node with the FRE; a file
// that cannot be read leaves the scene as it was and names the problem.
TEST(PhantomRegistrationLogic, AppliesPhantomToReferenceUnderTheReferenceToolWithItsFRE) {
  RP_REQUIRE_SHARED_DATA(PlusData);
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPLinearTransformNode> reference;
  reference->SetName("ReferenceToTracker");
  scene->AddNode(reference);
  vtkNew<vtkRPTrackingLogic> logic;
  logic->SetScene(scene);
  rp::PlusPhantomConfiguration config;
  vtkRPLinearTransformNode* applied = nullptr;
  const rp::PhantomRegistrationResult r =
      logic->RegisterPhantom(RecordingFile, ConfigFile, rp::LandmarkDetectionMethod::Plus, config, &applied);
  ASSERT_TRUE(r.Ok) << r.Error;
  const rp::PhantomRegistrationResult direct =
      rp::RegisterPhantomFromRecording(rp::ReadPlusSequence(RecordingFile), rp::PlusPhantomConfiguration::Read(ConfigFile));
  EXPECT_TRUE(r.PhantomToReference.isApprox(direct.PhantomToReference, 1e-12));
  ASSERT_NE(applied, nullptr);
  EXPECT_EQ(applied->GetName(), "PhantomToReference");
  EXPECT_EQ(applied->GetTransformNodeID(), reference->GetID());
  EXPECT_NEAR(applied->GetMatrixTransformToParent()->GetElement(0, 3), r.PhantomToReference(0, 3), 1e-9);
  EXPECT_NEAR(std::stod(applied->GetAttribute(vtkRPTrackingLogic::PhantomRegistrationFREAttribute())), r.FRE, 1e-6);
  const int nodes = scene->GetNumberOfNodes();
  const rp::PhantomRegistrationResult bad =
      logic->RegisterPhantom(RecordingFile, RecordingFile, rp::LandmarkDetectionMethod::Plus, config);
  EXPECT_FALSE(bad.Ok);
  EXPECT_NE(bad.Error.find("malformed XML"), std::string::npos) << bad.Error;
  EXPECT_EQ(scene->GetNumberOfNodes(), nodes);
}
