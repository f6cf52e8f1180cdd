#pragma once
// zlib streams for .vtp files, compressed by libdeflate: about three times as fast as zlib's own
// compress2 at level 1, for files of the same size. Reading is zlib's (vtkZLibDataCompressor).
#include <vtkZLibDataCompressor.h>

struct libdeflate_compressor;

class vtkRPDeflateDataCompressor : public vtkZLibDataCompressor {
 public:
  // No vtkTypeMacro on purpose: GetClassName() stays "vtkZLibDataCompressor", the name
  // vtkXMLWriter writes into the file and every VTK reader (Slicer, ParaView) picks its
  // decompressor by. The streams are zlib streams, so that name is the truth.
  static vtkRPDeflateDataCompressor* New();
  size_t GetMaximumCompressionSpace(size_t size) override;

 protected:
  vtkRPDeflateDataCompressor() = default;
  ~vtkRPDeflateDataCompressor() override;
  size_t CompressBuffer(unsigned char const* uncompressedData, size_t uncompressedSize, unsigned char* compressedData,
                        size_t compressionSpace) override;

 private:
  vtkRPDeflateDataCompressor(const vtkRPDeflateDataCompressor&) = delete;
  void operator=(const vtkRPDeflateDataCompressor&) = delete;
  libdeflate_compressor* Compressor = nullptr;  // for CompressionLevel; made on first use
  int CompressorLevel = 0;
};
