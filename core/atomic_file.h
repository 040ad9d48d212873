// All-or-nothing file output: every msdeform writer (meshes, reports, CSV)
// goes through WriteFileAtomically so that a failed or interrupted write
// never leaves a partial file behind, and never clobbers a good one.

#ifndef MSDEFORM_CORE_ATOMIC_FILE_H_
#define MSDEFORM_CORE_ATOMIC_FILE_H_

#include <functional>
#include <ostream>
#include <string>

namespace msdeform {

// Fills the output stream. Returns false on failure and may then explain why
// in *error (one line, without the file name; the caller adds it).
using StreamWriter = std::function<bool(std::ostream& out, std::string* error)>;

// Writes `path` through a temporary file in the same folder: `write` fills
// the temporary, which is flushed to disk and renamed over `path` only if
// `write` returns true and every stream operation succeeded. On failure the
// temporary is removed, `path` is left as it was, and *error holds one line
// naming `path` and the problem.
//
// Refusing to overwrite an input (e.g. `msdeform -in a.off -out a.off`) is the
// caller's job; SameFile below helps.
bool WriteFileAtomically(const std::string& path, const StreamWriter& write, std::string* error);

// True when both paths exist and name the same file (same device and inode,
// so through links and different spellings too). False if either is missing.
bool SameFile(const std::string& a, const std::string& b);

}  // namespace msdeform

#endif  // MSDEFORM_CORE_ATOMIC_FILE_H_
