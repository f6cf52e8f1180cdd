#include "rpSegmentationConversion.h"

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <vtkNew.h>
#include <vtkSmartPointer.h>

#include "rpDataLoader.h"
#include "rpDicomEntries.h"
#include "rpDicomMagic.h"
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

// A DICOM SEG or RTSTRUCT (a file, or the folder's only one) on the grid of --reference. The DICOM
// library loads here (rpDicomEntries.h); without it, the error names it.
bool ReadOnReference(const std::string& in, const std::string& reference, SegmentationInput& input, Failure& failure) {
  const auto objectKind = dicom::Entry<dicom::ObjectKindFunction>(dicom::ObjectKindEntry, in, failure.Message);
  if (!objectKind) return false;
  std::string object;
  const int kind = objectKind(in, &object, &failure.Message);
  if (kind < 0) return false;
  if (kind == 0) return Fail(failure, 2, "--reference goes with a DICOM SEG or RTSTRUCT input; '" + in + "' holds none");
  const auto read = dicom::Entry<dicom::ReadSegmentationFunction>(
      kind == 1 ? dicom::ReadSegmentationEntry : dicom::ReadRtStructEntry, in, failure.Message);
  input.Node = vtkSmartPointer<vtkRPSegmentationNode>::New();
  return read && read(object, input.Node, failure.Message, reference, &input.Warnings);
}

// A labelmap volume as a segmentation: one segment per label value (--input-kind, --labels).
bool LabelmapInput(const SegmentationConversionRequest& request, vtkImageData* image, const vtkMatrix4x4* ijkToRAS,
                   SegmentationInput& input, Failure& failure) {
  InputKind kind = InputKind::Auto;
  if (!ParseInputKind(request.InputKind, kind))
    return Fail(failure, 2, "--input-kind '" + request.InputKind + "': use auto, labelmap or intensity");
  const InputChoice choice = ChooseInputKind(kind, image, request.In, "a .seg.nrrd output");
  if (!choice.Labelmap)
    return Fail(failure, 2,
                "'" + request.In + "' is an " + choice.Reason +
                    ": an image does not convert to a segmentation file (segment it with `roboplan mesh`), a labelmap "
                    "does (--input-kind labelmap)");
  LabelTable table;
  if (!request.Labels.empty() && !ReadLabelTable(request.Labels, table, failure.Message)) return false;
  input.Node = vtkSmartPointer<vtkRPSegmentationNode>::New();
  input.Kind = "labelmap";
  input.Reason = choice.Reason;
  return LabelmapToSegmentation(image, ijkToRAS, !request.Labels.empty() ? &table : nullptr, input.Node, failure.Message,
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
bool ReadInput(const SegmentationConversionRequest& request, SegmentationInput& input, Failure& failure) {
  const std::string& in = request.In;
  if (!request.Reference.empty()) return ReadOnReference(in, request.Reference, input, failure);
  input.Scene = vtkSmartPointer<vtkRPScene>::New();
  ReadOptions options;
  options.Series = request.Series;
  options.ResampleIrregularSpacing = request.ResampleIrregularSpacing;
  const LoadResult load = LoadPath(input.Scene, in, options);
  if (!load.Ok) {
    // A plain labelmap named *.seg.nrrd (no Slicer segment keys), as earlier versions wrote them.
    ImageVolume volume;
    std::string volumeError;
    if (HasExtension(in, ".seg.nrrd") && ReadVolume(in, volume, volumeError))
      return LabelmapInput(request, volume.Image, volume.IJKToRAS, input, failure);
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
    return LabelmapInput(request, volumes.front()->GetImageData(), volumes.front()->GetIJKToRASMatrix(), input, failure);
  return Fail(failure, 1, volumes.empty() ? "'" + in + "' holds no segmentation or labelmap" : Choices(in, load, false));
}

// .seg.nrrd → DICOM SEG on the grid of the reference series (a .dcm file, or a folder receiving
// segmentation.dcm).
void WriteDicomSeg(const SegmentationConversionRequest& request, SegmentationConversion& result) {
  result.OutputFormat = "DICOM SEG";
  if (request.Reference.empty()) {
    result.FailureCode = 2;
    result.Error = "writing a DICOM SEG needs the image series it segments: --reference <DICOM folder>";
    return;
  }
  std::string file = request.Out;
  if (!HasExtension(request.Out, ".dcm")) {
    std::error_code ec;
    fs::create_directories(request.Out, ec);
    file = (fs::path(request.Out) / "segmentation.dcm").string();
  }
  vtkNew<vtkRPSegmentationNode> node;
  if (!ReadSegmentationFile(request.In, node, result.Error)) {
    result.FailureCode = 1;
    return;
  }
  const auto write = dicom::Entry<dicom::WriteSegmentationFunction>(dicom::WriteSegmentationEntry, file, result.Error);
  if (!write || !write(node, request.Reference, file, result.Error, DicomSegmentationWriteOptions{})) {
    result.FailureCode = 1;
    return;
  }
  result.Segments = node->GetNumberOfSegments();
}

}  // namespace

SegmentationConversion ConvertSegmentation(const SegmentationConversionRequest& request) {
  SegmentationConversion result;
  const std::string& in = request.In;
  if (HasExtension(in, ".seg.nrrd") && !HasExtension(request.Out, ".nrrd")) {
    result.Applies = true;
    WriteDicomSeg(request, result);
    return result;
  }
  if (!HasExtension(request.Out, ".seg.nrrd")) {
    // A volume output: a SEG or RTSTRUCT file has no image to give (a folder has its series). Only
    // a file that may be DICOM loads the DICOM library to be told apart; without that library the
    // volume read below names it.
    std::error_code ec;
    std::string unused;
    const auto objectKind = fs::is_regular_file(in, ec) && MaybeDicomFile(in)
                                ? dicom::Entry<dicom::ObjectKindFunction>(dicom::ObjectKindEntry, in, unused)
                                : nullptr;
    const int kind = objectKind ? objectKind(in, nullptr, nullptr) : 0;
    if (kind <= 0) return result;
    result.Applies = true;
    result.FailureCode = 2;
    result.Error = std::string("a DICOM ") + (kind == 1 ? "SEG" : "RTSTRUCT") + " converts to a segmentation file (.seg.nrrd)";
    return result;
  }
  result.Applies = true;
  result.OutputFormat = "segmentation file";
  SegmentationInput input;
  Failure failure;
  if (!ReadInput(request, input, failure)) {
    result.FailureCode = failure.Code;
    result.Error = failure.Message;
    return result;
  }
  result.Warnings = input.Warnings;
  if (!WriteSegmentationFile(request.Out, input.Node, result.Error)) {
    result.FailureCode = 1;
    return result;
  }
  result.Segments = input.Node->GetNumberOfSegments();
  for (const auto& segment : input.Node->GetSegments()) result.SegmentNames.push_back(segment.Name);
  result.InputKind = input.Kind;
  result.InputKindReason = input.Reason;
  return result;
}

}  // namespace rp
