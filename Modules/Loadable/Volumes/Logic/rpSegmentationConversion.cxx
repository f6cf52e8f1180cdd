#include "rpSegmentationConversion.h"

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <vtkNew.h>
#include <vtkSmartPointer.h>

#include "rpArgParser.h"
#include "rpDataLoader.h"
#include "rpDicomReferenceSeries.h"
#include "rpDicomRtStruct.h"
#include "rpDicomSegmentation.h"
#include "rpImageVolume.h"
#include "rpLabelmapInput.h"
#include "rpNodeStorage.h"
#include "rpSegmentationIO.h"
#include "rpVolumeFiles.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"

namespace fs = std::filesystem;

namespace rp {
namespace {

// What becomes the .seg.nrrd, and how it was read.
struct SegmentationInput {
  vtkSmartPointer<vtkRPScene> Scene;  // holds what the loader read
  vtkSmartPointer<vtkRPSegmentationNode> Node;
  std::string Kind = "segmentation";  // or "labelmap"
  std::string Reason;                 // a labelmap's: why its values were taken as labels
  std::vector<std::string> Warnings;
};

// Why the conversion stops: the exit code (2: the arguments, 1: the work) and what to say.
struct Failure {
  int Code = 1;
  std::string Message;
};

bool Fail(Failure& failure, int code, const std::string& message) {
  failure = {code, message};
  return false;
}

// A DICOM SEG or RTSTRUCT (a file, or the folder's only one) on the grid of --reference.
bool ReadOnReference(const std::string& in, const std::string& reference, SegmentationInput& input, Failure& failure) {
  std::string object;
  const int kind = DicomSegmentationObjectKind(in, &object, &failure.Message);
  if (kind < 0) return false;
  if (kind == 0) return Fail(failure, 2, "--reference goes with a DICOM SEG or RTSTRUCT input; '" + in + "' holds none");
  input.Node = vtkSmartPointer<vtkRPSegmentationNode>::New();
  return kind == 1 ? ReadDicomSegmentation(object, input.Node, failure.Message, reference, &input.Warnings)
                   : ReadDicomRtStruct(object, input.Node, failure.Message, reference, &input.Warnings);
}

// A labelmap volume as a segmentation: one segment per label value (--input-kind, --labels).
bool LabelmapInput(const ArgParser& parser, vtkImageData* image, const vtkMatrix4x4* ijkToRAS, SegmentationInput& input,
                   Failure& failure) {
  InputKind kind = InputKind::Auto;
  if (!ParseInputKind(parser.Get("input-kind"), kind))
    return Fail(failure, 2, "--input-kind '" + parser.Get("input-kind") + "': use auto, labelmap or intensity");
  const InputChoice choice = ChooseInputKind(kind, image, parser.Get("in"), "a .seg.nrrd output");
  if (!choice.Labelmap)
    return Fail(failure, 2,
                "'" + parser.Get("in") + "' is an " + choice.Reason +
                    ": an image does not convert to a segmentation file (segment it with `roboplan mesh`), a labelmap "
                    "does (--input-kind labelmap)");
  LabelTable table;
  if (parser.Has("labels") && !ReadLabelTable(parser.Get("labels"), table, failure.Message)) return false;
  input.Node = vtkSmartPointer<vtkRPSegmentationNode>::New();
  input.Kind = "labelmap";
  input.Reason = choice.Reason;
  return LabelmapToSegmentation(image, ijkToRAS, parser.Has("labels") ? &table : nullptr, input.Node, failure.Message,
                                choice.Scanned ? &choice.Values : nullptr);
}

// "'in' holds 2 segmentations: SEG "bones" (1.2.3), RTSTRUCT "knee" (1.2.4); choose one ..."
std::string Choices(const std::string& in, const LoadResult& load, bool segmentations) {
  std::string list;
  size_t count = 0;
  for (const auto& o : load.Details.value("objects", nlohmann::json::array())) {
    if ((o.value("kind", std::string()) != "volume") != segmentations) continue;
    std::string kind = o.value("modality", std::string());
    if (kind.empty()) kind = o.value("kind", std::string());
    list += (list.empty() ? "" : ", ") + kind + " \"" + o.value("description", std::string()) + "\" (" +
            o.value("id", std::string()) + ")";
    ++count;
  }
  return "'" + in + "' holds " + std::to_string(count) + (segmentations ? " segmentations" : " image series") + ": " +
         list + "; choose one with --series <ID>";
}

// The input through the one loader (rp::LoadPath): the one segmentation it holds, else the one
// volume as a labelmap; --reference reads a SEG or RTSTRUCT on that series' grid instead.
bool ReadInput(const ArgParser& parser, SegmentationInput& input, Failure& failure) {
  const std::string in = parser.Get("in");
  if (parser.Has("reference")) return ReadOnReference(in, parser.Get("reference"), input, failure);
  input.Scene = vtkSmartPointer<vtkRPScene>::New();
  ReadOptions options;
  options.Series = parser.Get("series");
  options.ResampleIrregularSpacing = parser.Has("resample-irregular");
  const LoadResult load = LoadPath(input.Scene, in, options);
  if (!load.Ok) {
    // A plain labelmap named *.seg.nrrd (no Slicer segment keys), as earlier versions wrote them.
    ImageVolume volume;
    std::string volumeError;
    if (HasExtension(in, ".seg.nrrd") && ReadVolume(in, volume, volumeError))
      return LabelmapInput(parser, volume.Image, volume.IJKToRAS, input, failure);
    return Fail(failure, 1, load.Error);
  }
  input.Warnings = load.Warnings;
  std::vector<vtkRPSegmentationNode*> segmentations;
  std::vector<vtkRPScalarVolumeNode*> volumes;
  for (const auto& node : load.Nodes) {
    if (auto* segmentation = vtkRPSegmentationNode::SafeDownCast(node)) segmentations.push_back(segmentation);
    if (auto* volume = vtkRPScalarVolumeNode::SafeDownCast(node)) volumes.push_back(volume);
  }
  if (segmentations.size() == 1) {
    input.Node = segmentations.front();
    return true;
  }
  if (segmentations.size() > 1) return Fail(failure, 1, Choices(in, load, true));
  if (volumes.size() == 1)
    return LabelmapInput(parser, volumes.front()->GetImageData(), volumes.front()->GetIJKToRASMatrix(), input, failure);
  return Fail(failure, 1, volumes.empty() ? "'" + in + "' holds no segmentation or labelmap" : Choices(in, load, false));
}

// .seg.nrrd → DICOM SEG on the grid of --reference (a .dcm file, or a folder receiving
// segmentation.dcm).
int WriteDicomSeg(const ArgParser& parser, std::ostream& out, std::ostream& err) {
  const std::string in = parser.Get("in"), outPath = parser.Get("out"), reference = parser.Get("reference");
  if (reference.empty()) {
    err << "roboplan convert: writing a DICOM SEG needs the image series it segments: --reference <DICOM folder>\n";
    return 2;
  }
  std::string file = outPath;
  if (!HasExtension(outPath, ".dcm")) {
    std::error_code ec;
    fs::create_directories(outPath, ec);
    file = (fs::path(outPath) / "segmentation.dcm").string();
  }
  vtkNew<vtkRPSegmentationNode> node;
  std::string error;
  if (!ReadSegmentationFile(in, node, error) || !WriteDicomSegmentation(node, reference, file, error)) {
    err << "roboplan convert: " << error << "\n";
    return 1;
  }
  if (parser.Json()) {
    const nlohmann::json doc = {{"ok", true}, {"input", in}, {"output", outPath}, {"segments", node->GetNumberOfSegments()},
                                {"outputFormat", "DICOM SEG"}, {"warnings", nlohmann::json::array()}};
    out << doc.dump(2) << "\n";
  } else {
    out << "wrote " << outPath << " (" << node->GetNumberOfSegments() << " segments)\n";
  }
  return 0;
}

void Report(const ArgParser& parser, const SegmentationInput& input, std::ostream& out, std::ostream& err) {
  vtkRPSegmentationNode* node = input.Node;
  for (const auto& w : input.Warnings) err << "roboplan convert: warning: " << w << "\n";
  if (parser.Json()) {
    nlohmann::json names = nlohmann::json::array();
    for (const auto& segment : node->GetSegments()) names.push_back(segment.Name);
    nlohmann::json doc = {{"ok", true}, {"input", parser.Get("in")}, {"output", parser.Get("out")},
                          {"segments", node->GetNumberOfSegments()}, {"segmentNames", names},
                          {"inputKind", input.Kind}, {"outputFormat", "segmentation file"}, {"warnings", input.Warnings}};
    if (!input.Reason.empty()) doc["inputKindReason"] = input.Reason;
    out << doc.dump(2) << "\n";
  } else {
    out << "wrote " << parser.Get("out") << " (" << node->GetNumberOfSegments() << " segments"
        << (input.Reason.empty() ? "" : " from a " + input.Reason) << ")\n";
  }
}

}  // namespace

std::optional<int> ConvertSegmentation(const ArgParser& parser, std::ostream& out, std::ostream& err) {
  const std::string in = parser.Get("in"), outPath = parser.Get("out");
  if (HasExtension(in, ".seg.nrrd") && !HasExtension(outPath, ".nrrd")) return WriteDicomSeg(parser, out, err);
  if (!HasExtension(outPath, ".seg.nrrd")) {
    // A volume output: a SEG or RTSTRUCT file has no image to give (a folder has its series).
    std::error_code ec;
    const int kind = fs::is_regular_file(in, ec) ? DicomSegmentationObjectKind(in) : 0;
    if (kind <= 0) return std::nullopt;
    err << "roboplan convert: a DICOM " << (kind == 1 ? "SEG" : "RTSTRUCT") << " converts to a segmentation file (.seg.nrrd)\n";
    return 2;
  }
  SegmentationInput input;
  Failure failure;
  std::string error;
  if (!ReadInput(parser, input, failure)) {
    err << "roboplan convert: " << failure.Message << "\n";
    return failure.Code;
  }
  if (!WriteSegmentationFile(outPath, input.Node, error)) {
    err << "roboplan convert: " << error << "\n";
    return 1;
  }
  Report(parser, input, out, err);
  return 0;
}

}  // namespace rp
