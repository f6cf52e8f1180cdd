// libRoboPlanVolumeRegistration.so: the ITK side of rp::RegisterVolumesRigid (rpVolumeRegistration.h),
// loaded by its forwarder in RoboPlanImaging (rpVolumeRegistrationLoader.cxx) on the first
// registration. All ITK registration templates live in this file (they compile slowly).
#include <type_traits>

#include "rpVolumeRegistrationEntry.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <itkCenteredTransformInitializer.h>
#include <itkCommand.h>
#include <itkImage.h>
#include <itkImageRegistrationMethodv4.h>
#include <itkMattesMutualInformationImageToImageMetricv4.h>
#include <itkRegistrationParameterScalesFromPhysicalShift.h>
#include <itkRegularStepGradientDescentOptimizerv4.h>
#include <itkVersorRigid3DTransform.h>

#include <vtkDataArray.h>
#include <vtkPointData.h>

#include "rpLPSRAS.h"

namespace rp {
namespace {

using ImageType = itk::Image<float, 3>;
using TransformType = itk::VersorRigid3DTransform<double>;
using OptimizerType = itk::RegularStepGradientDescentOptimizerv4<double>;
using MetricType = itk::MattesMutualInformationImageToImageMetricv4<ImageType, ImageType>;
using RegistrationType = itk::ImageRegistrationMethodv4<ImageType, ImageType, TransformType>;

// RAS volume → ITK image in LPS (voxel order is the same: i fastest).
ImageType::Pointer ToItk(const ImageVolume& volume) {
  int dims[3];
  volume.Image->GetDimensions(dims);
  auto image = ImageType::New();
  ImageType::RegionType region;
  ImageType::SizeType size;
  for (int a = 0; a < 3; ++a) size[a] = static_cast<itk::SizeValueType>(dims[a]);
  region.SetSize(size);
  image->SetRegions(region);
  ImageType::SpacingType spacing;
  ImageType::PointType origin;
  ImageType::DirectionType direction;
  double ijkToLPS[16];
  std::copy(volume.IJKToRAS->GetData(), volume.IJKToRAS->GetData() + 16, ijkToLPS);
  FlipLPSRASIndexToSpace(ijkToLPS);
  for (int c = 0; c < 3; ++c) {
    double len = 0.0;
    for (int r = 0; r < 3; ++r) len += ijkToLPS[4 * r + c] * ijkToLPS[4 * r + c];
    spacing[c] = std::sqrt(len);
    for (int r = 0; r < 3; ++r) direction(r, c) = ijkToLPS[4 * r + c] / spacing[c];
    origin[c] = ijkToLPS[4 * c + 3];
  }
  image->SetSpacing(spacing);
  image->SetOrigin(origin);
  image->SetDirection(direction);
  image->Allocate();
  vtkDataArray* scalars = volume.Image->GetPointData()->GetScalars();
  float* out = image->GetBufferPointer();
  const vtkIdType n = scalars->GetNumberOfTuples();
  for (vtkIdType i = 0; i < n; ++i) out[i] = static_cast<float>(scalars->GetComponent(i, 0));
  return image;
}

// RAS ↔ LPS for a 4x4 point transform (S · M · S).
void FlipRASLPS(const vtkMatrix4x4* in, vtkMatrix4x4* out) {
  out->DeepCopy(in);
  FlipLPSRASTransform(out->GetData());
  out->Modified();
}

class Observer : public itk::Command {
 public:
  using Self = Observer;
  using Superclass = itk::Command;
  using Pointer = itk::SmartPointer<Self>;
  itkNewMacro(Self);
  OptimizerType* Optimizer = nullptr;
  RegistrationType* Registration = nullptr;
  const ProgressCallback* Progress = nullptr;
  const std::atomic<bool>* Cancel = nullptr;
  unsigned Levels = 1, MaxIterations = 1, TotalIterations = 0;
  double InitialStep = 1.0, MinimumStep = 0.01;
  bool Cancelled = false;

  void Execute(itk::Object* caller, const itk::EventObject& event) override {
    this->Execute(static_cast<const itk::Object*>(caller), event);
  }
  void Execute(const itk::Object*, const itk::EventObject& event) override {
    if (!itk::IterationEvent().CheckEvent(&event)) return;
    ++this->TotalIterations;
    if (this->Cancel && this->Cancel->load()) {
      this->Cancelled = true;
      this->Optimizer->StopOptimization();
      return;
    }
    if (this->Progress && *this->Progress) {
      const unsigned level = this->Registration->GetCurrentLevel();
      const double byIterations = double(this->Optimizer->GetCurrentIteration()) / this->MaxIterations;
      const double step = this->Optimizer->GetLearningRate() * this->Optimizer->GetCurrentLearningRateRelaxation();
      const double byStep = std::log(this->InitialStep / std::max(step, 1e-12)) /
                            std::log(this->InitialStep / this->MinimumStep);
      const double within = std::clamp(std::max(byIterations, byStep), 0.0, 1.0);
      (*this->Progress)((level + within) / this->Levels,
                        "level " + std::to_string(level + 1) + "/" + std::to_string(this->Levels) +
                            " MI " + std::to_string(this->Optimizer->GetCurrentMetricValue()) + " step " +
                            std::to_string(step));
    }
  }
};

// At the start of each level: coarse levels stop at a coarser step (their answer only needs to
// be good to a fraction of their voxel), so no time is spent crawling there.
class LevelObserver : public itk::Command {
 public:
  using Self = LevelObserver;
  using Superclass = itk::Command;
  using Pointer = itk::SmartPointer<Self>;
  itkNewMacro(Self);
  OptimizerType* Optimizer = nullptr;
  RegistrationType* Registration = nullptr;
  const RigidRegistrationOptions* Options = nullptr;

  void Execute(itk::Object* caller, const itk::EventObject& event) override {
    this->Execute(static_cast<const itk::Object*>(caller), event);
  }
  void Execute(const itk::Object*, const itk::EventObject& event) override {
    if (!itk::MultiResolutionIterationEvent().CheckEvent(&event)) return;
    const unsigned level = this->Registration->GetCurrentLevel();
    const double shrink = std::max(1u, this->Options->ShrinkFactors[level]);
    this->Optimizer->SetLearningRate(this->Options->InitialStepMM);
    // The last level decides the accuracy: it always runs down to the minimum step.
    const bool last = level + 1 == this->Options->ShrinkFactors.size();
    this->Optimizer->SetMinimumStepLength(this->Options->MinimumStepMM * (last ? 1.0 : shrink * shrink));
  }
};

bool RegisterRigid(const ImageVolume& fixed, const ImageVolume& moving, const RigidRegistrationOptions& options,
                   RigidRegistrationResult& result, std::string& error, const ProgressCallback& progress,
                   const std::atomic<bool>* cancel) {
  const auto start = std::chrono::steady_clock::now();
  if (fixed.Empty() || moving.Empty()) {
    error = "registration: the fixed or the moving volume is empty";
    return false;
  }
  const size_t levels = options.ShrinkFactors.size();
  if (levels == 0 || options.SmoothingSigmasMM.size() != levels) {
    error = "registration: shrink factors and smoothing sigmas must have the same (non-zero) number of levels";
    return false;
  }
  if (!(options.SamplingFraction > 0.0 && options.SamplingFraction <= 1.0) || options.HistogramBins < 5 ||
      options.MaxIterationsPerLevel == 0 || !(options.InitialStepMM > options.MinimumStepMM) ||
      !(options.MinimumStepMM > 0.0)) {
    error = "registration: invalid options (sampling fraction in (0,1], >= 5 bins, iterations > 0, "
            "initial step > minimum step > 0)";
    return false;
  }
  try {
    ImageType::Pointer fixedImage = ToItk(fixed);
    ImageType::Pointer movingImage = ToItk(moving);

    auto transform = TransformType::New();
    if (options.InitializeByGeometryCentres) {
      using Initializer = itk::CenteredTransformInitializer<TransformType, ImageType, ImageType>;
      auto initializer = Initializer::New();
      initializer->SetTransform(transform);
      initializer->SetFixedImage(fixedImage);
      initializer->SetMovingImage(movingImage);
      initializer->GeometryOn();
      initializer->InitializeTransform();
    } else {
      // Rotate about the fixed image's centre: better conditioned than about the origin.
      itk::ContinuousIndex<double, 3> centre;
      const auto size = fixedImage->GetLargestPossibleRegion().GetSize();
      for (int a = 0; a < 3; ++a) centre[a] = (size[a] - 1) * 0.5;
      ImageType::PointType centrePoint;
      fixedImage->TransformContinuousIndexToPhysicalPoint(centre, centrePoint);
      transform->SetCenter(centrePoint);
      vtkNew<vtkMatrix4x4> lps;
      if (options.InitialFixedToMoving) {
        FlipRASLPS(options.InitialFixedToMoving, lps);
      }
      TransformType::MatrixType rotation;
      TransformType::OutputVectorType offset;
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) rotation(r, c) = lps->GetElement(r, c);
        offset[r] = lps->GetElement(r, 3);
      }
      transform->SetMatrix(rotation, 1e-5);
      transform->SetOffset(offset);
    }

    auto metric = MetricType::New();
    metric->SetNumberOfHistogramBins(options.HistogramBins);
    metric->SetUseMovingImageGradientFilter(false);
    metric->SetUseFixedImageGradientFilter(false);

    auto optimizer = OptimizerType::New();
    auto scales = itk::RegistrationParameterScalesFromPhysicalShift<MetricType>::New();
    scales->SetMetric(metric);
    optimizer->SetScalesEstimator(scales);
    optimizer->SetLearningRate(options.InitialStepMM);
    optimizer->SetMinimumStepLength(options.MinimumStepMM);
    optimizer->SetRelaxationFactor(options.RelaxationFactor);
    optimizer->SetNumberOfIterations(options.MaxIterationsPerLevel);
    optimizer->SetGradientMagnitudeTolerance(1e-8);
    optimizer->SetReturnBestParametersAndValue(false);

    auto registration = RegistrationType::New();
    registration->SetFixedImage(fixedImage);
    registration->SetMovingImage(movingImage);
    registration->SetMetric(metric);
    registration->SetOptimizer(optimizer);
    registration->SetInitialTransform(transform);
    registration->InPlaceOn();
    registration->SetNumberOfLevels(static_cast<itk::SizeValueType>(levels));
    RegistrationType::ShrinkFactorsArrayType shrink(levels);
    RegistrationType::SmoothingSigmasArrayType sigmas(levels);
    for (size_t l = 0; l < levels; ++l) {
      shrink[l] = std::max(1u, options.ShrinkFactors[l]);
      sigmas[l] = options.SmoothingSigmasMM[l];
    }
    registration->SetShrinkFactorsPerLevel(shrink);
    registration->SetSmoothingSigmasPerLevel(sigmas);
    registration->SetSmoothingSigmasAreSpecifiedInPhysicalUnits(true);
    registration->SetMetricSamplingStrategy(RegistrationType::MetricSamplingStrategyEnum::RANDOM);
    registration->SetMetricSamplingPercentage(options.SamplingFraction);
    registration->MetricSamplingReinitializeSeed(static_cast<int>(options.RandomSeed));

    auto observer = Observer::New();
    observer->Optimizer = optimizer;
    observer->Registration = registration;
    observer->Progress = &progress;
    observer->Cancel = cancel;
    observer->Levels = static_cast<unsigned>(levels);
    observer->MaxIterations = options.MaxIterationsPerLevel;
    observer->InitialStep = options.InitialStepMM;
    observer->MinimumStep = options.MinimumStepMM;
    optimizer->AddObserver(itk::IterationEvent(), observer);
    auto levelObserver = LevelObserver::New();
    levelObserver->Optimizer = optimizer;
    levelObserver->Registration = registration;
    levelObserver->Options = &options;
    registration->AddObserver(itk::MultiResolutionIterationEvent(), levelObserver);

    registration->Update();
    if (observer->Cancelled) {
      error = "registration cancelled";
      return false;
    }
    const TransformType* finalTransform = registration->GetTransform();
    vtkNew<vtkMatrix4x4> lps;
    const auto m = finalTransform->GetMatrix();
    const auto o = finalTransform->GetOffset();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) lps->SetElement(r, c, m(r, c));
      lps->SetElement(r, 3, o[r]);
    }
    FlipRASLPS(lps, result.FixedToMoving);
    vtkMatrix4x4::Invert(result.FixedToMoving, result.MovingToFixed);
    result.FinalMetric = optimizer->GetCurrentMetricValue();
    result.Iterations = observer->TotalIterations;
    result.StopReason = optimizer->GetStopConditionDescription();
    const auto stop = optimizer->GetStopCondition();
    result.Converged = stop == itk::StopConditionObjectToObjectOptimizerEnum::STEP_TOO_SMALL ||
                       stop == itk::StopConditionObjectToObjectOptimizerEnum::GRADIENT_MAGNITUDE_TOLEARANCE ||
                       stop == itk::StopConditionObjectToObjectOptimizerEnum::CONVERGENCE_CHECKER_PASSED;
    if (!result.Converged && result.StopReason.empty()) result.StopReason = "optimizer stopped without converging";
    result.Seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (progress) progress(1.0, result.Converged ? "converged" : "did not converge");
    return true;
  } catch (const itk::ExceptionObject& e) {
    const std::string what = e.GetDescription();
    error = "registration failed: " + what;
    if (what.find("samples") != std::string::npos)
      error += " (the volumes barely overlap from this start: check the initial transform)";
  } catch (const std::exception& e) {
    error = std::string("registration failed: ") + e.what();
  }
  return false;
}

}  // namespace
}  // namespace rp

RP_REGISTRATION_ENTRY bool roboplan_register_volumes_rigid(const rp::ImageVolume& fixed, const rp::ImageVolume& moving,
                                                           const rp::RigidRegistrationOptions& options,
                                                           rp::RigidRegistrationResult& result, std::string& error,
                                                           const rp::ProgressCallback& progress,
                                                           const std::atomic<bool>* cancel) {
  return rp::RegisterRigid(fixed, moving, options, result, error, progress, cancel);
}

// The entry's type is the C++ function's (a compile error here when one side changes).
static_assert(std::is_same_v<decltype(&roboplan_register_volumes_rigid), rp::registration::RigidFunction>);
