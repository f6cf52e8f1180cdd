#pragma once
// The one LPS <-> RAS conversion, used at every file boundary.
//
// DICOM, ITK images and transforms, NRRD/NIfTI/MetaImage headers and Slicer's model and
// markup files are LPS (x to the patient's Left, y Posterior, z Superior); the scene is RAS
// (x Right, y Anterior, z Superior), as in 3D Slicer. The two frames differ by
// S = diag(-1, -1, 1): x and y change sign, z is kept. S is its own inverse, so every function
// here converts both ways.
//
// Matrices are 4x4, row-major, 16 doubles (vtkMatrix4x4::GetData() and Eigen's RowMajor have
// this layout; call Modified() on a vtkMatrix4x4 edited through GetData()).
namespace rp {

/// The sign S applies to each axis: {-1, -1, +1}.
inline constexpr double kLPSRASSign[3] = {-1.0, -1.0, 1.0};

/// A point or a direction: p' = S p (in place).
void FlipLPSRASPoint(double p[3]);

/// A grid's index-to-space matrix (IJK-to-LPS <-> IJK-to-RAS): M' = S M, i.e. the first two
/// rows negate (directions and origin change frame; the index side does not).
void FlipLPSRASIndexToSpace(double m[16]);

/// A transform between two spaces of the same kind (LPS-to-LPS <-> RAS-to-RAS): M' = S M S.
void FlipLPSRASTransform(double m[16]);

/// S itself as a 4x4 matrix (e.g. for vtkTransform::SetMatrix to flip a mesh's points).
void LPSRASMatrix(double m[16]);

}  // namespace rp
