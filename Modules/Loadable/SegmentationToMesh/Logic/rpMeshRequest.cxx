#include "rpMeshRequest.h"

#include <stdexcept>

#include "rpNodeStorage.h"

namespace rp {
namespace {

// Volumes and segmentations: what `mesh` reads (from the storages' registrations).
std::vector<std::string> InputExtensions() {
  auto extensions = ExtensionsForNodeClass("vtkRPSegmentationNode");
  for (const auto& ext : ExtensionsForNodeClass("vtkRPScalarVolumeNode")) extensions.push_back(ext);
  return extensions;
}

// Model file formats, from the model storage's registration (rpModelIO): "vtp", "vtk", ...
std::string ModelFormats() {
  std::string formats;
  for (const auto& extension : ExtensionsForNodeClass("vtkRPModelNode"))
    formats += (formats.empty() ? "" : "|") + extension.substr(1);
  return formats;
}

}  // namespace

void DeclareMeshOptions(ArgParser& parser) {
  parser.Positional("input", "volume or labelmap (.nrrd, .nii.gz, .mha, DICOM folder or DICOMDIR) or segmentation (.seg.nrrd, DICOM SEG or RTSTRUCT file or folder)")
      .Input(FileKind::Image, InputExtensions())
      .Option("series", "id",
              "DICOM input: the series to mesh when there are several: its SeriesInstanceUID, or "
              "<SeriesInstanceUID>#<n> for one stack of a series that holds several (see `roboplan dicom`)")
      .Flag("resample-irregular",
            "DICOM input: load a series with a missing slice or uneven spacing by resampling it onto a "
            "regular grid along the slice normal (refused otherwise)")
      .Option("out", "dir", "output folder (created)")
      .OutputFolder()
      .Required()
      .Option("input-kind", "auto|labelmap|intensity",
              "a volume file is a labelmap (one segment per label value) or an intensity image to segment; auto: "
              "a labelmap when no threshold option is given, the voxels are few whole numbers >= 0 and --labels is "
              "given or the file is named *-label.*, *_label.*, *labelmap*, *.seg.*",
              "auto")
      .OneOf()
      .Option("labels", "file", "label names and colours: Slicer colour table (.ctbl/.txt) or ITK-SNAP label file")
      .Input(FileKind::Any)
      .Option("method", "threshold|region-grow|confidence", "segmentation method for volumes", "threshold")
      .OneOf()
      .Option("preset", "bone|cortical|soft-tissue|fat", "tissue preset(s), repeatable (several tissues)", "bone")
      .OneOf()
      .Repeatable()
      .Option("lower", "HU", "lower threshold (overrides the preset; one tissue)")
      .Number()
      .Option("upper", "HU", "upper threshold (overrides the preset; one tissue)")
      .Number()
      .Option("seed", "x,y,z", "seed point in RAS mm (repeatable): region growing, confidence, --keep-at-seed")
      .Point()
      .Repeatable()
      .Option("multiplier", "k", "confidence connected: mean ± k·sigma", "2.5")
      .Number()
      .GreaterThan(0)
      .Option("iterations", "n", "confidence connected iterations", "3")
      .Integer()
      .AtLeast(0)
      .Option("radius", "voxels", "confidence connected initial neighbourhood radius", "2")
      .Integer()
      .AtLeast(0)
      .Option("closing", "mm", "morphological closing radius")
      .Number()
      .AtLeast(0)
      .Option("opening", "mm", "morphological opening radius")
      .Number()
      .AtLeast(0)
      .Flag("fill-holes", "fill enclosed holes")
      .Flag("keep-largest", "keep the largest connected component")
      .Flag("keep-at-seed", "keep the component at the first seed")
      .Flag("split-bones", "bones one by one from a CT: one segment per bone, touching bones split, table and "
                           "specks dropped, knee bones named (femur, tibia, fibula, patella), others \"Bone N\"")
      .Option("bone-seed", "R,A,S[:name]", "a point on a bone (RAS mm) naming it, or forcing a split (repeatable)")
      .Repeatable()
      .Option("min-bone-ml", "ml", "--split-bones: drop pieces smaller than this", "0.3")
      .Number()
      .AtLeast(0)
      .Option("truth", "labelmap", "score each segment against this labelmap (Dice, surface distance)")
      .Input(FileKind::LabelMap)
      .Option("split", "n", "split into up to n segments, one per component")
      .Integer()
      .AtLeast(1)
      .Option("max-fraction", "f", "refuse a segment covering more than this fraction of the volume (leak)", "0.9")
      .Number()
      .GreaterThan(0)
      .AtMost(1)
      .Option("segment", "id", "mesh only these segments (repeatable)")
      .Repeatable()
      .Option("mesh-method", "gaussian|sinc|slicer|discrete", "surface method", "gaussian")
      .OneOf()
      .Option("smoothing", "sigma", "gaussian smoothing sigma in voxels", "1.0")
      .Number()
      .AtLeast(0)
      .Option("passband", "f", "windowed sinc pass band (sinc, slicer)", "0.01")
      .Number()
      .GreaterThan(0)
      .AtMost(2)
      .Option("sinc-iterations", "n", "windowed sinc iterations (sinc, slicer)", "20")
      .Integer()
      .AtLeast(0)
      .Option("grid-step", "s|sx,sy,sz", "gaussian contour grid step in voxels (>1 = coarser mesh)", "1")
      .Numbers()
      .GreaterThan(0)
      .Option("grid-mm", "mm", "gaussian contour grid spacing in mm (step per axis = max(1, mm / spacing))")
      .Number()
      .GreaterThan(0)
      .Option("decimate", "f", "extra quadric decimation: fraction of triangles removed", "0")
      .Number()
      .AtLeast(0)
      .LessThan(1)
      .Option("triangles", "n", "display mesh: target triangle count")
      .Integer()
      .AtLeast(1)
      .Option("max-error", "mm", "display mesh: max deviation from the full-resolution surface")
      .Number()
      .AtLeast(0)
      .Option("haptic-triangles", "n", "haptic mesh: target triangle count", "20000")
      .Integer()
      .AtLeast(1)
      .Option("haptic-max-error", "mm", "haptic mesh: max deviation from the full-resolution surface")
      .Number()
      .AtLeast(0)
      .Flag("no-haptic", "do not write haptic meshes")
      .Flag("no-volume-correction", "keep the raw surface (no volume correction)")
      .Option("format", ModelFormats(), "model file format", "vtp")
      .OneOf();
}

bool ParseMeshRequest(const ArgParser& parser, MeshRequest& request, std::ostream& err) {
  try {
    request.Input = parser.Get("input");
    request.OutDir = parser.Get("out");
    request.Json = parser.Json();
    request.Read.Series = parser.Get("series");
    request.Read.ResampleIrregularSpacing = parser.Has("resample-irregular");
    ParseInputKind(parser.Get("input-kind"), request.Kind);
    request.IntensityOptions = parser.Has("lower") || parser.Has("upper") || !parser.GetAll("preset").empty() ||
                               parser.Has("method") || parser.Has("multiplier") || parser.Has("iterations") ||
                               parser.Has("radius");
    if (parser.Has("labels")) request.Labels = parser.Get("labels");
    if (parser.Has("truth")) request.Truth = parser.Get("truth");
    request.Format = parser.Get("format");

    // Bones one by one.
    request.SplitBones = parser.Has("split-bones");
    if (parser.Has("lower")) request.Bones.LowerHU = parser.GetDouble("lower");
    if (parser.Has("upper")) request.Bones.UpperHU = parser.GetDouble("upper");
    request.Bones.MinBoneMl = parser.GetDouble("min-bone-ml");
    request.BoneSeeds = parser.GetAll("bone-seed");

    // Tissues: presets or one range, the method, the edits in the order they run.
    request.Presets = parser.GetAll("preset");
    if (request.Presets.empty()) request.Presets = {parser.Get("preset")};
    if (parser.Has("lower")) request.Lower = parser.GetDouble("lower");
    if (parser.Has("upper")) request.Upper = parser.GetDouble("upper");
    SegmentMethod& method = request.Method;
    ParseSegmentMethod(parser.Get("method"), method.Method);
    method.Seeds = parser.GetPoints("seed");
    method.Multiplier = parser.GetDouble("multiplier");
    method.Iterations = static_cast<int>(parser.GetInt("iterations"));
    method.Radius = static_cast<int>(parser.GetInt("radius"));
    request.MaxFraction = parser.GetDouble("max-fraction");
    if (parser.Has("closing"))
      request.Edits.push_back({SegmentEdit::Closing, parser.GetDouble("closing"), {}, 1});
    if (parser.Has("opening"))
      request.Edits.push_back({SegmentEdit::Opening, parser.GetDouble("opening"), {}, 1});
    if (parser.Has("fill-holes")) request.Edits.push_back({SegmentEdit::FillHoles, 0, {}, 1});
    if (parser.Has("keep-largest")) request.Edits.push_back({SegmentEdit::KeepLargest, 0, {}, 1});
    if (parser.Has("keep-at-seed") && !method.Seeds.empty())
      request.Edits.push_back({SegmentEdit::KeepAtSeed, 0, method.Seeds.front(), 1});
    if (parser.Has("split"))
      request.Edits.push_back({SegmentEdit::Split, 0, {}, static_cast<int>(parser.GetInt("split"))});

    // The surfaces: display, and haptic with the display's options at full resolution.
    ModelBuildOptions& build = request.Build;
    ParseMeshMethod(parser.Get("mesh-method"), build.Display.Method);
    build.Display.Sigma = parser.GetDouble("smoothing");
    build.Display.SincPassBand = parser.GetDouble("passband");
    build.Display.SincIterations = static_cast<int>(parser.GetInt("sinc-iterations"));
    const auto steps = parser.GetDoubles("grid-step");
    if (steps.size() != 1 && steps.size() != 3) throw std::invalid_argument("--grid-step: one value or three (sx,sy,sz)");
    for (size_t a = 0; a < 3; ++a) build.Display.GridStep[a] = steps[steps.size() == 1 ? 0 : a];
    if (parser.Has("grid-mm")) request.GridMm = parser.GetDouble("grid-mm");
    build.Display.DecimationFraction = parser.GetDouble("decimate");
    build.Display.CorrectVolume = !parser.Has("no-volume-correction");
    if (parser.Has("triangles")) build.DisplayLOD.TargetTriangles = parser.GetInt("triangles");
    if (parser.Has("max-error")) build.DisplayLOD.MaxErrorMm = parser.GetDouble("max-error");
    build.Haptic = build.Display;
    build.Haptic.DecimationFraction = 0;
    build.HapticLOD.TargetTriangles = parser.GetInt("haptic-triangles");
    build.HapticLOD.MaxErrorMm = parser.Has("haptic-max-error") ? parser.GetDouble("haptic-max-error") : 0.0;
    build.MakeHaptic = !parser.Has("no-haptic");
    build.SegmentIDs = parser.GetAll("segment");
    if (parser.Has("keep-at-seed") && method.Seeds.empty()) throw std::invalid_argument("--keep-at-seed needs --seed");
    if (method.Method != SegmentMethod::Threshold && method.Seeds.empty())
      throw std::invalid_argument("--method " + method.Name() + " needs at least one --seed x,y,z");
  } catch (const std::exception& e) {
    err << "roboplan mesh: " << e.what() << "\n";
    return false;
  }
  return true;
}

}  // namespace rp
