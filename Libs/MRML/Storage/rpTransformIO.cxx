#include "rpTransformIO.h"

#include <cmath>
#include <fstream>
#include <mutex>

#include <itkAffineTransform.h>
#include <itkHDF5TransformIOFactory.h>
#include <itkMatlabTransformIOFactory.h>
#include <itkMatrixOffsetTransformBase.h>
#include <itkTransform.h>
#include <itkTransformFileReader.h>
#include <itkTransformFileWriter.h>
#include <itkTransformFactory.h>
#include <itkTxtTransformIOFactory.h>

#include <vtkMatrix4x4.h>
#include <vtkNew.h>

#include "rpAtomicFile.h"
#include "rpLPSRAS.h"
#include "rpNodeStorage.h"
#include "rpStorageFormats.h"
#include "vtkRPLinearTransformNode.h"

// ITK transform files hold the resampling ("from parent") transform in LPS; the node holds
// "to parent" in RAS: toParentRAS = inverse(S · fromParentLPS · S), S = diag(-1, -1, 1, 1).
namespace rp {
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

bool IsTransformExtension(const std::string& path) {
  return HasExtension(path, ".tfm") || HasExtension(path, ".txt") || HasExtension(path, ".h5") ||
         HasExtension(path, ".hdf5") || HasExtension(path, ".mat");
}

// The same map expressed in the other of LPS/RAS (S · M · S).
void FlipLPSRAS(const vtkMatrix4x4* in, vtkMatrix4x4* out) {
  out->DeepCopy(in);
  FlipLPSRASTransform(out->GetData());
  out->Modified();
}

bool IsFiniteAffine(const vtkMatrix4x4* m) {
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (!std::isfinite(m->GetElement(i, j))) return false;
  return m->GetElement(3, 0) == 0 && m->GetElement(3, 1) == 0 && m->GetElement(3, 2) == 0 &&
         m->GetElement(3, 3) == 1;
}

// The 4x4 matrix of any linear ITK transform (Euler, Versor, Similarity, Affine, Translation,
// Scale, a composite of linear ones...) from the images of the origin and the unit vectors, so
// fixed parameters (centres) and composition order are ITK's own.
void MatrixOfLinearTransform(const Transform3* transform, vtkMatrix4x4* out) {
  Transform3::InputPointType origin;
  origin.Fill(0.0);
  const auto t = transform->TransformPoint(origin);
  out->Identity();
  for (int j = 0; j < 3; ++j) {
    Transform3::InputPointType unit = origin;
    unit[j] = 1.0;
    const auto image = transform->TransformPoint(unit);
    for (int i = 0; i < 3; ++i) out->SetElement(i, j, image[i] - t[i]);
  }
  for (int i = 0; i < 3; ++i) out->SetElement(i, 3, t[i]);
}

}  // namespace

bool WriteTransformFile(const std::string& path, const vtkMatrix4x4* toParentRAS, std::string& error) {
  if (!toParentRAS || !IsFiniteAffine(toParentRAS)) {
    error = "cannot write '" + path + "': the transform is not a finite affine 4x4 matrix";
    return false;
  }
  if (!IsTransformExtension(path)) {
    error = "cannot write '" + path + "': unknown transform extension (use .tfm, .txt or .h5)";
    return false;
  }
  vtkNew<vtkMatrix4x4> toParent, fromParentRAS, fromParentLPS;
  toParent->DeepCopy(toParentRAS);
  if (std::abs(toParent->Determinant()) < 1e-12) {
    error = "cannot write '" + path + "': the transform is singular (it has no inverse)";
    return false;
  }
  vtkMatrix4x4::Invert(toParent, fromParentRAS);
  FlipLPSRAS(fromParentRAS, fromParentLPS);
  RegisterTransformIOFactories();
  using Affine = itk::AffineTransform<double, 3>;
  auto affine = Affine::New();
  Affine::MatrixType matrix;
  Affine::OutputVectorType translation;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) matrix(i, j) = fromParentLPS->GetElement(i, j);
    translation[i] = fromParentLPS->GetElement(i, 3);
  }
  affine->SetMatrix(matrix);
  affine->SetTranslation(translation);
  auto writeTo = [&](const std::string& target, std::string& err) -> bool {
    auto writer = itk::TransformFileWriterTemplate<double>::New();
    writer->SetFileName(target);
    writer->SetInput(affine);
    try {
      writer->Update();
    } catch (const itk::ExceptionObject& e) {
      err = std::string("ITK transform writer failed: ") + e.GetDescription();
      return false;
    }
    return true;
  };
  return WriteAtomicallyWith(path, writeTo, error);
}

bool ReadTransformFile(const std::string& path, vtkMatrix4x4* toParentRAS, std::string& error) {
  if (!toParentRAS) {
    error = "no matrix to read '" + path + "' into";
    return false;
  }
  if (!std::ifstream(path).good()) {
    error = "cannot open transform file '" + path + "'";
    return false;
  }
  RegisterTransformIOFactories();
  auto reader = itk::TransformFileReaderTemplate<double>::New();
  reader->SetFileName(path);
  try {
    reader->Update();
  } catch (const itk::ExceptionObject& e) {
    error = "'" + path + "' is not a readable ITK transform file: " + e.GetDescription();
    return false;
  }
  const auto* list = reader->GetTransformList();
  if (!list || list->empty()) {
    error = "'" + path + "' holds no transform";
    return false;
  }
  if (list->size() > 1) {
    error = "'" + path + "' holds " + std::to_string(list->size()) +
            " transforms; RoboPlan reads files with one (linear or composite) transform";
    return false;
  }
  const auto* transform = dynamic_cast<const Transform3*>(list->front().GetPointer());
  if (!transform) {
    error = "'" + path + "' holds a " + list->front()->GetNameOfClass() + ", not a 3D transform";
    return false;
  }
  if (transform->GetTransformCategory() != Transform3::TransformCategoryEnum::Linear) {
    error = "'" + path + "' holds a " + transform->GetNameOfClass() +
            ", which is not linear (RoboPlan reads linear transforms only)";
    return false;
  }
  vtkNew<vtkMatrix4x4> fromParentLPS, fromParentRAS, result;
  MatrixOfLinearTransform(transform, fromParentLPS);
  FlipLPSRAS(fromParentLPS, fromParentRAS);
  if (std::abs(fromParentRAS->Determinant()) < 1e-12) {
    error = "'" + path + "' holds a singular transform (it has no inverse)";
    return false;
  }
  vtkMatrix4x4::Invert(fromParentRAS, result);
  if (!IsFiniteAffine(result)) {
    error = "'" + path + "' holds a transform with non-finite values";
    return false;
  }
  toParentRAS->DeepCopy(result);
  return true;
}

namespace {
class LinearTransformStorage : public NodeStorage {
 public:
  std::string Description() const override { return "linear transform (ITK .tfm/.txt/.h5)"; }
  bool CanHandle(const vtkRPNode* node) const override {
    return node && const_cast<vtkRPNode*>(node)->IsA("vtkRPLinearTransformNode");
  }
  std::vector<std::string> Extensions() const override { return {".tfm", ".txt", ".h5"}; }
  std::string DefaultExtension() const override { return ".tfm"; }
  std::string NodeClassForFiles() const override { return "vtkRPLinearTransformNode"; }
  bool Write(vtkRPNode* node, const std::string& path, std::string& error) const override {
    auto* transform = vtkRPLinearTransformNode::SafeDownCast(node);
    if (!transform) {
      error = "not a linear transform node";
      return false;
    }
    return WriteTransformFile(path, transform->GetMatrixTransformToParent(), error);
  }
  bool Read(vtkRPNode* node, const std::string& path, std::string& error) const override {
    auto* transform = vtkRPLinearTransformNode::SafeDownCast(node);
    if (!transform) {
      error = "not a linear transform node";
      return false;
    }
    vtkNew<vtkMatrix4x4> matrix;
    if (!ReadTransformFile(path, matrix, error)) return false;
    transform->SetMatrixTransformToParent(matrix);
    return true;
  }
};
}  // namespace

std::shared_ptr<NodeStorage> MakeLinearTransformStorage() { return std::make_shared<LinearTransformStorage>(); }

}  // namespace rp
