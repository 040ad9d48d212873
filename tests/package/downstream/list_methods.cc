// Links the umbrella target msdeform::msdeform (every method) and checks
// that the registry answers: the default method exists and can be created.
#include <cstdio>
#include <memory>
#include <string>

#include <msdeform/methods/registry.h>

int main() {
  std::string error;
  const std::unique_ptr<msdeform::EditingMethod> method =
      msdeform::CreateMethod("multiscale", &error);
  if (!method) {
    std::fprintf(stderr, "list_methods: %s\n", error.c_str());
    return 1;
  }
  std::printf("list_methods: %s\n", msdeform::MethodNameList().c_str());
  return 0;
}
