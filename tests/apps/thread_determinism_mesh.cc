// The input of tests/apps/thread_determinism_test.sh: a closed cylinder
// (core/procedural_meshes.h, MakeCylinder) of radius 1 and height 10 along z,
// 240 segments and 440 rings: 116,162 vertices, enough that each stage of
// msdeform takes its parallel path, and a slender bar, so that its lattice
// stays small (4,042 particles: a fatter one makes the rigidity estimate take
// seconds). Written to each path given, the format by extension (.off text,
// .ply binary).
//
//   thread_determinism_mesh OUT.off OUT.ply

#include <cstdio>
#include <string>

#include "msdeform/core/mesh.h"
#include "msdeform/core/mesh_io.h"
#include "msdeform/core/procedural_meshes.h"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: thread_determinism_mesh OUT.off|OUT.ply ...\n");
    return 2;
  }
  const msdeform::Mesh cylinder = msdeform::MakeCylinder(1.0, 10.0, 240, 440);
  for (int i = 1; i < argc; ++i) {
    std::string error;
    if (!msdeform::WriteMesh(argv[i], cylinder, &error)) {
      std::fprintf(stderr, "thread_determinism_mesh: %s\n", error.c_str());
      return 1;
    }
  }
  std::printf("thread_determinism_mesh: %d vertices, %d faces\n", cylinder.num_vertices(),
              cylinder.num_faces());
  return 0;
}
