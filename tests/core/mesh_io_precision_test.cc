// ReadMesh reads coordinates exactly: the doubles msdeform writes come back bit
// for bit (OFF, OBJ, PLY), a float property (binary or ASCII PLY, STL) is the
// float widened to double, and a decimal beyond the double range is refused.

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <ostream>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include <gtest/gtest.h>

#include "msdeform/core/mesh_io.h"
#include "tests/test_util.h"

namespace msdeform {
namespace {

// Coordinates that a detour through float, or a decimal parser that is not
// correctly rounded, would change: decimals without a finite binary form,
// subnormals, the extremes of the double range, values beyond the float
// range, a negative zero.
constexpr double kAwkward[] = {
    0.1,
    1.0 / 3.0,
    -2.0 / 3.0,
    1e-300,
    -1.2345678901234567e-300,
    std::numeric_limits<double>::denorm_min(),
    std::numeric_limits<double>::min(),
    -2.2250738585072009e-308,  // the largest subnormal, negated
    1e300,
    -1.7976931348623157e308,  // -DBL_MAX
    3.4028235677973366e38,    // just above FLT_MAX
    1e39,
    -0.0,
    0.0,
    123456789.12345679,
    1.0000000000000002,  // 1 + DBL_EPSILON
    3.141592653589793,
    -9007199254740993.0,  // 2^53 + 1 rounds to 2^53: a plain integer-looking text
    1.401298464324817e-45,  // the float denorm_min, as a double
    0.30000000000000004,
    6.02214076e23,
};
constexpr int kNumAwkward = sizeof(kAwkward) / sizeof(kAwkward[0]);

// Nine vertices holding the awkward values (then 1, 2, 3, ...), and a fan of
// triangles over them.
Mesh AwkwardMesh() {
  Mesh mesh;
  mesh.vertices.resize(3, 9);
  for (int i = 0; i < 27; ++i) mesh.vertices.data()[i] = i < kNumAwkward ? kAwkward[i] : i;
  mesh.faces.resize(3, 7);
  for (int f = 0; f < 7; ++f) mesh.faces.col(f) << 0, f + 1, f + 2;
  return mesh;
}

// The awkward mesh with the values beyond the float range replaced by ones
// within it (1e38, -3e38), for the float properties.
Mesh FloatRangeAwkwardMesh() {
  Mesh mesh = AwkwardMesh();
  for (Eigen::Index i = 0; i < mesh.vertices.size(); ++i) {
    double& value = mesh.vertices.data()[i];
    if (std::abs(value) > std::numeric_limits<float>::max()) value = value > 0 ? 1e38 : -3e38;
  }
  return mesh;
}

// Empty when a and b hold the same bits, else the first difference.
std::string BitDifference(const Eigen::Matrix3Xd& read, const Eigen::Matrix3Xd& expected) {
  if (read.cols() != expected.cols()) return "different vertex counts";
  for (Eigen::Index i = 0; i < read.size(); ++i) {
    if (std::memcmp(read.data() + i, expected.data() + i, sizeof(double)) != 0) {
      std::ostringstream message;
      message.precision(17);
      message << "coordinate " << i << ": read " << read.data()[i] << " (" << std::hexfloat
              << read.data()[i] << std::defaultfloat << "), expected " << expected.data()[i]
              << " (" << std::hexfloat << expected.data()[i] << ")";
      return message.str();
    }
  }
  return "";
}

// WriteMesh then ReadMesh of `mesh` as `extension` gives it back bit for bit,
// and so does a second round trip of what was read.
void ExpectWriteThenReadIsTheIdentity(const Mesh& mesh, const std::string& extension) {
  const std::string folder = FreshFolder();
  const std::string path = folder + "/awkward." + extension;
  std::string error;
  ASSERT_TRUE(WriteMesh(path, mesh, &error)) << error;
  Mesh read;
  ASSERT_TRUE(ReadMesh(path, &read, &error)) << error;
  EXPECT_EQ(BitDifference(read.vertices, mesh.vertices), "");
  EXPECT_EQ(read.faces, mesh.faces);
  const std::string again = folder + "/again." + extension;
  ASSERT_TRUE(WriteMesh(again, read, &error)) << error;
  Mesh read_again;
  ASSERT_TRUE(ReadMesh(again, &read_again, &error)) << error;
  EXPECT_EQ(BitDifference(read_again.vertices, mesh.vertices), "");
}

class ExactRoundTripTest : public testing::TestWithParam<std::string> {};

// Both meshes: the one within the float range shows what a detour through
// float does to the values a float can hold at all.
TEST_P(ExactRoundTripTest, WriteThenReadIsTheIdentityBitForBit) {
  {
    SCOPED_TRACE("within the float range");
    ExpectWriteThenReadIsTheIdentity(FloatRangeAwkwardMesh(), GetParam());
  }
  SCOPED_TRACE("the whole double range");
  ExpectWriteThenReadIsTheIdentity(AwkwardMesh(), GetParam());
}

INSTANTIATE_TEST_SUITE_P(Formats, ExactRoundTripTest, testing::Values("off", "obj", "ply"));

// The shortest decimal that reads back as `value` (a double or a float).
template <typename Real>
std::string Shortest(Real value) {
  char buffer[32];
  const std::to_chars_result result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

// `mesh` as a PLY with coordinates of `type` ("float" or "double") in
// `format` ("ascii", "binary_little_endian", "binary_big_endian"); with
// `extra_element`, an element "edge" of no items after the faces (a layout
// the reader hands to OpenMesh rather than reading it in its own pass).
std::string PlyText(const Mesh& mesh, const std::string& format, const std::string& type,
                    bool extra_element) {
  std::ostringstream text;
  text << "ply\nformat " << format << " 1.0\nelement vertex " << mesh.num_vertices() << "\n";
  for (const char* axis : {"x", "y", "z"}) text << "property " << type << " " << axis << "\n";
  text << "element face " << mesh.num_faces() << "\nproperty list uchar int vertex_indices\n";
  if (extra_element) text << "element edge 0\nproperty int vertex1\n";
  text << "end_header\n";
  const bool big_endian = format == "binary_big_endian";
  const auto put = [&text, big_endian](auto value) {
    char bytes[sizeof(value)];
    std::memcpy(bytes, &value, sizeof(value));
    if (big_endian) std::reverse(bytes, bytes + sizeof(value));
    text.write(bytes, sizeof(value));
  };
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    for (int k = 0; k < 3; ++k) {
      const double value = mesh.vertices(k, v);
      if (format == "ascii") {
        // A float property's text is the float's shortest decimal.
        text << (type == "float" ? Shortest(static_cast<float>(value)) : Shortest(value))
             << (k < 2 ? " " : "\n");
      } else if (type == "float") {
        put(static_cast<float>(value));
      } else {
        put(value);
      }
    }
  }
  for (int f = 0; f < mesh.num_faces(); ++f) {
    if (format == "ascii") {
      text << "3 " << mesh.faces(0, f) << " " << mesh.faces(1, f) << " " << mesh.faces(2, f)
           << "\n";
      continue;
    }
    put(static_cast<unsigned char>(3));
    for (int c = 0; c < 3; ++c) put(static_cast<int32_t>(mesh.faces(c, f)));
  }
  return text.str();
}

struct PlyCase {
  const char* format;
  const char* type;
  bool extra_element;
};

void PrintTo(const PlyCase& ply, std::ostream* out) {
  *out << ply.format << " " << ply.type << (ply.extra_element ? " with an extra element" : "");
}

class PlyPropertyTest : public testing::TestWithParam<PlyCase> {};

// Double properties read as they are and float properties as the float
// widened exactly (0.1f is 0.100000001490116..., not 0.1), in every PLY
// encoding, through the reader's own pass (binary little-endian, vertex and
// face elements) and OpenMesh's (the others).
TEST_P(PlyPropertyTest, ReadsTheDoublesOrTheFloatsWidened) {
  const PlyCase& ply = GetParam();
  const bool is_float = std::string(ply.type) == "float";
  // A float property holds the float range only.
  std::vector<Mesh> meshes = {FloatRangeAwkwardMesh()};
  if (!is_float) meshes.push_back(AwkwardMesh());
  for (const Mesh& mesh : meshes) {
    const std::string path = FreshFolder() + "/awkward.ply";
    WriteText(path, PlyText(mesh, ply.format, ply.type, ply.extra_element));
    Mesh read;
    std::string error;
    ASSERT_TRUE(ReadMesh(path, &read, &error)) << error;
    const Eigen::Matrix3Xd expected =
        is_float ? Eigen::Matrix3Xd(mesh.vertices.cast<float>().cast<double>()) : mesh.vertices;
    EXPECT_EQ(BitDifference(read.vertices, expected), "");
    EXPECT_EQ(read.faces, mesh.faces);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Encodings, PlyPropertyTest,
    testing::Values(PlyCase{"binary_little_endian", "double", false},
                    PlyCase{"binary_little_endian", "float", false},
                    PlyCase{"binary_little_endian", "double", true},
                    PlyCase{"binary_little_endian", "float", true},
                    PlyCase{"binary_big_endian", "double", false},
                    PlyCase{"binary_big_endian", "float", false},
                    PlyCase{"ascii", "double", false}, PlyCase{"ascii", "float", false}),
    [](const testing::TestParamInfo<PlyCase>& info) {
      std::string name = std::string(info.param.format) + "_" + info.param.type +
                         (info.param.extra_element ? "_extra_element" : "");
      return name;
    });

// STL holds floats: a binary facet's floats and an ASCII facet's decimals
// read as the nearest float, widened exactly.
TEST(MeshIoPrecisionTest, StlReadsTheFloatsWidened) {
  const float corners[3][3] = {{0.1f, 1.0f / 3.0f, -0.0f},
                               {1e-40f, 3.4028235e38f, -2.0f / 3.0f},
                               {6.02214076e23f, 1.0f, 1.4e-45f}};
  Eigen::Matrix3Xd expected(3, 3);
  for (int c = 0; c < 3; ++c) {
    for (int k = 0; k < 3; ++k) expected(k, c) = corners[c][k];
  }
  const std::string folder = FreshFolder();
  std::string binary(80, ' ');
  const auto put = [&binary](auto value) {
    binary.append(reinterpret_cast<const char*>(&value), sizeof(value));
  };
  put(uint32_t{1});
  for (float n : {0.0f, 0.0f, 1.0f}) put(n);
  for (const auto& corner : corners) {
    for (float value : corner) put(value);
  }
  put(uint16_t{0});
  WriteText(folder + "/binary.stl", binary);
  // The ASCII decimals: each float's shortest text ("0.1", "0.33333334"),
  // which as a double is another number, so that the reader must round them
  // to the nearest float.
  std::ostringstream ascii;
  ascii << "solid t\nfacet normal 0 0 1\nouter loop\n";
  for (const auto& corner : corners) {
    ascii << "vertex " << Shortest(corner[0]) << " " << Shortest(corner[1]) << " "
          << Shortest(corner[2]) << "\n";
  }
  ascii << "endloop\nendfacet\nendsolid t\n";
  WriteText(folder + "/ascii.stl", ascii.str());
  for (const char* name : {"/binary.stl", "/ascii.stl"}) {
    SCOPED_TRACE(name);
    Mesh read;
    std::string error;
    ASSERT_TRUE(ReadMesh(folder + name, &read, &error)) << error;
    EXPECT_EQ(BitDifference(read.vertices, expected), "");
  }
}

// The triangle (x,0,0) (1,0,0) (0,1,0) as the text of an .off, .obj or ASCII
// .ply file, x written as `x`.
std::string TriangleText(const std::string& extension, const std::string& x) {
  if (extension == "off") return "OFF\n3 1 0\n" + x + " 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  if (extension == "obj") return "v " + x + " 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  return "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
         "property double z\nelement face 1\nproperty list uchar int vertex_indices\n"
         "end_header\n" +
         x + " 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
}

// Within the double range a decimal reads as strtod reads it, to the nearest
// double: 1e300 (which through float was infinite and refused) is 1e300, a
// decimal below the smallest subnormal is a zero of its sign. Beyond the
// double range it is refused with the line's message.
TEST(MeshIoPrecisionTest, DecimalsReadAsStrtodAndBeyondTheDoubleRangeAreRefused) {
  const std::string folder = FreshFolder();
  struct Case {
    const char* text;
    double value;
  };
  for (const std::string extension : {"off", "obj", "ply"}) {
    SCOPED_TRACE(extension);
    const std::string path = folder + "/t." + extension;
    for (const Case& c : {Case{"1e300", 1e300}, Case{"-1.7976931348623157e308", -1.7976931348623157e308},
                          Case{"1e-400", 0.0}, Case{"-1e-400", -0.0},
                          Case{"4e-324", std::numeric_limits<double>::denorm_min()},
                          Case{"0.1000000000000000055511151231257827", 0.1}}) {
      SCOPED_TRACE(c.text);
      WriteText(path, TriangleText(extension, c.text));
      Mesh read;
      std::string error;
      ASSERT_TRUE(ReadMesh(path, &read, &error)) << error;
      EXPECT_EQ(std::memcmp(&read.vertices(0, 0), &c.value, sizeof(double)), 0)
          << read.vertices(0, 0);
    }
    for (const char* text : {"1e309", "-2e308"}) {
      SCOPED_TRACE(text);
      WriteText(path, TriangleText(extension, text));
      Mesh read;
      std::string error;
      EXPECT_FALSE(ReadMesh(path, &read, &error));
      const std::string line = extension == "off" ? "3" : extension == "obj" ? "1" : "10";
      const std::string expected =
          extension == "ply" ? path + ": line 10: '" + text + "' is not a finite number"
                             : path + ": line " + line + ": vertex 0 coordinate '" + text +
                                   "' is not finite";
      EXPECT_EQ(error, expected);
    }
  }
  // A binary PLY holds doubles, so only an infinity or a NaN is beyond the
  // range; the mesh is refused as non-finite.
  for (double x : {std::numeric_limits<double>::infinity(), std::nan("")}) {
    Mesh triangle;
    triangle.vertices.resize(3, 3);
    triangle.vertices << x, 1, 0, 0, 0, 1, 0, 0, 0;
    triangle.faces.resize(3, 1);
    triangle.faces << 0, 1, 2;
    const std::string path = folder + "/inf.ply";
    WriteText(path, PlyText(triangle, "binary_little_endian", "double", false));
    Mesh read;
    std::string error;
    EXPECT_FALSE(ReadMesh(path, &read, &error));
    EXPECT_EQ(error, path + ": vertex 0 has a non-finite coordinate");
  }
}

// OpenMesh reads the PLY layouts msdeform does not read itself, and its
// stream input cannot take an ASCII value beyond the float range (it read the
// rest of the file out of step): such a value is refused with its line.
TEST(MeshIoPrecisionTest, AsciiPlyBeyondTheFloatRangeInOpenMeshsLayoutIsRefused) {
  Mesh mesh = AwkwardMesh();
  const std::string path = FreshFolder() + "/extra.ply";
  WriteText(path, PlyText(mesh, "ascii", "double", /*extra_element=*/true));
  Mesh read;
  std::string error;
  EXPECT_FALSE(ReadMesh(path, &read, &error));
  // kAwkward[8] = 1e300, vertex 2's z, is the first value beyond the float
  // range; the header takes 11 lines, so vertex 2 is on line 14.
  EXPECT_EQ(error, path + ": line 14: '1e+300' is beyond the float range, which OpenMesh's "
                          "reader of this PLY layout cannot take; keep only a vertex and a face "
                          "element");
  // Within the float range the same layout reads exactly.
  WriteText(path, PlyText(FloatRangeAwkwardMesh(), "ascii", "double", true));
  ASSERT_TRUE(ReadMesh(path, &read, &error)) << error;
  EXPECT_EQ(BitDifference(read.vertices, FloatRangeAwkwardMesh().vertices), "");
}

}  // namespace
}  // namespace msdeform
