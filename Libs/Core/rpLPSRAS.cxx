#include "rpLPSRAS.h"

namespace rp {

void FlipLPSRASPoint(double p[3]) {
  for (int r = 0; r < 3; ++r) p[r] *= kLPSRASSign[r];
}

void FlipLPSRASIndexToSpace(double m[16]) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) m[4 * r + c] *= kLPSRASSign[r];
}

void FlipLPSRASTransform(double m[16]) {
  const double s[4] = {kLPSRASSign[0], kLPSRASSign[1], kLPSRASSign[2], 1.0};
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m[4 * r + c] *= s[r] * s[c];
}

void LPSRASMatrix(double m[16]) {
  for (int i = 0; i < 16; ++i) m[i] = 0.0;
  for (int r = 0; r < 3; ++r) m[5 * r] = kLPSRASSign[r];
  m[15] = 1.0;
}

}  // namespace rp
