// tools/accuracy/image_error.h — how far a render is from a reference image.
//
// Over every pixel and channel of the data window (x ours, r the reference):
//   relmse = mean of (x - r)^2 / (r^2 + 0.01)
//   rmse   = sqrt(mean of (x - r)^2)
//   mare   = mean of |x - r| / sqrt(r^2 + 0.01)
// relmse's 0.01 keeps black reference pixels from dominating; mare uses the
// same denominator so that sqrt(relmse) and mare are the RMS and the mean of
// one per-value relative error. The images must have the same data window.
#pragma once

#include <string>

#include "runtime/film/image_io.h"

namespace accuracy {

struct ImageErrors {
  double relmse = 0, rmse = 0, mare = 0;
};

// False with *error (naming both sizes) when the data windows differ or the
// images are empty.
bool image_errors(const rt::ImageRgb& ours, const rt::ImageRgb& reference, ImageErrors* out,
                  std::string* error);

}  // namespace accuracy
