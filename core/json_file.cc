#include "msdeform/core/json_file.h"

#include <fstream>
#include <sstream>

namespace msdeform {

bool ReadJsonFile(const std::string& path, nlohmann::json* root, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = path + ": cannot open for reading (missing or unreadable file)";
    return false;
  }
  std::stringstream text;
  text << in.rdbuf();
  try {
    *root = nlohmann::json::parse(text.str(), /*cb=*/nullptr, /*allow_exceptions=*/true,
                                  /*ignore_comments=*/true);
  } catch (const nlohmann::json::exception& e) {
    // e.what() is "[json.exception.parse_error.101] parse error at line 3, ...".
    std::string what = e.what();
    const size_t bracket = what.find("] ");
    if (bracket != std::string::npos) what.erase(0, bracket + 2);
    *error = path + ": invalid JSON: " + what;
    return false;
  }
  return true;
}

}  // namespace msdeform
