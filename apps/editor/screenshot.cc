#include "apps/editor/screenshot.h"

#include <stb_image_write.h>

#include <nlohmann/json.hpp>
#include <ostream>

#include "msdeform/core/atomic_file.h"

namespace msdeform {
namespace editor {
namespace {

void AppendToStream(void* context, void* data, int size) {
  static_cast<std::ostream*>(context)->write(static_cast<const char*>(data), size);
}

std::vector<double> RowByRow(const Eigen::Matrix4d& m) {
  std::vector<double> values;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) values.push_back(m(r, c));
  }
  return values;
}

}  // namespace

bool WritePng(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb,
              std::string* error) {
  if (width <= 0 || height <= 0 || rgb.size() != static_cast<size_t>(width) * height * 3) {
    *error = path + ": no image to write";
    return false;
  }
  return WriteFileAtomically(
      path,
      [&](std::ostream& out, std::string* problem) {
        if (stbi_write_png_to_func(AppendToStream, &out, width, height, 3, rgb.data(), width * 3) ==
            0) {
          *problem = "PNG encoding failed";
          return false;
        }
        return true;
      },
      error);
}

std::string CameraJson(const OrbitCamera& camera, const Viewport& viewport,
                       const std::vector<PanelRect>& panels) {
  nlohmann::ordered_json json;
  json["width"] = viewport.width;
  json["height"] = viewport.height;
  json["view"] = RowByRow(camera.View());
  json["projection"] = RowByRow(camera.Projection(viewport));
  json["yaw_deg"] = camera.yaw_deg();
  json["pitch_deg"] = camera.pitch_deg();
  json["distance"] = camera.distance();
  const Eigen::Vector3d& t = camera.target();
  json["target"] = {t.x(), t.y(), t.z()};
  for (const PanelRect& panel : panels) {
    json["panels"].push_back({{"name", panel.name},
                              {"x", panel.x},
                              {"y", panel.y},
                              {"width", panel.width},
                              {"height", panel.height},
                              {"overflow_x", panel.overflow_x},
                              {"overflow_y", panel.overflow_y}});
  }
  return json.dump(1) + "\n";
}

}  // namespace editor
}  // namespace msdeform
