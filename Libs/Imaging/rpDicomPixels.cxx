#include "rpDicomPixels.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dctk.h>

#include "rpDicomGdcmDecoder.h"
#include "rpDicomJpegLsDecoder.h"
#include "rpDicomTransferSyntax.h"

namespace rp::dicom {

namespace {

// Stored pixels → modality values (slope/intercept applied) into `out`, in tight loops.
// Integral series (integer slope and intercept) decode into int32, others into float.
template <typename Raw, typename Out>
void ConvertPixels(const Raw* in, size_t count, int bitsStored, bool isSigned, double slope, double intercept,
                   Out* out) {
  const bool masked = bitsStored < static_cast<int>(8 * sizeof(Raw));
  using U = std::make_unsigned_t<Raw>;
  const uint32_t mask = masked ? ((1u << bitsStored) - 1u) : 0xffffffffu;
  const uint32_t signBit = masked ? (1u << (bitsStored - 1)) : 0u;
  const bool identity = slope == 1.0 && intercept == 0.0;
  for (size_t i = 0; i < count; ++i) {
    int64_t v;
    if (masked) {
      const uint32_t u = static_cast<uint32_t>(static_cast<U>(in[i])) & mask;
      v = (isSigned && (u & signBit)) ? static_cast<int64_t>(u) - (int64_t(1) << bitsStored) : static_cast<int64_t>(u);
    } else {
      v = static_cast<int64_t>(in[i]);
    }
    if constexpr (std::is_integral_v<Out>) {
      out[i] = static_cast<Out>(identity ? v : v * static_cast<int64_t>(slope) + static_cast<int64_t>(intercept));
    } else {
      out[i] = static_cast<Out>(identity ? double(v) : double(v) * slope + intercept);
    }
  }
}

// Stored values → Modality LUT output values, in place.
template <typename Out>
void ApplyModalityLut(const SliceHeader& h, Out* values, size_t count) {
  const int64_t last = static_cast<int64_t>(h.LutData.size()) - 1;
  for (size_t i = 0; i < count; ++i) {
    const int64_t index = std::clamp(static_cast<int64_t>(values[i]) - h.LutFirst, int64_t(0), last);
    values[i] = static_cast<Out>(h.LutData[static_cast<size_t>(index)]);
  }
}

// One frame of integer pixel data → modality values.
template <typename Out>
void ConvertIntegerFrame(const char* base, size_t count, const SliceHeader& h, Out* out) {
  const bool isSigned = h.PixelRepresentation == 1;
  const int bitsStored = std::clamp(h.BitsStored, 1, h.BitsAllocated);
  if (h.BitsAllocated == 16) {
    if (isSigned)
      ConvertPixels(reinterpret_cast<const int16_t*>(base), count, bitsStored, true, h.Slope, h.Intercept, out);
    else
      ConvertPixels(reinterpret_cast<const uint16_t*>(base), count, bitsStored, false, h.Slope, h.Intercept, out);
  } else if (h.BitsAllocated == 8) {
    if (isSigned)
      ConvertPixels(reinterpret_cast<const int8_t*>(base), count, bitsStored, true, h.Slope, h.Intercept, out);
    else
      ConvertPixels(reinterpret_cast<const uint8_t*>(base), count, bitsStored, false, h.Slope, h.Intercept, out);
  } else {
    if (isSigned)
      ConvertPixels(reinterpret_cast<const int32_t*>(base), count, 32, true, h.Slope, h.Intercept, out);
    else
      ConvertPixels(reinterpret_cast<const uint32_t*>(base), count, 32, false, h.Slope, h.Intercept, out);
  }
  if (!h.LutData.empty()) ApplyModalityLut(h, out, count);
}

// One frame of decoded pixel data → modality values.
template <typename Out>
bool ConvertFrameAs(const DecodedPixels& pixels, const SliceHeader& h, Out* out, std::string& error) {
  const size_t count = static_cast<size_t>(h.Rows) * h.Columns;
  const int bits = pixels.FloatBits ? pixels.FloatBits : h.BitsAllocated;
  const size_t bytesPerPixel = static_cast<size_t>(bits / 8);
  const size_t offset = static_cast<size_t>(h.Frame) * count * bytesPerPixel;
  if (!pixels.FloatBits && h.BitsAllocated != 8 && h.BitsAllocated != 16 && h.BitsAllocated != 32) {
    error = std::to_string(h.BitsAllocated) + " bits allocated is not supported";
    return false;
  }
  if (!pixels.Data || pixels.Bytes < offset + count * bytesPerPixel) {
    error = "pixel data shorter than " + std::to_string(h.Frame + 1) + " frame(s) of " + std::to_string(h.Columns) +
            "x" + std::to_string(h.Rows) + " " + std::to_string(bits) + "-bit pixels (truncated file)";
    return false;
  }
  const char* base = static_cast<const char*>(pixels.Data) + offset;
  if (pixels.FloatBits == 32) {
    const float* in = reinterpret_cast<const float*>(base);
    std::transform(in, in + count, out, [](float v) { return static_cast<Out>(v); });
  } else if (pixels.FloatBits == 64) {
    const double* in = reinterpret_cast<const double*>(base);
    std::transform(in, in + count, out, [](double v) { return static_cast<Out>(v); });
  } else {
    ConvertIntegerFrame(base, count, h, out);
  }
  return true;
}

// Big Endian pixel data into this machine's (little-endian) order, sample by sample. The
// transfer syntax stores each sample most significant byte first (PS3.5 7.3: a binary number;
// pydicom reads it so), but DCMTK swaps an OW value 16 bits at a time, the width of its VR, which
// leaves the halves of a 32-bit sample swapped, and leaves OB as the file's bytes. GDCM and
// DCMTK's own Big Endian writer (dcmconv +tb) do the same, so such files they wrote read here
// with their halves swapped: per sample is what the standard says a big-endian number is.
void SamplesInMachineOrder(bool swappedPerWord, int bitsAllocated, DecodedPixels& pixels) {
  const size_t bytes = static_cast<size_t>(bitsAllocated / 8);
  if (!pixels.Data || bytes < 2 || (swappedPerWord && bytes == 2)) return;  // 16-bit OW is right
  const char* in = static_cast<const char*>(pixels.Data);
  pixels.Owned.assign(in, in + pixels.Bytes);
  for (size_t at = 0; at + bytes <= pixels.Bytes; at += bytes) {
    char* sample = pixels.Owned.data() + at;
    if (swappedPerWord) {  // the sample's 16-bit words in reverse order, each already swapped
      for (size_t w = 0; w < bytes / 4; ++w)
        for (size_t b = 0; b < 2; ++b) std::swap(sample[2 * w + b], sample[bytes - 2 * (w + 1) + b]);
    } else {
      std::reverse(sample, sample + bytes);
    }
  }
  pixels.Data = pixels.Owned.data();
}

template <typename In, typename Out>
void Narrow(const In* in, Out* out, size_t count) {
  for (size_t i = 0; i < count; ++i) out[i] = static_cast<Out>(in[i]);
}

}  // namespace

bool DecodeFile(const SliceHeader& h, DcmFileFormat& format, DecodedPixels& pixels, std::string& error) {
  const TransferSyntaxInfo* syntax = FindTransferSyntax(h.TransferSyntax);
  if (syntax && syntax->Decoder == PixelDecoder::GDCM) {
    if (!DecodePixelsWithGdcm(h.File, pixels.Owned, error)) {
      error = TransferSyntaxLabel(h.TransferSyntax) + ": " + error;
      return false;
    }
    pixels.Data = pixels.Owned.data();
    pixels.Bytes = pixels.Owned.size();
    return true;
  }
  SliceHeader full;
  std::string reason;
  if (LoadFile(h.File, format, full, reason, false) != FileKind::Image) {
    error = reason.empty() ? "cannot be read" : reason;
    return false;
  }
  DcmDataset* ds = format.getDataset();
  if (syntax && syntax->Decoder == PixelDecoder::CharLS) {
    const size_t frameBytes = static_cast<size_t>(h.Rows) * h.Columns * static_cast<size_t>(h.BitsAllocated / 8);
    if (!DecodeJpegLsPixels(ds, h.Frames, frameBytes, pixels.Owned, error)) {
      error = TransferSyntaxLabel(h.TransferSyntax) + ": " + error;
      return false;
    }
    pixels.Data = pixels.Owned.data();
    pixels.Bytes = pixels.Owned.size();
    return true;
  }
  if (DcmXfer(ds->getOriginalXfer()).isEncapsulated()) {
    OFCondition c = ds->chooseRepresentation(EXS_LittleEndianExplicit, nullptr);
    if (c.bad() || !ds->canWriteXfer(EXS_LittleEndianExplicit)) {
      error = "cannot decompress pixel data (" + TransferSyntaxLabel(h.TransferSyntax) + ", " + c.text() + ")";
      return false;
    }
  }
  DcmElement* element = nullptr;
  if (ds->findAndGetElement(DCM_FloatPixelData, element).good() && element) {
    Float32* data = nullptr;
    pixels.FloatBits = 32;
    pixels.Bytes = element->getFloat32Array(data).good() && data ? element->getLength() : 0;
    pixels.Data = data;
    return true;
  }
  if (ds->findAndGetElement(DCM_DoubleFloatPixelData, element).good() && element) {
    Float64* data = nullptr;
    pixels.FloatBits = 64;
    pixels.Bytes = element->getFloat64Array(data).good() && data ? element->getLength() : 0;
    pixels.Data = data;
    return true;
  }
  if (ds->findAndGetElement(DCM_PixelData, element).bad() || !element) {
    error = "no pixel data";
    return false;
  }
  // OB as bytes, OW as 16-bit words in this machine's byte order.
  OFCondition status;
  const bool words = element->getVR() != EVR_OB && h.BitsAllocated != 8;
  if (!words) {
    Uint8* data = nullptr;
    status = element->getUint8Array(data);
    pixels.Data = data;
  } else {
    Uint16* data = nullptr;
    status = element->getUint16Array(data);
    pixels.Data = data;
  }
  pixels.Bytes = status.good() && pixels.Data ? element->getLength() : 0;
  if (DcmXfer(ds->getOriginalXfer()).getByteOrder() == EBO_BigEndian && gLocalByteOrder == EBO_LittleEndian)
    SamplesInMachineOrder(words, h.BitsAllocated, pixels);
  return true;
}

bool ConvertFrame(const DecodedPixels& pixels, const SliceHeader& h, int outType, void* out, std::string& error) {
  switch (outType) {
    case VTK_DOUBLE: return ConvertFrameAs(pixels, h, static_cast<double*>(out), error);
    case VTK_INT: return ConvertFrameAs(pixels, h, static_cast<int*>(out), error);
    case VTK_FLOAT: return ConvertFrameAs(pixels, h, static_cast<float*>(out), error);
    default: error = "internal: no conversion to VTK type " + std::to_string(outType); return false;
  }
}

vtkSmartPointer<vtkImageData> NarrowWide(vtkImageData* stack, int floatBits) {
  const double* values = static_cast<const double*>(stack->GetScalarPointer());
  const size_t total = static_cast<size_t>(stack->GetNumberOfPoints());
  bool whole = floatBits == 0;
  double lo = 0.0, hi = 0.0;
  for (size_t i = 0; i < total && whole; ++i) {
    whole = values[i] == std::floor(values[i]);
    lo = i == 0 ? values[i] : std::min(lo, values[i]);
    hi = i == 0 ? values[i] : std::max(hi, values[i]);
  }
  int type = floatBits == 64 ? VTK_DOUBLE : VTK_FLOAT;
  if (whole)
    type = (lo >= -32768 && hi <= 32767)   ? VTK_SHORT
           : (lo >= 0 && hi <= 65535)      ? VTK_UNSIGNED_SHORT
           : (lo >= INT32_MIN && hi <= INT32_MAX) ? VTK_INT
                                          : VTK_DOUBLE;
  if (type == VTK_DOUBLE) return stack;
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(stack->GetDimensions());
  image->AllocateScalars(type, 1);
  switch (type) {
    case VTK_SHORT: Narrow(values, static_cast<short*>(image->GetScalarPointer()), total); break;
    case VTK_UNSIGNED_SHORT: Narrow(values, static_cast<unsigned short*>(image->GetScalarPointer()), total); break;
    case VTK_INT: Narrow(values, static_cast<int*>(image->GetScalarPointer()), total); break;
    default: Narrow(values, static_cast<float*>(image->GetScalarPointer()), total); break;
  }
  return image;
}

vtkSmartPointer<vtkImageData> NarrowInt(vtkImageData* stack) {
  const int* values = static_cast<const int*>(stack->GetScalarPointer());
  const size_t total = static_cast<size_t>(stack->GetNumberOfPoints());
  int lo = std::numeric_limits<int>::max(), hi = std::numeric_limits<int>::min();
  for (size_t i = 0; i < total; ++i) {
    lo = std::min(lo, values[i]);
    hi = std::max(hi, values[i]);
  }
  const int type = (lo >= -32768 && hi <= 32767) ? VTK_SHORT : (lo >= 0 && hi <= 65535) ? VTK_UNSIGNED_SHORT : VTK_INT;
  if (type == VTK_INT) return stack;
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(stack->GetDimensions());
  image->AllocateScalars(type, 1);
  if (type == VTK_SHORT)
    Narrow(values, static_cast<short*>(image->GetScalarPointer()), total);
  else
    Narrow(values, static_cast<unsigned short*>(image->GetScalarPointer()), total);
  return image;
}

}  // namespace rp::dicom
