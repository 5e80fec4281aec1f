#include "pllvo/report/live_viewer.h"

#include <cstdlib>

#include <opencv2/highgui.hpp>

#include "pllvo/common/error.h"

namespace pllvo::report {

bool display_available() {
  for (const char* var : {"DISPLAY", "WAYLAND_DISPLAY", "QT_QPA_PLATFORM"}) {
    const char* v = std::getenv(var);
    if (v && *v) return true;
  }
  return false;
}

LiveViewer::LiveViewer(std::string window) : window_(std::move(window)) {
  if (!display_available())
    throw InputError("--view needs a display: DISPLAY is not set (run without --view, or with "
                     "QT_QPA_PLATFORM=offscreen to render the window without a screen)");
  cv::namedWindow(window_, cv::WINDOW_AUTOSIZE);
}

LiveViewer::~LiveViewer() {
  try {
    cv::destroyWindow(window_);
  } catch (const cv::Exception&) {
    // The window may already be closed by the user.
  }
}

void LiveViewer::operator()(const vo::TrackingView& view) {
  const cv::Mat image = annotate(view);
  if (image.empty()) return;
  cv::imshow(window_, image);
  cv::waitKey(1);  // lets highgui draw; the run never waits for the user
  ++shown_;
}

}  // namespace pllvo::report
