#include "apps/outputs.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <ostream>

#include "msdeform/core/atomic_file.h"

namespace msdeform {

namespace fs = std::filesystem;

namespace {

std::string LowerExtension(const std::string& path) {
  std::string extension = fs::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

// The nearest existing ancestor of `path`'s folder must be a writable
// directory (the rest is created when the outputs are written).
bool FolderWritable(const std::string& path, std::string* problem) {
  fs::path folder = fs::absolute(fs::path(path)).parent_path();
  std::error_code ec;
  while (!folder.empty() && !fs::exists(folder, ec)) folder = folder.parent_path();
  if (!fs::is_directory(folder, ec)) {
    *problem = folder.string() + " is not a folder";
    return false;
  }
  if (access(folder.c_str(), W_OK) != 0) {
    *problem = "cannot write in " + folder.string();
    return false;
  }
  return true;
}

}  // namespace

bool CheckOutputs(const std::vector<OutputCheck>& outputs, const std::vector<std::string>& inputs,
                  bool overwrite, std::string* error) {
  for (size_t i = 0; i < outputs.size(); ++i) {
    const OutputCheck& output = outputs[i];
    if (output.path.empty()) continue;
    const std::string where = output.flag + "=" + output.path;
    std::error_code ec;
    if (fs::is_directory(output.path, ec) || output.path.back() == '/') {
      *error = where + ": is a folder; give a file name";
      return false;
    }
    if (!output.extensions.empty()) {
      const std::string extension = LowerExtension(output.path);
      if (std::find(output.extensions.begin(), output.extensions.end(), extension) ==
          output.extensions.end()) {
        std::string list;
        for (const std::string& e : output.extensions) list += (list.empty() ? "" : ", ") + e;
        *error = where + ": cannot write " +
                 (extension.empty() ? std::string("a file without an extension")
                                    : "format '" + extension + "'") +
                 "; use " + list;
        return false;
      }
    }
    std::string problem;
    if (!FolderWritable(output.path, &problem)) {
      *error = where + ": " + problem;
      return false;
    }
    for (const std::string& input : inputs) {
      if (!input.empty() && SameFile(output.path, input)) {
        *error = where + ": is an input file; refusing to overwrite it";
        return false;
      }
    }
    for (size_t j = 0; j < i; ++j) {
      std::error_code ec_i, ec_j;
      if (!outputs[j].path.empty() && fs::weakly_canonical(output.path, ec_i) ==
                                          fs::weakly_canonical(outputs[j].path, ec_j)) {
        *error = where + ": also given as " + outputs[j].flag;
        return false;
      }
    }
    if (!overwrite && fs::exists(output.path, ec)) {
      *error = where + ": exists; pass --overwrite to replace it";
      return false;
    }
  }
  return true;
}

StagedOutputs::~StagedOutputs() {
  std::error_code ignored;
  for (const auto& [staged, final_path] : files_) fs::remove(staged, ignored);
}

bool StagedOutputs::Stage(const std::string& path, std::string* staged, std::string* error) {
  const fs::path final_path(path);
  const fs::path parent = final_path.parent_path();
  std::error_code ec;
  if (!parent.empty() && !fs::is_directory(parent, ec)) {
    fs::create_directories(parent, ec);
    if (ec) {
      *error = path + ": cannot create its folder (" + ec.message() + ")";
      return false;
    }
  }
  *staged = (parent / ("." + final_path.stem().string() + ".partial" +
                       final_path.extension().string()))
                .string();
  files_.emplace_back(*staged, path);
  return true;
}

bool StagedOutputs::Commit(std::string* error) {
  for (const auto& [staged, final_path] : files_) {
    std::error_code ec;
    fs::rename(staged, final_path, ec);
    if (ec) {
      *error = final_path + ": cannot move the finished output into place (" + ec.message() + ")";
      return false;
    }
  }
  files_.clear();
  return true;
}

std::string StagedOutputs::Translate(std::string error) const {
  for (const auto& [staged, final_path] : files_) {
    for (size_t at = error.find(staged); at != std::string::npos;
         at = error.find(staged, at + final_path.size())) {
      error.replace(at, staged.size(), final_path);
    }
  }
  return error;
}

bool WriteText(const std::string& path, const std::string& text, std::string* error) {
  return WriteFileAtomically(
      path,
      [&](std::ostream& out, std::string*) {
        out << text;
        return static_cast<bool>(out);
      },
      error);
}

}  // namespace msdeform
