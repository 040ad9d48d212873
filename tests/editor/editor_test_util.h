// Shared set-up of the editor's session tests.

#ifndef MSDEFORM_TESTS_EDITOR_EDITOR_TEST_UTIL_H_
#define MSDEFORM_TESTS_EDITOR_EDITOR_TEST_UTIL_H_

#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "apps/editor/edit_inputs.h"
#include "apps/editor/edit_session.h"

namespace msdeform {
namespace editor {

inline const std::string& MeshesDir() {
  static const std::string* const dir = new std::string(std::string(MSDEFORM_DATA_DIR) + "/meshes/");
  return *dir;
}

// Opens the cactus mesh alone (no handle layout) in `session` and waits for
// the set-up; a failure to read it fails the test.
inline void OpenCactusMesh(EditSession* session) {
  OpenRequest request;
  request.mesh = MeshesDir() + "cactus.off";
  EditInputs inputs;
  std::string error;
  ASSERT_TRUE(LoadEditInputs(request, &inputs, &error)) << error;
  ASSERT_FALSE(inputs.has_layout);
  session->Open(std::move(inputs), DeformerOptions());
  session->Wait();
}

}  // namespace editor
}  // namespace msdeform

#endif  // MSDEFORM_TESTS_EDITOR_EDITOR_TEST_UTIL_H_
