#pragma once
// `pllvo run --view`: an OpenCV highgui window showing each frame with its tracked points and
// lines coloured by state. Only created when asked for, so headless runs never touch a display.
#include <string>

#include "pllvo/report/frame_annotator.h"

namespace pllvo::report {

/// True when a window can be opened: an X11 or Wayland display, or a Qt platform chosen
/// explicitly (QT_QPA_PLATFORM=offscreen runs the window without a screen, e.g. in tests).
bool display_available();

class LiveViewer {
 public:
  /// InputError when no display is available (highgui's Qt backend would abort the process).
  explicit LiveViewer(std::string window = "pllvo");
  ~LiveViewer();
  LiveViewer(const LiveViewer&) = delete;
  LiveViewer& operator=(const LiveViewer&) = delete;

  void operator()(const vo::TrackingView& view);
  size_t shown() const { return shown_; }

 private:
  std::string window_;
  size_t shown_ = 0;
};

}  // namespace pllvo::report
