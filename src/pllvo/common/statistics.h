#pragma once
// Small order statistics shared by the modules' diagnostics and decisions.
#include <vector>

namespace pllvo {

/// The middle value (the upper one of an even count); 0 for no values.
double median(std::vector<double> values);

}  // namespace pllvo
