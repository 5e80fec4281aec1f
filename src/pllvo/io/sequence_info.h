#pragma once
// A human-readable summary of an opened dataset (what `pllvo info` prints).
#include <string>

#include "pllvo/io/sequence.h"

namespace pllvo::io {

/// Format, frame count, time span, rate, resolution, camera models with parameters, stereo
/// baseline (and rectified intrinsics) and ground truth, one `name  value` line each.
std::string describe_sequence(const Sequence& seq);

}  // namespace pllvo::io
