#pragma once
// Internal to RoboPlanDicom: the pixels of a DICOM file, decoded with the library its transfer
// syntax needs (DCMTK, CharLS for JPEG-LS, GDCM for JPEG 2000), turned into modality values
// (Rescale Slope/Intercept, Dose Grid Scaling, a Modality LUT), and a decoded stack narrowed to
// the smallest type that holds its values exactly.
#include <cstddef>
#include <string>
#include <vector>

#include <vtkImageData.h>
#include <vtkSmartPointer.h>

#include "rpDicomHeader.h"

namespace rp::dicom {

// Decoded pixel data of one file: all its frames, stored values, this machine's byte order.
struct DecodedPixels {
  const void* Data = nullptr;
  size_t Bytes = 0;
  int FloatBits = 0;  // 32 or 64: Float / Double Float Pixel Data (7FE0,0008 / 0009)
  std::vector<char> Owned;  // GDCM's output, or big-endian samples reordered (else DCMTK's buffer)
};

/// Decodes the pixel data of one file with the library its transfer syntax needs. `format`
/// must outlive `pixels` (DCMTK's buffer stays inside it).
bool DecodeFile(const SliceHeader& h, DcmFileFormat& format, DecodedPixels& pixels, std::string& error);
/// One frame of decoded pixel data (frame h.Frame) → modality values, into `out` of VTK scalar
/// type `outType` (VTK_DOUBLE, VTK_INT or VTK_FLOAT).
bool ConvertFrame(const DecodedPixels& pixels, const SliceHeader& h, int outType, void* out, std::string& error);
/// A double stack (32/64-bit pixels) → the narrowest type that holds its values exactly:
/// short/ushort/int when they are whole numbers in range (integer pixel data only), double for
/// Double Float Pixel Data, float otherwise.
vtkSmartPointer<vtkImageData> NarrowWide(vtkImageData* stack, int floatBits);
/// An int32 stack narrowed to 16 bits when the values fit (CT in HU, most MR).
vtkSmartPointer<vtkImageData> NarrowInt(vtkImageData* stack);

}  // namespace rp::dicom
