#include "vtkRPDeflateDataCompressor.h"

#include <algorithm>

#include <libdeflate.h>
#include <vtkObjectFactory.h>

vtkStandardNewMacro(vtkRPDeflateDataCompressor);

vtkRPDeflateDataCompressor::~vtkRPDeflateDataCompressor() {
  if (this->Compressor) libdeflate_free_compressor(this->Compressor);
}

size_t vtkRPDeflateDataCompressor::GetMaximumCompressionSpace(size_t size) {
  // The larger of zlib's bound and libdeflate's, so either can compress into the buffer.
  const size_t zlibBound = this->vtkZLibDataCompressor::GetMaximumCompressionSpace(size);
  return std::max(zlibBound, libdeflate_zlib_compress_bound(nullptr, size));
}

size_t vtkRPDeflateDataCompressor::CompressBuffer(unsigned char const* uncompressedData, size_t uncompressedSize,
                                                  unsigned char* compressedData, size_t compressionSpace) {
  const int level = this->GetCompressionLevel();
  if (!this->Compressor || this->CompressorLevel != level) {
    if (this->Compressor) libdeflate_free_compressor(this->Compressor);
    this->Compressor = libdeflate_alloc_compressor(level);
    this->CompressorLevel = level;
  }
  const size_t written = this->Compressor ? libdeflate_zlib_compress(this->Compressor, uncompressedData,
                                                                     uncompressedSize, compressedData, compressionSpace)
                                          : 0;
  if (written > 0) return written;
  // Out of memory for the compressor, or a buffer sized by someone else's bound: zlib's way.
  return this->vtkZLibDataCompressor::CompressBuffer(uncompressedData, uncompressedSize, compressedData,
                                                     compressionSpace);
}
