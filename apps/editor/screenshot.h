// Screenshots: the frame's pixels as a PNG (stb_image_write, Debian's
// libstb-dev), and the camera they were taken with as JSON, so that a test or
// a figure script can project points onto the image:
//   {"width": W, "height": H, "view": [16], "projection": [16],   // row by row
//    "yaw_deg": .., "pitch_deg": .., "distance": .., "target": [x, y, z],
//    "panels": [{"name": .., "x": .., "y": .., "width": .., "height": ..,
//                "overflow_x": .., "overflow_y": ..}, ...]}   // with the panels drawn
// A world point p lands at pixel x = (ndc_x + 1) / 2 W, y = (1 - ndc_y) / 2 H
// (top-left origin) with ndc = (projection view [p 1])_xyz / w.

#ifndef MSDEFORM_APPS_EDITOR_SCREENSHOT_H_
#define MSDEFORM_APPS_EDITOR_SCREENSHOT_H_

#include <cstdint>
#include <string>
#include <vector>

#include "apps/editor/camera.h"

namespace msdeform {
namespace editor {

// Writes RGB pixels (top row first, width * height * 3 bytes) to `path`
// atomically. False with "<path>: ..." on failure.
bool WritePng(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb,
              std::string* error);

// A panel window as drawn: its rectangle (pixels, top-left origin) and how far
// its contents reach past what it shows, right and down (pixels; <= 0: all of
// it is in view, nothing cut or scrolled away).
struct PanelRect {
  std::string name;
  float x = 0, y = 0, width = 0, height = 0;
  float overflow_x = 0, overflow_y = 0;
};

// The camera JSON above; "panels" when `panels` is not empty.
std::string CameraJson(const OrbitCamera& camera, const Viewport& viewport,
                       const std::vector<PanelRect>& panels = {});

}  // namespace editor
}  // namespace msdeform

#endif  // MSDEFORM_APPS_EDITOR_SCREENSHOT_H_
