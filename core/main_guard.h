// The executables' main(): out of memory (a mesh, lattice or frame count too
// large for this machine) ends the run with one line and exit 1 instead of an
// abort; unwinding the stack removes staged outputs, so nothing partial is
// left. (An allocation that fails inside an OpenMP region or a worker thread
// still terminates.) Not part of the installed API.

#ifndef MSDEFORM_CORE_MAIN_GUARD_H_
#define MSDEFORM_CORE_MAIN_GUARD_H_

#include <iostream>
#include <new>
#include <stdexcept>

namespace msdeform {

// main_body(argc, argv), or 1 with "<program>: out of memory: <what>" on
// standard error when it throws std::bad_alloc or std::length_error.
inline int RunReportingOutOfMemory(const char* program, int (*main_body)(int, char**), int argc,
                                   char** argv) {
  try {
    return main_body(argc, argv);
  } catch (const std::bad_alloc& e) {
    std::cerr << program << ": out of memory: " << e.what() << "\n";
  } catch (const std::length_error& e) {
    std::cerr << program << ": out of memory: " << e.what() << "\n";
  }
  return 1;
}

}  // namespace msdeform

#endif  // MSDEFORM_CORE_MAIN_GUARD_H_
