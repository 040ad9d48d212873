// Shared by the tests that need a lattice over a procedural mesh.

#ifndef MSDEFORM_TESTS_CORE_LATTICE_TEST_UTIL_H_
#define MSDEFORM_TESTS_CORE_LATTICE_TEST_UTIL_H_

#include <string>

#include <gtest/gtest.h>

#include "msdeform/core/lattice.h"
#include "msdeform/core/mesh.h"

namespace msdeform {

// The lattice of `mesh` with cell width `cell_width` (0: the default,
// diagonal / 48); a failed build fails the calling test.
inline Lattice BuildTestLattice(const Mesh& mesh, double cell_width = 0.0) {
  LatticeOptions options;
  options.cell_width = cell_width;
  Lattice lattice;
  std::string error;
  EXPECT_TRUE(Lattice::Build(mesh, options, &lattice, &error)) << error;
  return lattice;
}

}  // namespace msdeform

#endif  // MSDEFORM_TESTS_CORE_LATTICE_TEST_UTIL_H_
