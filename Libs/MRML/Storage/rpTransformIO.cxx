#include "rpTransformIO.h"

#include <cmath>
#include <fstream>

#include <vtkMatrix4x4.h>
#include <vtkNew.h>

#include "rpAtomicFile.h"
#include "rpLPSRAS.h"
#include "rpNodeStorage.h"
#include "rpSiblingLibrary.h"
#include "rpStorageFormats.h"
#include "vtkRPLinearTransformNode.h"

// ITK transform files hold the resampling ("from parent") transform in LPS; the node holds
// "to parent" in RAS: toParentRAS = inverse(S · fromParentLPS · S), S = diag(-1, -1, 1, 1).
namespace rp {
namespace {

// ITK's transform IO lives in a library of its own, loaded on first use (rpItkTransformIO.cxx).
template <typename Function>
Function ItkTransformIO(const char* symbol, std::string& error) {
  std::string loadError;
  const auto function = SiblingLibraryFunction<Function>(reinterpret_cast<const void*>(&ReadTransformFile),
                                                         "libRoboPlanItkTransformIO.so", symbol, loadError);
  if (!function) error = "ITK's transform file IO is not available: " + loadError;
  return function;
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
  using Write = bool (*)(const std::string*, const double*, std::string*);
  const auto write = ItkTransformIO<Write>("roboplan_itk_write_transform", error);
  if (!write) return false;
  auto writeTo = [&](const std::string& target, std::string& err) {
    return write(&target, &fromParentLPS->Element[0][0], &err);
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
  using Read = bool (*)(const std::string*, double*, std::string*);
  const auto read = ItkTransformIO<Read>("roboplan_itk_read_transform", error);
  if (!read) return false;
  vtkNew<vtkMatrix4x4> fromParentLPS, fromParentRAS, result;
  if (!read(&path, &fromParentLPS->Element[0][0], &error)) return false;
  fromParentLPS->Modified();
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
