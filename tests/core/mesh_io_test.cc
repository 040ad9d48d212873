#include "msdeform/core/mesh_io.h"

#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "msdeform/core/build_info.h"
#include "msdeform/core/mesh_io_formats.h"
#include "tests/test_util.h"

namespace msdeform {
namespace {

namespace fs = std::filesystem;

// Two triangles forming a unit square, plus a third triangle off to the side;
// coordinates are exact in float.
Mesh SmallMesh() {
  Mesh mesh;
  mesh.vertices.resize(3, 6);
  mesh.vertices << 0, 1, 0, 1, 2.5, 3.125,  //
      0, 0, 1, 1, -0.5, 0.25,               //
      0, 0.5, 0, -0.75, 8, 16;
  mesh.faces.resize(3, 3);
  mesh.faces << 0, 1, 3,  //
      1, 3, 4,            //
      2, 2, 5;
  return mesh;
}

// Random doubles in [-100, 100], not representable in float.
Mesh RandomMesh(int num_vertices, int num_faces, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> coordinate(-100.0, 100.0);
  Mesh mesh;
  mesh.vertices.resize(3, num_vertices);
  for (int v = 0; v < num_vertices; ++v) {
    for (int k = 0; k < 3; ++k) mesh.vertices(k, v) = coordinate(random);
  }
  std::uniform_int_distribution<int> id(0, num_vertices - 1);
  mesh.faces.resize(3, num_faces);
  for (int f = 0; f < num_faces; ++f) {
    int a = id(random), b = id(random), c = id(random);
    while (b == a) b = id(random);
    while (c == a || c == b) c = id(random);
    mesh.faces.col(f) << a, b, c;
  }
  return mesh;
}

class MeshRoundTripTest : public testing::TestWithParam<std::string> {};

TEST_P(MeshRoundTripTest, KeepsVertexOrderAndFacesExactlyForFloatCoordinates) {
  const std::string path = FreshFolder() + "/small." + GetParam();
  const Mesh mesh = SmallMesh();
  std::string error;
  ASSERT_TRUE(WriteMesh(path, mesh, &error)) << error;
  Mesh read;
  ASSERT_TRUE(ReadMesh(path, &read, &error)) << error;
  EXPECT_EQ(read.vertices, mesh.vertices);
  EXPECT_EQ(read.faces, mesh.faces);
}

// (Awkward values, bit for bit: tests/core/mesh_io_precision_test.cc.)
TEST_P(MeshRoundTripTest, RandomDoublesComeBackExactly) {
  const std::string path = FreshFolder() + "/random." + GetParam();
  const Mesh mesh = RandomMesh(200, 300, 7);
  std::string error;
  ASSERT_TRUE(WriteMesh(path, mesh, &error)) << error;
  Mesh read;
  ASSERT_TRUE(ReadMesh(path, &read, &error)) << error;
  EXPECT_EQ(read.vertices, mesh.vertices);
  EXPECT_EQ(read.faces, mesh.faces);
}

// The file holds every double exactly: its numbers, read as doubles by
// another program, are the mesh's coordinates bit for bit.
TEST_P(MeshRoundTripTest, FileHoldsEveryCoordinateAsTheSameDouble) {
  const std::string path = FreshFolder() + "/exact." + GetParam();
  const Mesh mesh = RandomMesh(50, 40, 11);
  std::string error;
  ASSERT_TRUE(WriteMesh(path, mesh, &error)) << error;
  if (GetParam() == "ply") {
    // Binary: the header, then the doubles x y z of each vertex as they are.
    std::ifstream in(path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string header =
        "ply\nformat binary_little_endian 1.0\ncomment written by msdeform\nelement vertex 50\n"
        "property double x\nproperty double y\nproperty double z\nelement face 40\n"
        "property list uchar int vertex_indices\nend_header\n";
    ASSERT_EQ(bytes.substr(0, header.size()), header);
    ASSERT_EQ(bytes.size(), header.size() + 50 * 24 + 40 * 13);
    EXPECT_EQ(std::memcmp(bytes.data() + header.size(), mesh.vertices.data(), 50 * 24), 0);
    return;
  }
  std::ifstream in(path);
  std::string line;
  std::vector<double> coordinates;
  int header_lines = GetParam() == "off" ? 2 : GetParam() == "obj" ? 1 : 0;
  while (std::getline(in, line) && static_cast<int>(coordinates.size()) < 3 * 50) {
    if (header_lines > 0) {
      --header_lines;
      continue;
    }
    std::istringstream fields(GetParam() == "obj" ? line.substr(2) : line);
    std::string field;
    while (fields >> field) coordinates.push_back(std::strtod(field.c_str(), nullptr));
  }
  ASSERT_EQ(coordinates.size(), 3u * 50u);
  for (int v = 0; v < 50; ++v) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(coordinates[3 * v + k], mesh.vertices(k, v));
  }
}

INSTANTIATE_TEST_SUITE_P(Formats, MeshRoundTripTest, testing::Values("off", "obj", "ply"));

// Edge (0, 1) is shared by three triangles, vertex 5 is a bowtie (two fans
// touching only there), and vertex 10 is used by no face. A halfedge mesh
// would drop a face or duplicate vertices here.
constexpr char kNonManifoldOff[] =
    "OFF\n"
    "11 5 0\n"
    "0 0 0\n1 0 0\n0.5 1 0\n0.5 -1 0\n0.5 0 1\n"
    "5 0 0\n6 1 0\n6 -1 0\n4 1 0\n4 -1 0\n"
    "9 9 9\n"
    "3 0 1 2\n3 1 0 3\n3 0 1 4\n3 5 6 7\n3 5 8 9\n";

TEST(MeshIoTest, NonManifoldOffKeepsEveryVertexAndFace) {
  const std::string folder = FreshFolder();
  const std::string path = folder + "/nonmanifold.off";
  WriteText(path, kNonManifoldOff);
  Mesh mesh;
  std::string error;
  ASSERT_TRUE(ReadMesh(path, &mesh, &error)) << error;
  EXPECT_EQ(mesh.num_vertices(), 11);
  Eigen::Matrix3Xi expected(3, 5);
  expected << 0, 1, 0, 5, 5,  //
      1, 0, 1, 6, 8,          //
      2, 3, 4, 7, 9;
  EXPECT_EQ(mesh.faces, expected);
  EXPECT_EQ(mesh.vertices.col(10), Eigen::Vector3d(9, 9, 9));

  // And it writes back unchanged.
  const std::string copy = folder + "/copy.ply";
  ASSERT_TRUE(WriteMesh(copy, mesh, &error)) << error;
  Mesh read;
  ASSERT_TRUE(ReadMesh(copy, &read, &error)) << error;
  EXPECT_EQ(read.vertices, mesh.vertices);
  EXPECT_EQ(read.faces, mesh.faces);
}

TEST(MeshIoTest, PolygonsAreSplitIntoFans) {
  const std::string path = FreshFolder() + "/polygons.off";
  WriteText(path,
            "OFF\n6 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n2 1 0\n"
            "4 0 1 2 3\n"
            "5 1 4 5 2 3\n");
  Mesh mesh;
  std::string error;
  ASSERT_TRUE(ReadMesh(path, &mesh, &error)) << error;
  Eigen::Matrix3Xi expected(3, 5);
  expected << 0, 0, 1, 1, 1,  //
      1, 2, 4, 5, 2,          //
      2, 3, 5, 2, 3;
  EXPECT_EQ(mesh.faces, expected);
}

TEST(MeshIoTest, ReadsCommentedCoffWithColorsAndBlankLines) {
  // Laid out like CGAL's data/meshes/mesh_with_colors.off.
  const std::string path = FreshFolder() + "/colored.off";
  WriteText(path,
            "# a comment\n"
            "#another\n"
            "COFF\n"
            "4 2 0\n"
            "\n"
            "-1 -1 0 0.9 0.0 0.0 #red\n"
            "1 -1 0 0 0 0.9\n"
            "\n"
            "1 1 0 255 0 0 255\n"
            "-1 1 0.5 0 0 255 255   # blue\n"
            "3 0 1 2  0.9 0 0 # face colour\n"
            "3 0 2 3\n");
  Mesh mesh;
  std::string error;
  ASSERT_TRUE(ReadMesh(path, &mesh, &error)) << error;
  ASSERT_EQ(mesh.num_vertices(), 4);
  EXPECT_EQ(mesh.vertices.col(3), Eigen::Vector3d(-1, 1, 0.5));
  Eigen::Matrix3Xi expected(3, 2);
  expected << 0, 0,  //
      1, 2,          //
      2, 3;
  EXPECT_EQ(mesh.faces, expected);
}

TEST(MeshIoTest, ReadsPlainCoffAndCountsOnTheHeaderLine) {
  const std::string folder = FreshFolder();
  const std::string coff = folder + "/plain.off";
  WriteText(coff,
            "COFF\n3 1 0\n0 0 0 192 192 192 255\n1 0 0 192 192 192 255\n"
            "0 2 0 192 192 192 255\n3 0 1 2\n");
  const std::string one_line = folder + "/one_line.off";
  WriteText(one_line, "OFF 3 1 0\n0 0 0\n1 0 0\n0 2 0\n3 0 1 2\n");
  for (const std::string& path : {coff, one_line}) {
    Mesh mesh;
    std::string error;
    ASSERT_TRUE(ReadMesh(path, &mesh, &error)) << error;
    EXPECT_EQ(mesh.num_vertices(), 3) << path;
    EXPECT_EQ(mesh.vertices.col(2), Eigen::Vector3d(0, 2, 0)) << path;
    EXPECT_EQ(mesh.num_faces(), 1) << path;
  }
}

TEST(MeshIoTest, ReadsFaceColoursUnderAPlainOffHeader) {
  // Like CGAL's quint_tris.off: OpenMesh alone would read ".7" as the next
  // face's vertex count.
  const std::string path = FreshFolder() + "/face_colours.off";
  WriteText(path,
            "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
            "3 0 1 2 .7 0 0\n"
            "3 0 2 3 .7 0 0\n");
  Mesh mesh;
  std::string error;
  ASSERT_TRUE(ReadMesh(path, &mesh, &error)) << error;
  Eigen::Matrix3Xi expected(3, 2);
  expected << 0, 0,  //
      1, 2,          //
      2, 3;
  EXPECT_EQ(mesh.faces, expected);
}

TEST(MeshIoTest, BinaryOffReadsAndTruncationIsCaught) {
  // OpenMesh's binary OFF layout: little-endian int32 counts and ids, float32
  // coordinates.
  std::string bytes = "OFF BINARY\n";
  auto append = [&bytes](const auto& value) {
    bytes.append(reinterpret_cast<const char*>(&value), sizeof(value));
  };
  for (int32_t count : {4, 2, 0}) append(count);
  for (float coordinate : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 1.f, 1.f, 0.f, 0.f, 1.f, 0.25f}) {
    append(coordinate);
  }
  for (int32_t id : {3, 0, 1, 2, 3, 0, 2, 3}) append(id);
  const std::string folder = FreshFolder();
  WriteText(folder + "/binary.off", bytes);
  Mesh mesh;
  std::string error;
  ASSERT_TRUE(ReadMesh(folder + "/binary.off", &mesh, &error)) << error;
  EXPECT_EQ(mesh.vertices.col(3), Eigen::Vector3d(0, 1, 0.25));
  Eigen::Matrix3Xi expected(3, 2);
  expected << 0, 0,  //
      1, 2,          //
      2, 3;
  EXPECT_EQ(mesh.faces, expected);

  WriteText(folder + "/short.off", bytes.substr(0, bytes.size() - 8));
  EXPECT_FALSE(ReadMesh(folder + "/short.off", &mesh, &error));
  EXPECT_NE(error.find("short.off: truncated"), std::string::npos) << error;
}

TEST(MeshIoTest, ExtensionIsCaseInsensitive) {
  const std::string path = FreshFolder() + "/SHOUT.OFF";
  WriteText(path, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  Mesh mesh;
  std::string error;
  ASSERT_TRUE(ReadMesh(path, &mesh, &error)) << error;
  EXPECT_EQ(mesh.num_faces(), 1);
}

TEST(MeshIoTest, ReadsObjWithTextureAndNormalIndices) {
  const std::string path = FreshFolder() + "/textured.obj";
  WriteText(path,
            "# comment\n"
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
            "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
            "vn 0 0 1\n"
            "f 1/1/1 2/2/1 3/3/1 4/4/1\n");
  Mesh mesh;
  std::string error;
  ASSERT_TRUE(ReadMesh(path, &mesh, &error)) << error;
  EXPECT_EQ(mesh.num_vertices(), 4);
  Eigen::Matrix3Xi expected(3, 2);
  expected << 0, 0,  //
      1, 2,          //
      2, 3;
  EXPECT_EQ(mesh.faces, expected);
}

// Two facets of a unit square sharing the edge (1,0,0)-(0,1,0).
constexpr float kStlTriangles[2][3][3] = {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
                                          {{1, 0, 0}, {1, 1, 0}, {0, 1, 0}}};

TEST(MeshIoTest, AsciiStlIsWeldedToSharedVertices) {
  const std::string path = FreshFolder() + "/square.stl";
  std::ostringstream text;
  text << "solid square\n";
  for (const auto& triangle : kStlTriangles) {
    text << "  facet normal 0 0 1\n    outer loop\n";
    for (const auto& p : triangle)
      text << "      vertex " << p[0] << " " << p[1] << " " << p[2] << "\n";
    text << "    endloop\n  endfacet\n";
  }
  text << "endsolid square\n";
  WriteText(path, text.str());
  Mesh mesh;
  std::string error;
  ASSERT_TRUE(ReadMesh(path, &mesh, &error)) << error;
  EXPECT_EQ(mesh.num_vertices(), 4);
  Eigen::Matrix3Xi expected(3, 2);
  expected << 0, 1,  //
      1, 3,          //
      2, 2;
  EXPECT_EQ(mesh.faces, expected);
  EXPECT_EQ(mesh.vertices.col(3), Eigen::Vector3d(1, 1, 0));
}

TEST(MeshIoTest, BinaryStlIsWeldedToSharedVertices) {
  const std::string path = FreshFolder() + "/square_binary.stl";
  std::string bytes(80, ' ');
  const uint32_t count = 2;
  bytes.append(reinterpret_cast<const char*>(&count), 4);
  for (const auto& triangle : kStlTriangles) {
    const float normal[3] = {0, 0, 1};
    bytes.append(reinterpret_cast<const char*>(normal), 12);
    for (const auto& p : triangle) bytes.append(reinterpret_cast<const char*>(p), 12);
    bytes.append(2, '\0');
  }
  WriteText(path, bytes);
  Mesh mesh;
  std::string error;
  ASSERT_TRUE(ReadMesh(path, &mesh, &error)) << error;
  EXPECT_EQ(mesh.num_vertices(), 4);
  EXPECT_EQ(mesh.num_faces(), 2);
  EXPECT_EQ(mesh.faces(1, 0), mesh.faces(0, 1)) << "shared vertex (1,0,0) is merged";
}

// Five vertices; faces: (0,1,2), (0,0,3) repeats a vertex, (1,3,2),
// (2,0,1) repeats (0,1,2) in the same cyclic order, (3,4,4) repeats a vertex
// (and is the only face of vertex 4), (0,2,1) is (0,1,2) turned over.
const std::vector<std::vector<int>> kFacesWithDrops = {{0, 1, 2}, {0, 0, 3}, {1, 3, 2},
                                                       {2, 0, 1}, {3, 4, 4}, {0, 2, 1}};
constexpr double kFiveVertices[5][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0.5}, {2, 2, 2}};

// The file extension of a MeshText format.
std::string Extension(const std::string& format) {
  return format == "binary_ply" ? "ply" : format;
}

// The five vertices and `faces` as the text of an .off, .obj or .ply file, or
// ("binary_ply") a binary little-endian PLY with a normal and a colour per
// vertex beside the float coordinates and int16 ids in uint8-counted lists.
std::string MeshText(const std::string& format, const std::vector<std::vector<int>>& faces) {
  std::ostringstream text;
  if (format == "binary_ply") {
    text << "ply\nformat binary_little_endian 1.0\nelement vertex 5\nproperty float nx\n"
            "property float x\nproperty float y\nproperty float z\nproperty uchar red\n"
            "property float ny\nproperty double nz\nelement face "
         << faces.size() << "\nproperty list uint8 short vertex_indices\nend_header\n";
    const auto put = [&text](auto value) {
      text.write(reinterpret_cast<const char*>(&value), sizeof(value));
    };
    for (const auto& p : kFiveVertices) {
      put(0.5f);
      for (double c : p) put(static_cast<float>(c));
      put(static_cast<unsigned char>(200));
      put(0.25f);
      put(-1.0);
    }
    for (const auto& face : faces) {
      put(static_cast<unsigned char>(face.size()));
      for (int id : face) put(static_cast<int16_t>(id));
    }
    return text.str();
  }
  if (format == "off") text << "OFF\n5 " << faces.size() << " 0\n";
  if (format == "ply") {
    text << "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
            "property float z\nelement face "
         << faces.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
  }
  for (const auto& p : kFiveVertices) {
    text << (format == "obj" ? "v " : "") << p[0] << " " << p[1] << " " << p[2] << "\n";
  }
  for (const auto& face : faces) {
    text << (format == "obj" ? "f" : std::to_string(face.size()));
    for (int id : face) text << " " << (format == "obj" ? id + 1 : id);
    text << "\n";
  }
  return text.str();
}

class DroppedFacesTest : public testing::TestWithParam<std::string> {};

TEST_P(DroppedFacesTest, RepeatedVertexAndDuplicateFacesAreDroppedAndCounted) {
  const std::string path = FreshFolder() + "/drops." + Extension(GetParam());
  WriteText(path, MeshText(GetParam(), kFacesWithDrops));
  Mesh mesh;
  MeshReadReport report;
  std::string error;
  ASSERT_TRUE(ReadMesh(path, &mesh, &report, &error)) << error;
  Eigen::Matrix3Xi expected(3, 3);
  expected << 0, 1, 0,  //
      1, 3, 2,          //
      2, 2, 1;
  EXPECT_EQ(mesh.faces, expected) << "the rest in file order; the turned-over copy stays";
  ASSERT_EQ(mesh.num_vertices(), 5) << "vertex 4, now in no face, stays";
  for (int v = 0; v < 5; ++v) {
    EXPECT_EQ(mesh.vertices.col(v),
              Eigen::Vector3d(kFiveVertices[v][0], kFiveVertices[v][1], kFiveVertices[v][2]));
  }
  EXPECT_EQ(report.dropped_degenerate_faces, 2);
  EXPECT_EQ(report.dropped_duplicate_faces, 1);
  EXPECT_EQ(report.notice, path + ": dropped 2 faces that repeat a vertex and 1 duplicate face");

  // The old signature reads the same mesh.
  Mesh again;
  ASSERT_TRUE(ReadMesh(path, &again, &error)) << error;
  EXPECT_EQ(again.faces, expected);
}

TEST_P(DroppedFacesTest, NothingDroppedMeansNoNotice) {
  const std::string path = FreshFolder() + "/clean." + Extension(GetParam());
  WriteText(path, MeshText(GetParam(), {{0, 1, 2}, {1, 3, 2}, {0, 2, 1}, {2, 3, 4}}));
  Mesh mesh;
  MeshReadReport report;
  report.dropped_duplicate_faces = 7;  // stale values are reset
  report.notice = "stale";
  std::string error;
  ASSERT_TRUE(ReadMesh(path, &mesh, &report, &error)) << error;
  EXPECT_EQ(mesh.num_faces(), 4);
  EXPECT_EQ(report.dropped_degenerate_faces, 0);
  EXPECT_EQ(report.dropped_duplicate_faces, 0);
  EXPECT_EQ(report.notice, "");
}

TEST_P(DroppedFacesTest, OnlyDuplicatesGiveTheirOwnNotice) {
  const std::string path = FreshFolder() + "/duplicates." + Extension(GetParam());
  WriteText(path, MeshText(GetParam(), {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 1, 2}, {1, 3, 2}}));
  Mesh mesh;
  MeshReadReport report;
  std::string error;
  ASSERT_TRUE(ReadMesh(path, &mesh, &report, &error)) << error;
  Eigen::Matrix3Xi expected(3, 2);
  expected << 0, 1,  //
      1, 3,          //
      2, 2;
  EXPECT_EQ(mesh.faces, expected);
  EXPECT_EQ(report.dropped_degenerate_faces, 0);
  EXPECT_EQ(report.dropped_duplicate_faces, 3);
  EXPECT_EQ(report.notice, path + ": dropped 3 duplicate faces");
}

TEST_P(DroppedFacesTest, OnlyFacesThatRepeatAVertexIsAnError) {
  const std::string path = FreshFolder() + "/degenerate." + Extension(GetParam());
  WriteText(path, MeshText(GetParam(), {{0, 0, 1}, {2, 3, 3}, {4, 1, 4}}));
  Mesh mesh;
  MeshReadReport report;
  std::string error;
  EXPECT_FALSE(ReadMesh(path, &mesh, &report, &error));
  EXPECT_EQ(error, path +
                       ": no face left after dropping 3 faces that repeat a vertex; need at least "
                       "one triangle");
}

// A polygon that repeats a vertex keeps its area: (0, 1, 2, 0) is the triangle
// (0, 1, 2), and (0, 0, 1, 3, 2) the fan (0, 1, 3), (0, 3, 2); one fan triangle
// of each repeats a vertex.
TEST_P(DroppedFacesTest, PolygonsThatRepeatAVertexLoseOnlyTheirEmptyTriangles) {
  const std::string path = FreshFolder() + "/polygons." + Extension(GetParam());
  WriteText(path, MeshText(GetParam(), {{0, 1, 2, 0}, {0, 0, 1, 3, 2}}));
  Mesh mesh;
  MeshReadReport report;
  std::string error;
  ASSERT_TRUE(ReadMesh(path, &mesh, &report, &error)) << error;
  Eigen::Matrix3Xi expected(3, 3);
  expected << 0, 0, 0,  //
      1, 1, 3,          //
      2, 3, 2;
  EXPECT_EQ(mesh.faces, expected);
  EXPECT_EQ(report.dropped_degenerate_faces, 2);
  EXPECT_EQ(report.dropped_duplicate_faces, 0);
  EXPECT_EQ(report.notice, path + ": dropped 2 faces that repeat a vertex");
}

// The binary PLY read in the check's pass reads what the OpenMesh pass (with
// the check's exact coordinates) reads from the same mesh as ASCII PLY: the
// doubles, the faces in order.
TEST(MeshIoTest, BinaryPlyReadsAsTheSameAscii) {
  const std::string folder = FreshFolder();
  const Mesh mesh = RandomMesh(300, 500, 5);
  std::string error;
  ASSERT_TRUE(WriteMesh(folder + "/binary.ply", mesh, &error)) << error;
  std::ostringstream ascii;
  ascii << "ply\nformat ascii 1.0\nelement vertex 300\nproperty double x\nproperty double y\n"
           "property double z\nelement face 500\nproperty list uchar int vertex_indices\n"
           "end_header\n";
  ascii.precision(17);
  for (int v = 0; v < 300; ++v) {
    ascii << mesh.vertices(0, v) << " " << mesh.vertices(1, v) << " " << mesh.vertices(2, v)
          << "\n";
  }
  for (int f = 0; f < 500; ++f) {
    ascii << "3 " << mesh.faces(0, f) << " " << mesh.faces(1, f) << " " << mesh.faces(2, f) << "\n";
  }
  WriteText(folder + "/ascii.ply", ascii.str());
  Mesh binary_read, ascii_read;
  ASSERT_TRUE(ReadMesh(folder + "/binary.ply", &binary_read, &error)) << error;
  ASSERT_TRUE(ReadMesh(folder + "/ascii.ply", &ascii_read, &error)) << error;
  EXPECT_EQ(binary_read.vertices, ascii_read.vertices);
  EXPECT_EQ(binary_read.faces, ascii_read.faces);
  EXPECT_EQ(binary_read.faces, mesh.faces);
  EXPECT_EQ(binary_read.vertices, mesh.vertices);
}

TEST(MeshIoTest, BinaryPlyTruncationAndBadIdsAreCaught) {
  const std::string folder = FreshFolder();
  const std::string bytes = MeshText("binary_ply", {{0, 1, 2}, {1, 3, 2}});
  const size_t header = bytes.find("end_header\n") + 11;
  const size_t vertex_bytes = 4 * 4 + 1 + 4 + 8;
  std::string error;
  Mesh mesh;
  WriteText(folder + "/vertices.ply", bytes.substr(0, header + 2 * vertex_bytes + 5));
  EXPECT_FALSE(ReadMesh(folder + "/vertices.ply", &mesh, &error));
  EXPECT_EQ(error, folder + "/vertices.ply: truncated: the binary data ends in element 'vertex' 2 of 5");
  WriteText(folder + "/faces.ply", bytes.substr(0, bytes.size() - 2));
  EXPECT_FALSE(ReadMesh(folder + "/faces.ply", &mesh, &error));
  EXPECT_EQ(error, folder +
                       "/faces.ply: binary face 1: list count 3 is negative or runs past the end "
                       "of the file");
  std::string bad_id = bytes;
  bad_id[bad_id.size() - 2] = 9;  // the last id: 9 of 5 vertices
  WriteText(folder + "/bad_id.ply", bad_id);
  EXPECT_FALSE(ReadMesh(folder + "/bad_id.ply", &mesh, &error));
  EXPECT_EQ(error, folder + "/bad_id.ply: binary face 1: a vertex id is not in 0..4");
}

// A regular file is mapped, anything else read to its end: a mesh that comes
// through a named pipe reads as the same mesh as its file.
TEST(MeshIoTest, AMeshReadsTheSameFromAPipeAsFromItsFile) {
  const std::string folder = FreshFolder();
  std::string error;
  for (const char* extension : {".off", ".ply"}) {
    SCOPED_TRACE(extension);
    const std::string file = folder + "/mesh" + extension;
    const std::string pipe = folder + "/pipe" + extension;
    ASSERT_TRUE(WriteMesh(file, SmallMesh(), &error)) << error;
    std::ifstream in(file, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_EQ(::mkfifo(pipe.c_str(), 0600), 0) << std::strerror(errno);
    std::thread writer([&pipe, &bytes] {
      std::ofstream out(pipe, std::ios::binary);
      out << bytes;
    });
    Mesh from_file, from_pipe;
    const bool read = ReadMesh(pipe, &from_pipe, &error);
    writer.join();
    ASSERT_TRUE(read) << error;
    ASSERT_TRUE(ReadMesh(file, &from_file, &error)) << error;
    EXPECT_EQ(from_pipe.vertices, from_file.vertices);
    EXPECT_EQ(from_pipe.faces, from_file.faces);
  }
}

// A mapped file has no terminating zero after its last byte, and when its
// size is a multiple of the page size the next byte is not mapped at all: a
// check that read one byte too far would crash there. Every mesh file of the
// bad-input corpus, whole and cut after each of its first 4096 bytes, is
// checked lying right before an inaccessible page; each refusal is one line.
TEST(MeshIoTest, ChecksReadNothingPastTheEndOfTheirBytes) {
  using Check = bool (*)(std::string_view, FormatCheck*, std::string*);
  const std::vector<std::pair<std::string, Check>> checks = {
      {".off", CheckOff}, {".obj", CheckObj}, {".ply", CheckPly}, {".stl", CheckStl}};
  const size_t page = static_cast<size_t>(::sysconf(_SC_PAGESIZE));
  const size_t room = 64 * page;  // the largest corpus file is under 20 KB
  char* region = static_cast<char*>(
      ::mmap(nullptr, room + page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0));
  ASSERT_NE(region, MAP_FAILED);
  ASSERT_EQ(::mprotect(region + room, page, PROT_NONE), 0);
  int files = 0;
  for (const auto& entry : fs::directory_iterator(SourceTreePath("tests/data/bad"))) {
    const std::string extension = entry.path().extension().string();
    const auto check = std::find_if(checks.begin(), checks.end(),
                                    [&](const auto& c) { return c.first == extension; });
    if (check == checks.end() || !entry.is_regular_file()) continue;  // a folder named x.off
    ++files;
    std::ifstream in(entry.path(), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_LE(bytes.size(), room) << entry.path();
    for (size_t size = 0; size <= bytes.size(); size = size < 4096 ? size + 1 : bytes.size() + 1) {
      const size_t cut = std::min(size, bytes.size());
      char* at = region + room - cut;
      std::memcpy(at, bytes.data(), cut);
      FormatCheck found;
      std::string problem;
      if (!check->second(std::string_view(at, cut), &found, &problem)) {
        EXPECT_TRUE(!problem.empty() && problem.find('\n') == std::string::npos)
            << entry.path() << " cut at " << cut << ": " << problem;
      }
    }
  }
  ::munmap(region, room + page);
  EXPECT_GE(files, 40);  // the corpus: tests/data/bad/MANIFEST.tsv
}

// A binary little-endian PLY with double coordinates: the triangle
// (0,0,0) (1,0,0) (0,1,0), its first x replaced by `first_x`; the header
// announces `announced_faces` faces, of which the file holds the one.
std::string DoublePly(double first_x, long long announced_faces = 1) {
  std::ostringstream text;
  text << "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\n"
          "property double y\nproperty double z\nelement face "
       << announced_faces << "\nproperty list uchar int vertex_indices\nend_header\n";
  const auto put = [&text](auto value) {
    text.write(reinterpret_cast<const char*>(&value), sizeof(value));
  };
  for (double c : {first_x, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0}) put(c);
  put(static_cast<unsigned char>(3));
  for (int id : {0, 1, 2}) put(id);
  return text.str();
}

// The counts of a header are not trusted before the data is read: a short
// file that announces two billion faces gets its one-line message (not an
// allocation of tens of gigabytes first), and what the readers reserve is
// bounded by what the rest of the file can hold.
TEST(MeshIoTest, HeaderCountsReserveNoMoreThanTheFileHolds) {
  EXPECT_EQ(ReservationFor(2000000000, 150, 13), 11u);
  EXPECT_EQ(ReservationFor(5, 150, 13), 5u);
  EXPECT_EQ(ReservationFor(0, 150, 13), 0u);
  EXPECT_EQ(ReservationFor(-1, 150, 13), 0u);
  EXPECT_EQ(ReservationFor(2000000000, size_t{1} << 40, 1), size_t{1} << 24);

  const std::string folder = FreshFolder();
  std::string error;
  Mesh mesh;
  WriteText(folder + "/faces.ply", DoublePly(0.0, 2000000000));
  EXPECT_FALSE(ReadMesh(folder + "/faces.ply", &mesh, &error));
  EXPECT_EQ(error, folder +
                       "/faces.ply: truncated: the binary data ends in element 'face' 1 of "
                       "2000000000");
  WriteText(folder + "/faces.off", "OFF\n3 2000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_FALSE(ReadMesh(folder + "/faces.off", &mesh, &error));
  EXPECT_EQ(error.rfind(folder + "/faces.off: truncated", 0), 0u) << error;
}

// Many triangles around one vertex (a fan, each listed twice, the copy
// rotated): the duplicates are found the same way in a large group.
TEST(MeshIoTest, DuplicatesInALargeFanAreDroppedInOrder) {
  const int kFan = 40;
  std::ostringstream off;
  off << "OFF\n" << kFan + 2 << " " << 2 * kFan << " 0\n0 0 0\n";
  for (int i = 0; i <= kFan; ++i) off << std::cos(0.1 * i) << " " << std::sin(0.1 * i) << " 0\n";
  for (int i = 1; i <= kFan; ++i) off << "3 0 " << i << " " << i + 1 << "\n";
  for (int i = kFan; i >= 1; --i) off << "3 " << i << " " << i + 1 << " 0\n";
  const std::string path = FreshFolder() + "/fan.off";
  WriteText(path, off.str());
  Mesh mesh;
  MeshReadReport report;
  std::string error;
  ASSERT_TRUE(ReadMesh(path, &mesh, &report, &error)) << error;
  EXPECT_EQ(report.dropped_duplicate_faces, kFan);
  ASSERT_EQ(mesh.num_faces(), kFan);
  for (int i = 1; i <= kFan; ++i) EXPECT_EQ(mesh.faces.col(i - 1), Eigen::Vector3i(0, i, i + 1));
}

INSTANTIATE_TEST_SUITE_P(Formats, DroppedFacesTest,
                         testing::Values("off", "obj", "ply", "binary_ply"));

// The unit square of kStlTriangles, then a facet with two corners at (1,0,0),
// the first facet again from its second corner, and the first facet turned
// over.
constexpr float kStlTrianglesWithDrops[5][3][3] = {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
                                                   {{1, 0, 0}, {1, 1, 0}, {0, 1, 0}},
                                                   {{0, 0, 0}, {1, 0, 0}, {1, 0, 0}},
                                                   {{1, 0, 0}, {0, 1, 0}, {0, 0, 0}},
                                                   {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}}};

TEST(MeshIoTest, StlFacetsThatCollapseOrRepeatAreDroppedAndCounted) {
  const std::string folder = FreshFolder();
  std::ostringstream ascii;
  ascii << "solid drops\n";
  std::string binary(80, ' ');
  const uint32_t count = 5;
  binary.append(reinterpret_cast<const char*>(&count), 4);
  for (const auto& triangle : kStlTrianglesWithDrops) {
    ascii << "  facet normal 0 0 1\n    outer loop\n";
    const float normal[3] = {0, 0, 1};
    binary.append(reinterpret_cast<const char*>(normal), 12);
    for (const auto& p : triangle) {
      ascii << "      vertex " << p[0] << " " << p[1] << " " << p[2] << "\n";
      binary.append(reinterpret_cast<const char*>(p), 12);
    }
    ascii << "    endloop\n  endfacet\n";
    binary.append(2, '\0');
  }
  ascii << "endsolid drops\n";
  WriteText(folder + "/ascii.stl", ascii.str());
  WriteText(folder + "/binary.stl", binary);
  for (const std::string name : {"ascii.stl", "binary.stl"}) {
    const std::string path = folder + "/" + name;
    Mesh mesh;
    MeshReadReport report;
    std::string error;
    ASSERT_TRUE(ReadMesh(path, &mesh, &report, &error)) << error;
    EXPECT_EQ(mesh.num_vertices(), 4) << name;
    Eigen::Matrix3Xi expected(3, 3);
    expected << 0, 1, 0,  //
        1, 3, 2,          //
        2, 2, 1;
    EXPECT_EQ(mesh.faces, expected) << name;
    EXPECT_EQ(report.dropped_degenerate_faces, 1) << name;
    EXPECT_EQ(report.dropped_duplicate_faces, 1) << name;
    EXPECT_EQ(report.notice, path + ": dropped 1 face that repeats a vertex and 1 duplicate face");
  }
}

struct BadFile {
  const char* name;      // file name, also the test name
  const char* contents;  // nullptr: do not create the file
  const char* expected;  // part of the error message
};

void PrintTo(const BadFile& bad, std::ostream* out) { *out << bad.name; }

class BadMeshFileTest : public testing::TestWithParam<BadFile> {};

TEST_P(BadMeshFileTest, FailsWithOneLineNamingTheFile) {
  const BadFile& bad = GetParam();
  const std::string path = FreshFolder() + "/" + bad.name;
  if (bad.contents != nullptr) WriteText(path, bad.contents);
  Mesh mesh;
  std::string error;
  EXPECT_FALSE(ReadMesh(path, &mesh, &error));
  EXPECT_NE(error.find(path), std::string::npos) << error;
  EXPECT_NE(error.find(bad.expected), std::string::npos) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
}

INSTANTIATE_TEST_SUITE_P(
    Errors, BadMeshFileTest,
    testing::Values(
        BadFile{"missing.off", nullptr, "no such file"}, BadFile{"empty.off", "", "empty"},
        BadFile{"empty.obj", "", "empty"},
        BadFile{"wrong_header.off", "PLY\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
                "line 1: expected an OFF header"},
        BadFile{"ply_header.ply", "PLX\nformat ascii 1.0\nend_header\n",
                "line 1: expected the PLY magic 'ply'"},
        BadFile{"truncated_faces.ply",
                "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                "property float z\nelement face 2\nproperty list uchar int vertex_indices\n"
                "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
                "the file ends in element 'face' 1 of 2"},
        BadFile{"nan.ply",
                "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                "end_header\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n",
                "line 11: 'nan' is not a finite number"},
        BadFile{"nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n",
                "line 2: vertex 1 coordinate 'nan' is not finite"},
        BadFile{"bad_counts.off", "OFF\n3 one 0\n", "line 2: expected three counts"},
        BadFile{"truncated_vertices.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n",
                "ends after 3 of 4 vertices"},
        BadFile{"truncated_faces.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
                "ends after 1 of 2 faces"},
        BadFile{"nan.off", "OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n",
                "line 4: vertex 1 coordinate 'nan' is not finite"},
        BadFile{"junk.off", "OFF\n3 1 0\n0 0 0\n1 x 0\n0 1 0\n3 0 1 2\n", "'x' is not a number"},
        BadFile{"out_of_range.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
                "line 6: face 0 refers to vertex 3, outside 0..2"},
        BadFile{"two_corner_face.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "at least 3"},
        BadFile{"out_of_range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 7\n",
                "face 1 refers to vertex 6, outside 0..2"},
        BadFile{"no_faces.obj", "v 0 0 0\nv 1 0 0\n", "need at least one triangle"},
        // OpenMesh's OBJ reader aborts on a corner without a vertex number
        // (found by tests/fuzz/obj_fuzzer).
        BadFile{"corner_without_vertex.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf /1 2/1 3/1\n",
                "line 5: face corner '/1' is not v, v/t, v//n or v/t/n"},
        BadFile{"corner_vertex_zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",
                "line 4: face corner '0'"},
        BadFile{"two_corner_face.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n",
                "line 3: a face has 2 vertices; need at least 3"},
        // Faces that repeat a vertex are dropped; none left is an error.
        BadFile{"all_faces_repeat_a_vertex.off",
                "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 1\n3 2 2 0\n",
                "no face left after dropping 2 faces that repeat a vertex; need at least one"},
        BadFile{"all_faces_repeat_a_vertex.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 2\n",
                "no face left after dropping 1 face that repeats a vertex"},
        BadFile{"truncated_facet.stl",
                "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n",
                "truncated: the file ends in facet 0"},
        BadFile{"nan.stl",
                "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 nan 0\n"
                "vertex 0 1 0\nendloop\nendfacet\nendsolid t\n",
                "line 5: facet 0: 'nan' is not a finite number"},
        // OpenMesh takes the three lines after any line holding "outer" as
        // corners: here "facet normal 0 0 1" and "outer loop".
        BadFile{"outer_in_the_name.stl",
                "solid outerwear\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                "vertex 0 1 0\nendloop\nendfacet\nendsolid outerwear\n",
                "line 2: facet 0: expected 'vertex x y z' (corner 0 after 'outer' on line 1)"},
        BadFile{"unknown.xyz", "0 0 0\n", "unknown mesh format '.xyz'"}),
    [](const testing::TestParamInfo<BadFile>& info) {
      std::string name = info.param.name;
      for (char& c : name) {
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      }
      return name;
    });

TEST(MeshIoTest, FailedWriteLeavesNoFile) {
  const std::string folder = FreshFolder();
  std::string error;
  // Unknown format.
  EXPECT_FALSE(WriteMesh(folder + "/out.stl", SmallMesh(), &error));
  EXPECT_NE(error.find("out.stl"), std::string::npos) << error;
  // Invalid mesh: a face id out of range.
  Mesh broken = SmallMesh();
  broken.faces(0, 0) = 99;
  EXPECT_FALSE(WriteMesh(folder + "/broken.off", broken, &error));
  EXPECT_NE(error.find("broken.off"), std::string::npos) << error;
  // Folder that does not exist.
  EXPECT_FALSE(WriteMesh(folder + "/no/such/folder/out.off", SmallMesh(), &error));
  EXPECT_NE(error.find("out.off"), std::string::npos) << error;
  EXPECT_TRUE(fs::is_empty(folder)) << "no output and no temporaries";
}

TEST(MeshIoTest, FailedWriteKeepsThePreviousFile) {
  const std::string path = FreshFolder() + "/keep.off";
  std::string error;
  ASSERT_TRUE(WriteMesh(path, SmallMesh(), &error)) << error;
  Mesh broken = SmallMesh();
  broken.vertices(0, 0) = std::nan("");
  EXPECT_FALSE(WriteMesh(path, broken, &error));
  Mesh read;
  ASSERT_TRUE(ReadMesh(path, &read, &error)) << error;
  EXPECT_EQ(read.vertices, SmallMesh().vertices);
}

}  // namespace
}  // namespace msdeform
