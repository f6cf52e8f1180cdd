// ITK's transform file IO (.tfm/.txt text, .h5 HDF5, .mat) as a library of its own
// (libRoboPlanItkTransformIO.so beside libRoboPlanMRMLStorage.so), loaded on the first transform
// file read or written (rpTransformIO.cxx): ITK's HDF5 IO brings HDF5, curl and a TLS stack, about
// 30 libraries every program linking the storage would otherwise map and relocate at start-up.
// Matrices cross as 16 doubles, row-major, the file's own "from parent" LPS transform.
#include <mutex>
#include <string>

#include <itkAffineTransform.h>
#include <itkHDF5TransformIOFactory.h>
#include <itkMatlabTransformIOFactory.h>
#include <itkMatrixOffsetTransformBase.h>
#include <itkTransform.h>
#include <itkTransformFileReader.h>
#include <itkTransformFileWriter.h>
#include <itkTransformFactory.h>
#include <itkTxtTransformIOFactory.h>

namespace {

using Transform3 = itk::Transform<double, 3, 3>;

// The transform IO factories are registered explicitly: our targets do not use ITK's
// generated factory register managers. MatrixOffsetTransformBase is not in ITK's default
// transform factory, but Slicer reads it, so we do too.
void RegisterTransformIOFactories() {
  static std::once_flag once;
  std::call_once(once, [] {
    itk::TxtTransformIOFactory::RegisterOneFactory();
    itk::HDF5TransformIOFactory::RegisterOneFactory();
    itk::MatlabTransformIOFactory::RegisterOneFactory();
    itk::TransformFactory<itk::MatrixOffsetTransformBase<double, 3, 3>>::RegisterTransform();
    itk::TransformFactory<itk::MatrixOffsetTransformBase<float, 3, 3>>::RegisterTransform();
  });
}

// The 4x4 matrix of any linear ITK transform (Euler, Versor, Similarity, Affine, Translation,
// Scale, a composite of linear ones...) from the images of the origin and the unit vectors, so
// fixed parameters (centres) and composition order are ITK's own.
void MatrixOfLinearTransform(const Transform3* transform, double out[16]) {
  Transform3::InputPointType origin;
  origin.Fill(0.0);
  const auto t = transform->TransformPoint(origin);
  for (int k = 0; k < 16; ++k) out[k] = k % 5 == 0 ? 1.0 : 0.0;
  for (int j = 0; j < 3; ++j) {
    Transform3::InputPointType unit = origin;
    unit[j] = 1.0;
    const auto image = transform->TransformPoint(unit);
    for (int i = 0; i < 3; ++i) out[4 * i + j] = image[i] - t[i];
  }
  for (int i = 0; i < 3; ++i) out[4 * i + 3] = t[i];
}

}  // namespace

/// Writes one affine transform (`fromParentLPS`, 16 doubles row-major) to `path` (its extension
/// chooses the format). False with `error`.
extern "C" __attribute__((visibility("default"))) bool roboplan_itk_write_transform(const std::string* path,
                                                                                    const double* fromParentLPS,
                                                                                    std::string* error) {
  RegisterTransformIOFactories();
  using Affine = itk::AffineTransform<double, 3>;
  auto affine = Affine::New();
  Affine::MatrixType matrix;
  Affine::OutputVectorType translation;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) matrix(i, j) = fromParentLPS[4 * i + j];
    translation[i] = fromParentLPS[4 * i + 3];
  }
  affine->SetMatrix(matrix);
  affine->SetTranslation(translation);
  auto writer = itk::TransformFileWriterTemplate<double>::New();
  writer->SetFileName(*path);
  writer->SetInput(affine);
  try {
    writer->Update();
  } catch (const itk::ExceptionObject& e) {
    *error = std::string("ITK transform writer failed: ") + e.GetDescription();
    return false;
  }
  return true;
}

/// Reads the one linear transform of `path` into `fromParentLPS` (16 doubles row-major). False
/// with `error` naming the problem (unreadable, several transforms, not 3D, not linear).
extern "C" __attribute__((visibility("default"))) bool roboplan_itk_read_transform(const std::string* path,
                                                                                   double* fromParentLPS,
                                                                                   std::string* error) {
  RegisterTransformIOFactories();
  auto reader = itk::TransformFileReaderTemplate<double>::New();
  reader->SetFileName(*path);
  try {
    reader->Update();
  } catch (const itk::ExceptionObject& e) {
    *error = "'" + *path + "' is not a readable ITK transform file: " + e.GetDescription();
    return false;
  }
  const auto* list = reader->GetTransformList();
  if (!list || list->empty()) {
    *error = "'" + *path + "' holds no transform";
    return false;
  }
  if (list->size() > 1) {
    *error = "'" + *path + "' holds " + std::to_string(list->size()) +
             " transforms; RoboPlan reads files with one (linear or composite) transform";
    return false;
  }
  const auto* transform = dynamic_cast<const Transform3*>(list->front().GetPointer());
  if (!transform) {
    *error = "'" + *path + "' holds a " + list->front()->GetNameOfClass() + ", not a 3D transform";
    return false;
  }
  if (transform->GetTransformCategory() != Transform3::TransformCategoryEnum::Linear) {
    *error = "'" + *path + "' holds a " + transform->GetNameOfClass() +
             ", which is not linear (RoboPlan reads linear transforms only)";
    return false;
  }
  MatrixOfLinearTransform(transform, fromParentLPS);
  return true;
}
