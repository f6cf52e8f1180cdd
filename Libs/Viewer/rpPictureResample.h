#pragma once
// A slice picture resampled onto a view's pixel grid (what vtkRPVolumeSliceDisplayableManager
// hands to vtkRPViewportImageActor): bilinear, in parallel over rows; it allocates only its
// per-call tables (a few kB), never per pixel.

namespace rp {

/// Where target pixel (i, j) samples the source, in source pixel indices (pixel k's centre at k):
/// (u, v) = Origin + i·AlongI + j·AlongJ. Any affine map: the slice camera may be turned.
struct PixelMap {
  double Origin[2] = {0, 0};
  double AlongI[2] = {1, 0};
  double AlongJ[2] = {0, 1};
};

/// Resamples `source` (width × height RGBA, 8 bits a channel, rows from the bottom) into `target`
/// (targetWidth × targetHeight RGBA): colours by bilinear interpolation, clamped at the edge
/// pixels within half a pixel of the picture, black beyond; alpha 255 everywhere (slice views
/// show the colours on black).
void ResampleOpaqueRGBA(const unsigned char* source, int width, int height, const PixelMap& map, unsigned char* target,
                        int targetWidth, int targetHeight);

}  // namespace rp
