// The output files of one msdeform run: checked before any work, written to
// hidden temporaries, and renamed into place together at the end, so a run
// that fails leaves nothing behind and an existing file is replaced only when
// the user asked (--overwrite).

#ifndef MSDEFORM_APPS_OUTPUTS_H_
#define MSDEFORM_APPS_OUTPUTS_H_

#include <string>
#include <utility>
#include <vector>

namespace msdeform {

struct OutputCheck {
  std::string path;
  std::string flag;                     // "--out", for messages
  std::vector<std::string> extensions;  // accepted, lower case with the dot; empty: any
};

// False with one line naming the flag and the path when an output is a
// directory, has an extension it cannot be written as, lies in a folder that
// cannot be created or written, is one of `inputs`, is given twice, or exists
// and `overwrite` is false.
bool CheckOutputs(const std::vector<OutputCheck>& outputs, const std::vector<std::string>& inputs,
                  bool overwrite, std::string* error);

// Outputs staged under hidden names beside their final paths.
class StagedOutputs {
 public:
  StagedOutputs() = default;
  StagedOutputs(const StagedOutputs&) = delete;
  StagedOutputs& operator=(const StagedOutputs&) = delete;
  // Removes whatever was staged and not committed.
  ~StagedOutputs();

  // Where to write `path` for now: ".<name>.partial<ext>" in its folder,
  // which is created if needed.
  bool Stage(const std::string& path, std::string* staged, std::string* error);
  // Renames every staged file to its final path.
  bool Commit(std::string* error);
  // `error` with each staged path replaced by its final path, so messages
  // name the file the user asked for, not the hidden temporary.
  std::string Translate(std::string error) const;

 private:
  std::vector<std::pair<std::string, std::string>> files_;  // staged, final
};

// Writes `text` to `path` atomically (core/atomic_file.h).
bool WriteText(const std::string& path, const std::string& text, std::string* error);

}  // namespace msdeform

#endif  // MSDEFORM_APPS_OUTPUTS_H_
