// ReadMesh on several threads (MeshReadOptions): text OFF and OBJ parsed in
// pieces, binary PLY decoded in chunks, the fan split and the dropped faces
// in chunks. The known answer is the one-thread reading: the same mesh bit
// for bit, the same counts and the same messages for any thread count and
// chunk size, and for the formats that round-trip exactly, the mesh written.

#include <array>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "msdeform/core/build_info.h"
#include "msdeform/core/mesh_io.h"
#include "msdeform/core/procedural_meshes.h"
#include "tests/test_util.h"

namespace msdeform {
namespace {

namespace fs = std::filesystem;

// A UV sphere of 50,900 vertices and 101,600 triangles (2.6 MB as OFF).
Mesh BigSphere() { return MakeSphere(1.0, 200, 256); }

// The ways of reading compared: one thread (the reference), then 2 and 3
// threads with the default chunks (a few pieces) and with small ones (many
// pieces, many chunks of faces and vertex blocks).
std::vector<MeshReadOptions> ReadingsToCompare() {
  std::vector<MeshReadOptions> readings;
  for (int threads : {1, 2, 3}) {
    for (bool small : {false, true}) {
      MeshReadOptions options;
      options.num_threads = threads;
      if (small) {
        options.text_chunk_bytes = 4096;
        options.items_per_chunk = 1000;
      }
      readings.push_back(options);
    }
  }
  return readings;
}

std::string Describe(const MeshReadOptions& options) {
  return "threads " + std::to_string(options.num_threads) + ", text chunk " +
         std::to_string(options.text_chunk_bytes) + ", items per chunk " +
         std::to_string(options.items_per_chunk);
}

// Bit for bit (a -0.0 is not a 0.0).
void ExpectSameMesh(const Mesh& expected, const Mesh& actual, const std::string& what) {
  ASSERT_EQ(expected.vertices.cols(), actual.vertices.cols()) << what;
  ASSERT_EQ(expected.faces.cols(), actual.faces.cols()) << what;
  EXPECT_EQ(std::memcmp(expected.vertices.data(), actual.vertices.data(),
                        sizeof(double) * expected.vertices.size()),
            0)
      << what;
  EXPECT_EQ(expected.faces, actual.faces) << what;
}

// Reads `path` every way; each reading must give `expected` (when it
// succeeds) and the one-thread reading's report or message.
struct Reading {
  bool ok = false;
  Mesh mesh;
  MeshReadReport report;
  std::string error;
};

Reading Read(const std::string& path, const MeshReadOptions& options) {
  Reading reading;
  reading.ok = ReadMesh(path, options, &reading.mesh, &reading.report, &reading.error);
  return reading;
}

Reading ExpectSameAtAnyThreadCount(const std::string& path) {
  const std::vector<MeshReadOptions> readings = ReadingsToCompare();
  const Reading reference = Read(path, readings[0]);
  for (size_t k = 1; k < readings.size(); ++k) {
    const std::string what = path + ", " + Describe(readings[k]);
    const Reading reading = Read(path, readings[k]);
    EXPECT_EQ(reading.ok, reference.ok) << what;
    EXPECT_EQ(reading.error, reference.error) << what;
    EXPECT_EQ(reading.report.dropped_degenerate_faces, reference.report.dropped_degenerate_faces)
        << what;
    EXPECT_EQ(reading.report.dropped_duplicate_faces, reference.report.dropped_duplicate_faces)
        << what;
    EXPECT_EQ(reading.report.notice, reference.report.notice) << what;
    if (reading.ok && reference.ok) ExpectSameMesh(reference.mesh, reading.mesh, what);
  }
  return reference;
}

TEST(MeshIoThreadsTest, WrittenMeshReadsBackTheSameAtAnyThreadCount) {
  const Mesh sphere = BigSphere();
  ASSERT_GE(sphere.num_vertices(), 50000);
  const std::string folder = FreshFolder();
  for (const std::string extension : {".off", ".obj", ".ply"}) {
    const std::string path = folder + "/sphere" + extension;
    std::string error;
    ASSERT_TRUE(WriteMesh(path, sphere, &error)) << error;
    const Reading reading = ExpectSameAtAnyThreadCount(path);
    ASSERT_TRUE(reading.ok) << reading.error;
    ExpectSameMesh(sphere, reading.mesh, path);
    EXPECT_TRUE(reading.report.notice.empty()) << reading.report.notice;
  }
}

// The sphere's OFF text with line `line` (1-based) replaced by `replacement`.
std::string OffWithLine(const std::string& text, int line, const std::string& replacement) {
  std::istringstream in(text);
  std::ostringstream out;
  std::string current;
  for (int number = 1; std::getline(in, current); ++number) {
    out << (number == line ? replacement : current) << "\n";
  }
  return out.str();
}

// The text's first `count` lines.
std::string FirstLines(const std::string& text, int count) {
  size_t end = 0;
  for (int k = 0; k < count; ++k) end = text.find('\n', end) + 1;
  return text.substr(0, end);
}

TEST(MeshIoThreadsTest, BadLineDeepInTheFileGivesTheSameMessageAtAnyThreadCount) {
  const Mesh sphere = BigSphere();
  const std::string folder = FreshFolder();
  const std::string off_path = folder + "/sphere.off";
  std::string error;
  ASSERT_TRUE(WriteMesh(off_path, sphere, &error)) << error;
  const std::string off = ReadText(off_path);
  // Line 1 is "OFF", line 2 the counts: vertex v is on line v + 3, face f
  // on line #V + f + 3.
  const int num_vertices = sphere.num_vertices();
  struct Case {
    std::string text;
    std::string message;  // after "<path>: "
  };
  const std::vector<Case> cases = {
      {OffWithLine(off, 40003, "0.5 abc 1"),
       "line 40003: vertex 40000 coordinate 'abc' is not a number"},
      {OffWithLine(off, num_vertices + 90003, "3 1 2 " + std::to_string(num_vertices)),
       "line " + std::to_string(num_vertices + 90003) + ": face 90000 refers to vertex " +
           std::to_string(num_vertices) + ", outside 0.." + std::to_string(num_vertices - 1)},
      // Two bad lines: the first one is named.
      {OffWithLine(OffWithLine(off, 30003, "1 2"), num_vertices + 90003, "2 1 2"),
       "line 30003: vertex 30000 has fewer than 3 coordinates"},
      // Cut after 80001 faces: the count of what was read.
      {FirstLines(off, 2 + num_vertices + 80001),
       "truncated: the header (line 2) announces " + std::to_string(num_vertices) +
           " vertices and " + std::to_string(sphere.num_faces()) +
           " faces, but the file ends after 80001 of " + std::to_string(sphere.num_faces()) +
           " faces"},
  };
  for (size_t k = 0; k < cases.size(); ++k) {
    const std::string path = folder + "/bad" + std::to_string(k) + ".off";
    WriteText(path, cases[k].text);
    const Reading reading = ExpectSameAtAnyThreadCount(path);
    EXPECT_FALSE(reading.ok) << path;
    EXPECT_EQ(reading.error, path + ": " + cases[k].message);
  }

  // OBJ: a bad face corner deep in the file.
  const std::string obj_path = folder + "/sphere.obj";
  ASSERT_TRUE(WriteMesh(obj_path, sphere, &error)) << error;
  std::string obj = ReadText(obj_path);
  const size_t face = obj.find("\nf ", obj.size() / 2 + 1);
  ASSERT_NE(face, std::string::npos);
  obj.insert(face + 3, "/7 ");
  const std::string bad_obj = folder + "/bad.obj";
  WriteText(bad_obj, obj);
  const Reading reading = ExpectSameAtAnyThreadCount(bad_obj);
  EXPECT_FALSE(reading.ok);
  EXPECT_NE(reading.error.find("face corner '/7' is not v, v/t, v//n or v/t/n"),
            std::string::npos)
      << reading.error;
}

// OFF text of `mesh`'s vertices and the faces `faces` (3 ids each).
std::string OffText(const Mesh& mesh, const std::vector<std::array<int, 3>>& faces) {
  std::ostringstream text;
  text.precision(17);
  text << "OFF\n" << mesh.num_vertices() << " " << faces.size() << " 0\n";
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    text << mesh.vertices(0, v) << " " << mesh.vertices(1, v) << " " << mesh.vertices(2, v)
         << "\n";
  }
  for (const std::array<int, 3>& face : faces) {
    text << "3 " << face[0] << " " << face[1] << " " << face[2] << "\n";
  }
  return text.str();
}

// Copies of earlier triangles (rotated, far from their originals, in many
// chunks), triangles that repeat a vertex, a fan of 40 triangles around
// vertex 0 (one group larger than the pairwise scan takes) with copies, and
// back faces (opposite orientation, kept): the same triangles and counts at
// any thread count, and exactly the sphere's triangles plus the fan and the
// back faces.
TEST(MeshIoThreadsTest, DroppedFacesAreTheSameAtAnyThreadCount) {
  const Mesh sphere = BigSphere();
  std::vector<std::array<int, 3>> faces, expected;
  for (int f = 0; f < sphere.num_faces(); ++f) {
    faces.push_back({sphere.faces(0, f), sphere.faces(1, f), sphere.faces(2, f)});
  }
  expected = faces;
  int duplicates = 0, degenerate = 0;
  for (int f = 0; f < sphere.num_faces(); f += 997) {
    const std::array<int, 3>& a = faces[f];
    faces.push_back({a[1], a[2], a[0]});  // the same triangle, rotated
    ++duplicates;
    faces.push_back({a[0], a[0], a[1]});
    ++degenerate;
  }
  for (int f = 5; f < sphere.num_faces(); f += 4999) {
    const std::array<int, 3> back = {faces[f][0], faces[f][2], faces[f][1]};
    faces.push_back(back);
    expected.push_back(back);
  }
  for (int k = 1; k <= 40; ++k) {
    const std::array<int, 3> fan = {0, 1000 + k, 1001 + k};
    faces.push_back(fan);
    expected.push_back(fan);
  }
  for (int k = 1; k <= 40; k += 3) {
    faces.push_back({1001 + k, 0, 1000 + k});
    ++duplicates;
  }
  const std::string path = FreshFolder() + "/copies.off";
  WriteText(path, OffText(sphere, faces));
  const Reading reading = ExpectSameAtAnyThreadCount(path);
  ASSERT_TRUE(reading.ok) << reading.error;
  EXPECT_EQ(reading.report.dropped_duplicate_faces, duplicates);
  EXPECT_EQ(reading.report.dropped_degenerate_faces, degenerate);
  ASSERT_EQ(reading.mesh.num_faces(), static_cast<int>(expected.size()));
  for (size_t f = 0; f < expected.size(); ++f) {
    EXPECT_EQ(reading.mesh.faces(0, f), expected[f][0]) << f;
    EXPECT_EQ(reading.mesh.faces(1, f), expected[f][1]) << f;
    EXPECT_EQ(reading.mesh.faces(2, f), expected[f][2]) << f;
  }
}

// OBJ faces with negative (relative) vertex numbers, "v" and "f" lines
// interleaved, comments and blank lines between: the negative numbers count
// back from the vertices before their line, wherever the piece starts.
TEST(MeshIoThreadsTest, ObjRelativeVertexNumbersAcrossPieces) {
  const Mesh sphere = BigSphere();
  std::ostringstream text;
  text.precision(17);
  int written = 0;
  for (int f = 0; f < sphere.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      while (written <= sphere.faces(c, f)) {
        text << "v " << sphere.vertices(0, written) << " " << sphere.vertices(1, written) << " "
             << sphere.vertices(2, written) << "\n";
        ++written;
      }
    }
    if (f % 101 == 0) text << "# face " << f << "\n\n";
    text << "f " << sphere.faces(0, f) - written << " " << sphere.faces(1, f) + 1 << "//"
         << " " << sphere.faces(2, f) - written << "/1\n";
  }
  ASSERT_EQ(written, sphere.num_vertices());
  const std::string path = FreshFolder() + "/relative.obj";
  WriteText(path, text.str());
  const Reading reading = ExpectSameAtAnyThreadCount(path);
  ASSERT_TRUE(reading.ok) << reading.error;
  ExpectSameMesh(sphere, reading.mesh, path);
}

// Every file of the bad-input corpus: the same message on 3 threads with
// pieces of a few bytes and chunks of a few items as on one thread.
TEST(MeshIoThreadsTest, BadInputCorpusGivesTheSameMessages) {
  int files = 0;
  for (const auto& entry : fs::directory_iterator(SourceTreePath("tests/data/bad"))) {
    if (!entry.is_regular_file()) continue;
    const std::string path = entry.path().string();
    Reading reference = Read(path, MeshReadOptions());
    for (int chunk : {1, 7, 64}) {
      MeshReadOptions options;
      options.num_threads = 3;
      options.text_chunk_bytes = chunk;
      options.items_per_chunk = 2;
      const Reading reading = Read(path, options);
      EXPECT_EQ(reading.ok, reference.ok) << path;
      EXPECT_EQ(reading.error, reference.error) << path << ", chunk " << chunk;
      if (reading.ok && reference.ok) ExpectSameMesh(reference.mesh, reading.mesh, path);
    }
    ++files;
  }
  EXPECT_GT(files, 20);
}

TEST(MeshIoThreadsTest, InvalidOptionsAreRefused) {
  MeshReadOptions options;
  options.num_threads = 0;
  Mesh mesh;
  MeshReadReport report;
  std::string error;
  EXPECT_FALSE(ReadMesh("any.off", options, &mesh, &report, &error));
  EXPECT_EQ(error, "any.off: ReadMesh options: num_threads 0: need at least 1");
  options = MeshReadOptions();
  options.text_chunk_bytes = 0;
  EXPECT_FALSE(ReadMesh("any.off", options, &mesh, &report, &error));
  EXPECT_EQ(error, "any.off: ReadMesh options: text_chunk_bytes 0: need at least 1");
  options = MeshReadOptions();
  options.items_per_chunk = -1;
  EXPECT_FALSE(ReadMesh("any.off", options, &mesh, &report, &error));
  EXPECT_EQ(error, "any.off: ReadMesh options: items_per_chunk -1: need at least 1");
}

}  // namespace
}  // namespace msdeform
