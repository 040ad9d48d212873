// Reading a JSON file (comments allowed) with the project's one-line errors:
// "PATH: cannot open for reading (...)" and "PATH: invalid JSON: <where and
// what>". Shared by the scenario reader and the editor's scripts; internal
// (not installed), as it names nlohmann::json.

#ifndef MSDEFORM_CORE_JSON_FILE_H_
#define MSDEFORM_CORE_JSON_FILE_H_

#include <string>

#include <nlohmann/json.hpp>

namespace msdeform {

// Parses the file at `path` into *root. On failure returns false and sets
// *error to a one-line message that starts with the path.
bool ReadJsonFile(const std::string& path, nlohmann::json* root, std::string* error);

}  // namespace msdeform

#endif  // MSDEFORM_CORE_JSON_FILE_H_
