#pragma once
// Loading dataset images as the 8-bit grayscale the front end works on, and depth images as metres.
#include <filesystem>

#include <opencv2/core.hpp>

namespace pllvo::io {

/// Reads `file` as CV_8UC1: colour is converted with OpenCV's BGR weights, 16-bit is scaled
/// by 255/65535 (full range to full range). No EXIF rotation is applied. InputError naming
/// the file when it is missing, unreadable or of an unsupported pixel type, and when
/// `expected` is non-empty and the image has another size.
cv::Mat read_gray_image(const std::filesystem::path& file, cv::Size expected = {});

/// Reads a 16-bit single-channel depth image as CV_32FC1 metres (value / `units_per_metre`;
/// 0 stays 0: no depth). InputError naming the file when it is missing, unreadable, not 16-bit
/// single-channel, or of another size than `expected` (when given).
cv::Mat read_depth_image(const std::filesystem::path& file, double units_per_metre, cv::Size expected = {});

}  // namespace pllvo::io
