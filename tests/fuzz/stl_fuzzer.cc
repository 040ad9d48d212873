// libFuzzer target: the STL mesh reader (scripts/fuzz.sh builds and runs it).
#include "tests/fuzz/fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  msdeform::fuzz::FuzzMesh(data, size, ".stl");
  return 0;
}
