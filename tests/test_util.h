// Helpers shared by the C++ tests of every folder (as Ceres's test_util.h):
// temporary folders and text files, and the small transforms the edit tests
// drag handles with. Compiled into msdeform_test_main, so every test has them;
// they depend on nothing of msdeform's. Helpers of one layer live beside its
// tests: tests/energies/cost_test_util.h (cost functions against autodiff and
// numeric derivatives), tests/solvers/frame_solver_test_util.h (stopping
// rules), tests/scales/deformer_test_util.h (small edits), and
// tests/core/lattice_test_util.h.

#ifndef MSDEFORM_TESTS_TEST_UTIL_H_
#define MSDEFORM_TESTS_TEST_UTIL_H_

#include <string>

#include <Eigen/Geometry>

namespace msdeform {

// A new, empty folder under testing::TempDir(), named after the running test
// suite; a failed test expectation if it cannot be made. It is removed when
// the test that made it ends, unless the test failed: then its path is
// printed and the folder kept to look at (RemoveFreshFolders).
std::string FreshFolder();

// Removes the folders FreshFolder made since the last call, or prints their
// paths if `keep`; test_main.cc calls it after each test (and once at the
// end, for folders made outside a test).
void RemoveFreshFolders(bool keep);

// Writes `text` to `path` byte for byte (binary mode), making the parent
// folders first; a failed test expectation if it cannot. Returns `path`.
std::string WriteText(const std::string& path, const std::string& text);

// The bytes of the file at `path` (binary mode); empty if it cannot be read.
std::string ReadText(const std::string& path);

// A translation by z along the z axis: the drag the edit tests apply.
Eigen::Affine3d Lift(double z);

}  // namespace msdeform

#endif  // MSDEFORM_TESTS_TEST_UTIL_H_
