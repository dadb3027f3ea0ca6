// Tests of mesh reading and writing: round trips of every format and mode,
// the features of each reader, and the typed errors on bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "foldfill/error.h"
#include "foldfill/examples.h"
#include "foldfill/file.h"
#include "foldfill/io.h"
#include "test_support.h"

namespace foldfill {
namespace {

namespace fs = std::filesystem;

// Positions that need every digit to survive a text round trip.
Mesh double_mesh() {
  Mesh mesh;
  mesh.positions = {{0.1, 1e-300, -123456.789012345678},
                    {1.0 / 3.0, -0.0, 5e-324},
                    {1e300, -2.5, 0.2},
                    {std::nextafter(1.0, 2.0), 7.0, -1e-7}};
  mesh.faces = {{0, 1, 2}, {0, 2, 3}, {1, 3, 2}};
  return mesh;
}

// STL is float32: positions that are float32 values.
Mesh float_mesh() {
  Mesh mesh = double_mesh();
  for (Vec3& p : mesh.positions) {
    for (double& coordinate : p) coordinate = static_cast<float>(coordinate);
  }
  mesh.positions[2] = {1e30f, -2.5f, 0.2f};  // 1e300 has no float32 value
  return mesh;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

constexpr char kUtf8Bom[] = "\xEF\xBB\xBF";

void expect_same_mesh(const Mesh& expected, const Mesh& actual) {
  ASSERT_EQ(expected.positions.size(), actual.positions.size());
  for (size_t v = 0; v < expected.positions.size(); ++v) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_TRUE(same_bits(expected.positions[v][k], actual.positions[v][k]))
          << "vertex " << v << " coordinate " << k << ": " << expected.positions[v][k] << " vs "
          << actual.positions[v][k];
    }
  }
  EXPECT_EQ(expected.faces, actual.faces);
}

std::string write_bytes(const fs::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
  return path.string();
}

// Writes `bytes` to a fresh file `name`, reads it, and expects an Error of
// `kind` whose message names the file; returns the message.
std::string read_error(const std::string& name, const std::string& bytes, ErrorKind kind) {
  const std::string path = write_bytes(testing::scratch_dir("io_errors") / name, bytes);
  try {
    read_mesh(path);
  } catch (const Error& error) {
    EXPECT_EQ(static_cast<int>(kind), static_cast<int>(error.kind())) << error.what();
    EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
    EXPECT_EQ(std::string(error.what()).find('\n'), std::string::npos) << error.what();
    return error.what();
  }
  ADD_FAILURE() << name << ": no error";
  return {};
}

// ---------------------------------------------------------------- round trips

struct FormatCase {
  const char* extension;
  bool binary;
  bool float32;  // STL keeps float32 positions only
};

class RoundTrip : public ::testing::TestWithParam<FormatCase> {};

TEST_P(RoundTrip, PositionsAndFacesSurviveBitForBit) {
  const FormatCase& format_case = GetParam();
  const Mesh mesh = format_case.float32 ? float_mesh() : double_mesh();
  const fs::path dir = testing::scratch_dir(std::string("io_round_trip_") + format_case.extension +
                                            (format_case.binary ? "_bin" : "_ascii"));
  const std::string path = (dir / (std::string("mesh.") + format_case.extension)).string();
  write_mesh(mesh, path, {format_case.binary});
  const Mesh read = read_mesh(path);
  expect_same_mesh(mesh, read);

  const MeshFormat format = format_from_path(path);
  const std::string bytes = serialize_mesh(mesh, format, {format_case.binary});
  EXPECT_EQ(bytes, serialize_mesh(read, format, {format_case.binary}));
  expect_same_mesh(mesh, parse_mesh(bytes, format, path));
}

INSTANTIATE_TEST_SUITE_P(
    AllFormats, RoundTrip,
    ::testing::Values(FormatCase{"obj", true, false}, FormatCase{"ply", true, false},
                      FormatCase{"ply", false, false}, FormatCase{"off", true, false},
                      FormatCase{"stl", true, true}, FormatCase{"stl", false, true}));

TEST(Io, FormatFromPathIgnoresCase) {
  EXPECT_EQ(MeshFormat::Obj, format_from_path("a/B.OBJ"));
  EXPECT_EQ(MeshFormat::Ply, format_from_path("x.Ply"));
  EXPECT_EQ(MeshFormat::Off, format_from_path("x.off"));
  EXPECT_EQ(MeshFormat::Stl, format_from_path("x.sTl"));
  try {
    format_from_path("mesh.xyz");
    ADD_FAILURE() << "no error";
  } catch (const Error& error) {
    EXPECT_EQ(ErrorKind::Usage, error.kind());
    EXPECT_NE(std::string(error.what()).find("mesh.xyz"), std::string::npos);
  }
}

// ----------------------------------------------------------------------- OBJ

constexpr char kObjWithEverything[] =
    "# exported\r\n"
    "mtllib cloth.mtl\r\n"
    "o cloth\n"
    "g part\n"
    "s 1\n"
    "usemtl fabric\n"
    "\n"
    "v 0 0 0\r\n"
    "v 1 0 0\n"
    "v\t1 1 0\n"
    "v 0 1 0\n"
    "v 0.5 0.5 1 1.0\n"
    "vt 0 0\n"
    "vt 1 0 0\n"
    "vt 1 1\n"
    "vt 0.5\n"
    "vn 0 0 1\n"
    "l 1 2\n"
    "vp 0.1 0.2\n"
    "f 1/1/1 2/2/1 3/3/1 4/4/1\r\n"
    "f -5 -4 -1\n"
    "f 1//1 2//1 5//1   \n"
    "f 2/2 3/3 5/4\n";

TEST(Obj, ReadsAttributesPolygonsNegativeIndicesAndIgnoresTheRest) {
  const Mesh mesh = parse_mesh(kObjWithEverything, MeshFormat::Obj, "cloth.obj");
  ASSERT_EQ(5, mesh.vertex_count());
  EXPECT_EQ((Vec3{0.5, 0.5, 1}), mesh.positions[4]);
  EXPECT_EQ((std::vector<Vec2>{{0, 0}, {1, 0}, {1, 1}, {0.5, 0}}), mesh.texcoords);
  EXPECT_EQ((std::vector<Vec3>{{0, 0, 1}}), mesh.normals);
  EXPECT_EQ((std::vector<Tri>{{0, 1, 2}, {0, 2, 3}, {0, 1, 4}, {0, 1, 4}, {1, 2, 4}}), mesh.faces);
  EXPECT_EQ((std::vector<Tri>{{0, 1, 2}, {0, 2, 3}, {-1, -1, -1}, {-1, -1, -1}, {1, 2, 3}}),
            mesh.face_texcoords);
  EXPECT_EQ((std::vector<Tri>{{0, 0, 0}, {0, 0, 0}, {-1, -1, -1}, {0, 0, 0}, {-1, -1, -1}}),
            mesh.face_normals);
}

TEST(Obj, AttributesSurviveWriting) {
  const Mesh mesh = parse_mesh(kObjWithEverything, MeshFormat::Obj, "cloth.obj");
  const Mesh read = parse_mesh(serialize_mesh(mesh, MeshFormat::Obj), MeshFormat::Obj, "out.obj");
  expect_same_mesh(mesh, read);
  EXPECT_EQ(mesh.texcoords, read.texcoords);
  EXPECT_EQ(mesh.normals, read.normals);
  EXPECT_EQ(mesh.face_texcoords, read.face_texcoords);
  EXPECT_EQ(mesh.face_normals, read.face_normals);
}

TEST(Obj, FaceAttributesStayEmptyWhenNoFaceHasThem) {
  const Mesh mesh = parse_mesh("vt 0 0\nvn 0 0 1\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
                               MeshFormat::Obj, "plain.obj");
  EXPECT_EQ(1u, mesh.faces.size());
  EXPECT_TRUE(mesh.face_texcoords.empty());
  EXPECT_TRUE(mesh.face_normals.empty());
}

TEST(Obj, SkipsAUtf8ByteOrderMark) {
  const Mesh mesh =
      parse_mesh(std::string(kUtf8Bom) + "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n",
                 MeshFormat::Obj, "bom.obj");
  EXPECT_EQ((std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}}), mesh.positions);
  EXPECT_EQ((std::vector<Tri>{{0, 1, 2}, {1, 3, 2}}), mesh.faces);
}

// ----------------------------------------------------------------------- PLY

// Builds binary PLY bodies in either byte order.
class PlyBody {
 public:
  explicit PlyBody(bool big_endian) : big_endian_(big_endian) {}
  template <class T>
  PlyBody& put(T value) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    const bool host_big = __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__;
    if (host_big != big_endian_) std::reverse(bytes, bytes + sizeof(T));
    bytes_.append(bytes, sizeof(T));
    return *this;
  }
  const std::string& bytes() const { return bytes_; }

 private:
  bool big_endian_;
  std::string bytes_;
};

constexpr char kPlyExtrasHeader[] =
    "ply\n"
    "format binary_big_endian 1.0\n"
    "comment made by hand\n"
    "obj_info anything\n"
    "element vertex 4\n"
    "property uchar red\n"
    "property float x\n"
    "property double y\n"
    "property int16 z\n"
    "property list uchar float weights\n"
    "property float32 nx\n"
    "element edge 1\n"
    "property int vertex1\n"
    "property list int uint8 stuff\n"
    "element nothing 9000000000000\n"
    "element face 2\n"
    "property uint flags\n"
    "property list uint8 uint32 vertex_indices\n"
    "property list uchar float texcoord\n"
    "end_header\n";

std::string ply_with_extras() {
  PlyBody body(true);
  const double ys[] = {0.1, -0.25, 1e-300, 3.0};
  for (int v = 0; v < 4; ++v) {
    body.put<uint8_t>(200).put<float>(0.5f * v).put<double>(ys[v]).put<int16_t>(-7 * v);
    body.put<uint8_t>(v % 3);
    for (int w = 0; w < v % 3; ++w) body.put<float>(1.0f);
    body.put<float>(0.0f);
  }
  body.put<int32_t>(3).put<int32_t>(2).put<uint8_t>(1).put<uint8_t>(2);
  body.put<uint32_t>(7).put<uint8_t>(3).put<uint32_t>(0).put<uint32_t>(1).put<uint32_t>(2);
  body.put<uint8_t>(0);
  body.put<uint32_t>(8).put<uint8_t>(4);
  for (uint32_t v : {0u, 1u, 2u, 3u}) body.put<uint32_t>(v);
  body.put<uint8_t>(2).put<float>(0.25f).put<float>(0.75f);
  return kPlyExtrasHeader + body.bytes();
}

TEST(Ply, BigEndianWithExtraPropertiesAndElements) {
  const Mesh mesh = parse_mesh(ply_with_extras(), MeshFormat::Ply, "extras.ply");
  ASSERT_EQ(4, mesh.vertex_count());
  EXPECT_EQ((Vec3{0.0, 0.1, 0.0}), mesh.positions[0]);
  EXPECT_EQ((Vec3{1.5, 3.0, -21.0}), mesh.positions[3]);
  EXPECT_TRUE(same_bits(1e-300, mesh.positions[2][1]));
  EXPECT_EQ((std::vector<Tri>{{0, 1, 2}, {0, 1, 2}, {0, 2, 3}}), mesh.faces);
}

TEST(Ply, AsciiWithOtherTypesAndExtras) {
  const std::string ply =
      "ply\r\n"
      "format ascii 1.0\r\n"
      "comment hello\r\n"
      "element vertex 3\r\n"
      "property int x\r\n"
      "property uchar y\r\n"
      "property float64 z\r\n"
      "property list uchar int junk\r\n"
      "element face 1\r\n"
      "property list int int vertex_index\r\n"
      "property float quality\r\n"
      "element material 1\r\n"
      "property float shine\r\n"
      "end_header\r\n"
      "1 2 0.5 2 9 9\r\n"
      "-3 255 1e-3 0\r\n"
      "0 0 0 1 4\r\n"
      "3 2 1 0 0.5\r\n"
      "0.75\r\n";
  const Mesh mesh = parse_mesh(ply, MeshFormat::Ply, "types.ply");
  EXPECT_EQ((std::vector<Vec3>{{1, 2, 0.5}, {-3, 255, 1e-3}, {0, 0, 0}}), mesh.positions);
  EXPECT_EQ((std::vector<Tri>{{2, 1, 0}}), mesh.faces);
}

// An ASCII PLY of 3 vertices with `vertex_properties` and one face, then `body`.
std::string ascii_ply(const std::string& vertex_properties, const std::string& body) {
  return "ply\nformat ascii 1.0\nelement vertex 3\n" + vertex_properties +
         "element face 1\nproperty list uchar int vertex_indices\nend_header\n" + body;
}

constexpr char kXyz[] = "property float x\nproperty float y\nproperty float z\n";
constexpr char kTriangleBody[] = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";

TEST(Ply, SkipsAUtf8ByteOrderMark) {
  const Mesh ascii =
      parse_mesh(kUtf8Bom + ascii_ply(kXyz, kTriangleBody), MeshFormat::Ply, "bom_ascii.ply");
  EXPECT_EQ((std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}), ascii.positions);
  EXPECT_EQ((std::vector<Tri>{{0, 1, 2}}), ascii.faces);
  const std::string binary = kUtf8Bom + serialize_mesh(double_mesh(), MeshFormat::Ply);
  expect_same_mesh(double_mesh(), parse_mesh(binary, MeshFormat::Ply, "bom_binary.ply"));
}

TEST(Ply, VertexNeedsExactlyOneScalarXYZ) {
  const std::string twice =
      read_error("x_twice.ply",
                 ascii_ply("property float x\nproperty float y\nproperty float x\n", kTriangleBody),
                 ErrorKind::BadFormat);
  EXPECT_NE(twice.find("two 'x' properties"), std::string::npos) << twice;
  const std::string missing = read_error(
      "no_z.ply", ascii_ply("property float x\nproperty float y\n", "0 0\n1 0\n0 1\n3 0 1 2\n"),
      ErrorKind::BadFormat);
  EXPECT_NE(missing.find("no 'z' property"), std::string::npos) << missing;
  const std::string list =
      read_error("list_y.ply",
                 ascii_ply("property float x\nproperty list uchar float y\nproperty float z\n",
                           "0 1 0 0\n1 1 0 0\n0 1 1 0\n3 0 1 2\n"),
                 ErrorKind::BadFormat);
  EXPECT_NE(list.find("'y'"), std::string::npos) << list;
}

TEST(Ply, RefusesAsciiDataBeyondTheDeclaredCounts) {
  const std::string message =
      read_error("extra_face.ply", ascii_ply(kXyz, std::string(kTriangleBody) + "3 0 2 1\n"),
                 ErrorKind::BadFormat);
  EXPECT_NE(message.find("line 14: data beyond the 1 face the header declares"), std::string::npos)
      << message;
  // Blank space after the last item is fine.
  const Mesh mesh = parse_mesh(ascii_ply(kXyz, std::string(kTriangleBody) + " \r\n\n\t"),
                               MeshFormat::Ply, "t.ply");
  EXPECT_EQ(1, mesh.face_count());
}

TEST(Ply, RefusesBinaryBytesBeyondTheLastElement) {
  const std::string ply = serialize_mesh(double_mesh(), MeshFormat::Ply);
  const std::string message = read_error("extra_bytes.ply", ply + "\n", ErrorKind::BadFormat);
  EXPECT_NE(message.find("1 byte beyond the 3 faces the header declares"), std::string::npos)
      << message;
  read_error("extra_face.ply", ply + ply.substr(ply.size() - 13), ErrorKind::BadFormat);
}

// ----------------------------------------------------------------------- OFF

TEST(Off, CountsOnHeaderLineCommentsColoursAndPolygons) {
  const std::string off =
      "# a comment first\n"
      "OFF 5 2 0\n"
      "0 0 0 # origin\n"
      "1 0 0\n"
      "1 1 0\n"
      "\n"
      "0 1 0\n"
      "0.5 0.5 1\n"
      "4 0 1 2 3 255 0 0\n"
      "3 0 1 4\n";
  const Mesh mesh = parse_mesh(off, MeshFormat::Off, "quad.off");
  EXPECT_EQ(5, mesh.vertex_count());
  EXPECT_EQ((std::vector<Tri>{{0, 1, 2}, {0, 2, 3}, {0, 1, 4}}), mesh.faces);
}

TEST(Off, ColouredVariantHeader) {
  const Mesh mesh =
      parse_mesh("COFF\n3 1 0\n0 0 0 1 0 0 1\n1 0 0 1 0 0 1\n0 1 0 1 0 0 1\n3 0 1 2\n",
                 MeshFormat::Off, "c.off");
  EXPECT_EQ(3, mesh.vertex_count());
  EXPECT_EQ((Vec3{1, 0, 0}), mesh.positions[1]);
}

TEST(Off, SkipsAUtf8ByteOrderMark) {
  const Mesh mesh = parse_mesh(std::string(kUtf8Bom) + "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
                               MeshFormat::Off, "bom.off");
  EXPECT_EQ(3, mesh.vertex_count());
  EXPECT_EQ((std::vector<Tri>{{0, 1, 2}}), mesh.faces);
}

TEST(Off, RefusesFacesBeyondTheDeclaredCount) {
  const std::string message =
      read_error("extra_face.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 2 1\n",
                 ErrorKind::BadFormat);
  EXPECT_NE(message.find("line 7: data beyond the 1 face the header declares"), std::string::npos)
      << message;
  // Comments and blank space after the last face are fine.
  const Mesh mesh = parse_mesh("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 # last\n\n# end\n  \n",
                               MeshFormat::Off, "comments.off");
  EXPECT_EQ(1, mesh.face_count());
}

// ----------------------------------------------------------------------- STL

// A binary STL of the given header (padded to 80 bytes) and facets.
std::string binary_stl(std::string header, const std::vector<std::array<float, 9>>& facets) {
  header.resize(80, ' ');
  PlyBody body(false);
  body.put<uint32_t>(static_cast<uint32_t>(facets.size()));
  for (const auto& corners : facets) {
    for (int i = 0; i < 3; ++i) body.put<float>(0.0f);
    for (float coordinate : corners) body.put<float>(coordinate);
    body.put<uint16_t>(0);
  }
  return header + body.bytes();
}

const std::vector<std::array<float, 9>> kTwoFacets = {{0, 0, 0, 1, 0, 0, 1, 1, 0},
                                                      {0, 0, 0, 1, 1, 0, 0, 1, 0}};

TEST(Stl, BinaryWeldsCorners) {
  const Mesh mesh = parse_mesh(binary_stl("two", kTwoFacets), MeshFormat::Stl, "two.stl");
  EXPECT_EQ((std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}), mesh.positions);
  EXPECT_EQ((std::vector<Tri>{{0, 1, 2}, {0, 2, 3}}), mesh.faces);
}

TEST(Stl, BinaryWhoseHeaderStartsWithSolid) {
  const Mesh mesh =
      parse_mesh(binary_stl("solid but binary", kTwoFacets), MeshFormat::Stl, "s.stl");
  EXPECT_EQ(4, mesh.vertex_count());
  EXPECT_EQ(2, mesh.face_count());
}

TEST(Stl, AsciiWeldsCorners) {
  const std::string stl =
      "solid square\n"
      " facet normal 0 0 1\n  outer loop\n"
      "   vertex 0 0 0\n   vertex 1 0 0\n   vertex 1 1 0\n"
      "  endloop\n endfacet\n"
      " facet normal 0 0 1\n  outer loop\n"
      "   vertex 0 0 0\n   vertex 1 1 0\n   vertex 0 1 0\n"
      "  endloop\n endfacet\n"
      "endsolid square\n";
  const Mesh mesh = parse_mesh(stl, MeshFormat::Stl, "square.stl");
  EXPECT_EQ(4, mesh.vertex_count());
  EXPECT_EQ((std::vector<Tri>{{0, 1, 2}, {0, 2, 3}}), mesh.faces);
}

// The ASCII STL of `facets`, each corner written with `number` (as text).
std::string ascii_stl(const std::vector<std::array<std::string, 9>>& facets) {
  std::string out = "solid grid\n";
  for (const auto& corners : facets) {
    out += " facet normal 0 0 1\n  outer loop\n";
    for (int k = 0; k < 3; ++k) {
      out += "   vertex " + corners[3 * k] + " " + corners[3 * k + 1] + " " + corners[3 * k + 2] +
             "\n";
    }
    out += "  endloop\n endfacet\n";
  }
  return out + "endsolid grid\n";
}

// The 8 facets of a 3 x 3 grid over x, y in {-1, 0, 1} at z = 0, where every
// zero coordinate is -0 in odd facets and +0 in even ones.
std::vector<std::array<float, 9>> signed_zero_grid() {
  std::vector<std::array<float, 9>> facets;
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 2; ++j) {
      const float x0 = i - 1.0f, x1 = i + 0.0f, y0 = j - 1.0f, y1 = j + 0.0f;
      facets.push_back({x0, y0, 0, x1, y0, 0, x1, y1, 0});
      facets.push_back({x0, y0, 0, x1, y1, 0, x0, y1, 0});
    }
  }
  for (size_t f = 0; f < facets.size(); ++f) {
    for (float& coordinate : facets[f]) {
      if (coordinate == 0) coordinate = f % 2 ? -0.0f : 0.0f;
    }
  }
  return facets;
}

TEST(Stl, WeldsPlusAndMinusZeroByValue) {
  const auto facets = signed_zero_grid();
  std::vector<std::array<std::string, 9>> text_facets;
  for (const auto& corners : facets) {
    text_facets.emplace_back();
    for (int k = 0; k < 9; ++k) {
      text_facets.back()[k] = std::signbit(corners[k]) && corners[k] == 0
                                  ? "-0.0"
                                  : std::to_string(static_cast<int>(corners[k]));
    }
  }
  for (const std::string& stl : {binary_stl("grid", facets), ascii_stl(text_facets)}) {
    const Mesh mesh = parse_mesh(stl, MeshFormat::Stl, "grid.stl");
    EXPECT_EQ(9, mesh.vertex_count());
    EXPECT_EQ(8, mesh.face_count());
    // Each vertex keeps the bits of its first corner: (0, 0) that of facet 0
    // (+0), (-1, 0) that of facet 1 (-0).
    for (const Vec3& p : mesh.positions) {
      if (p[0] == 0 && p[1] == 0) {
        EXPECT_FALSE(std::signbit(p[0]) || std::signbit(p[1]));
      }
      if (p[0] == -1 && p[1] == 0) {
        EXPECT_TRUE(std::signbit(p[1]) && std::signbit(p[2]));
      }
    }
  }
}

TEST(Stl, NonFiniteCornersEndAsNonFiniteCoordinate) {
  // NaNs never compare equal: every one of them, whatever its payload or sign,
  // must still end in a clean error.
  auto facets = signed_zero_grid();
  const uint32_t specials[] = {0x7fc00000u, 0xffc00000u, 0x7f800001u, 0xffffffffu,
                               0x7f800000u, 0xff800000u, 0x00000001u, 0x80000001u};
  for (size_t f = 0; f < facets.size(); ++f) {
    for (size_t k = 0; k < 9; ++k) {
      std::memcpy(&facets[f][k], &specials[(f + k) % 8], sizeof(float));
    }
  }
  read_error("specials.stl", binary_stl("specials", facets), ErrorKind::NonFiniteCoordinate);
  read_error("nan.stl",
             ascii_stl({{"nan", "0", "0", "-nan", "0", "0", "nan", "nan", "0"},
                        {"0", "0", "0", "1", "0", "0", "inf", "1", "0"}}),
             ErrorKind::NonFiniteCoordinate);
}

TEST(Stl, SkipsAUtf8ByteOrderMark) {
  const Mesh ascii =
      parse_mesh(kUtf8Bom + ascii_stl({{"0", "0", "0", "1", "0", "0", "1", "1", "0"},
                                       {"0", "0", "0", "1", "1", "0", "0", "1", "0"}}),
                 MeshFormat::Stl, "bom.stl");
  EXPECT_EQ(4, ascii.vertex_count());
  EXPECT_EQ(2, ascii.face_count());
  // A binary header is arbitrary bytes: one that starts with the mark stays binary.
  const Mesh binary = parse_mesh(binary_stl(std::string(kUtf8Bom) + "solid", kTwoFacets),
                                 MeshFormat::Stl, "bom_binary.stl");
  EXPECT_EQ(4, binary.vertex_count());
}

TEST(Stl, TruncatedBinaryWhoseHeaderStartsWithSolidReportsTheTruncation) {
  const std::string stl = binary_stl("solid but binary", kTwoFacets);
  const std::string message =
      read_error("solid_truncated.stl", stl.substr(0, stl.size() - 10), ErrorKind::BadFormat);
  EXPECT_NE(message.find("binary STL is truncated or padded: it claims 2 facets (184 bytes) but "
                         "has 174 bytes"),
            std::string::npos)
      << message;
  // Text that is neither: both readings are reported.
  const std::string typo =
      read_error("typo.stl",
                 "solid typo\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertx 1 0 0\n"
                 "   vertex 1 1 0\n  endloop\n endfacet\nendsolid typo\n",
                 ErrorKind::BadFormat);
  EXPECT_NE(typo.find("line 5: expected 'vertex', found 'vertx'"), std::string::npos) << typo;
  EXPECT_NE(typo.find("as binary STL"), std::string::npos) << typo;
}

// --------------------------------------------------------------------- errors

TEST(IoErrors, MissingFileOrDirectoryCannotBeRead) {
  const fs::path dir = testing::scratch_dir("io_missing");
  for (const fs::path& path : {dir / "absent.obj", dir / "folder.ply"}) {
    if (path.filename() == "folder.ply") fs::create_directory(path);
    try {
      read_mesh(path.string());
      ADD_FAILURE() << path << ": no error";
    } catch (const Error& error) {
      EXPECT_EQ(ErrorKind::CannotRead, error.kind()) << error.what();
      EXPECT_NE(std::string(error.what()).find(path.string()), std::string::npos);
    }
  }
}

TEST(IoErrors, EmptyOrBlankFiles) {
  for (const char* extension : {"obj", "ply", "off", "stl"}) {
    read_error(std::string("empty.") + extension, "", ErrorKind::BadFormat);
    read_error(std::string("blank.") + extension, " \n\t\r\n", ErrorKind::BadFormat);
  }
  read_error("comments.obj", "# nothing\n# here\n", ErrorKind::BadFormat);
  read_error("no_faces.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n", ErrorKind::BadFormat);
}

TEST(IoErrors, GarbageBytes) {
  std::mt19937 random(7);
  std::string garbage(2000, '\0');
  for (char& c : garbage) c = static_cast<char>(random() & 0xff);
  for (const char* extension : {"obj", "ply", "off", "stl"}) {
    read_error(std::string("garbage.") + extension, garbage, ErrorKind::BadFormat);
  }
  read_error("words.off", "hello world\n", ErrorKind::BadFormat);
  read_error("words.stl", "solid x\nfacet normal a b c\n", ErrorKind::BadFormat);
}

TEST(IoErrors, UnparsableNumbersGiveTheLine) {
  const std::string message =
      read_error("number.obj", "v 0 0 0\nv 1 0 0\nv 0 1,5 0\nf 1 2 3\n", ErrorKind::BadFormat);
  EXPECT_NE(message.find("line 3"), std::string::npos) << message;
  read_error("number.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0x\n3 0 1 2\n", ErrorKind::BadFormat);
}

TEST(IoErrors, UnsupportedHeaders) {
  read_error("format.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n",
             ErrorKind::BadFormat);
  read_error("type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n",
             ErrorKind::BadFormat);
  read_error("noend.ply", "ply\nformat ascii 1.0\nelement vertex 1\n", ErrorKind::BadFormat);
  read_error("four.off", "4OFF\n3 1 0\n0 0 0 0\n1 0 0 0\n0 1 0 0\n3 0 1 2\n", ErrorKind::BadFormat);
}

TEST(IoErrors, TruncatedBinaryFiles) {
  const std::string ply = serialize_mesh(double_mesh(), MeshFormat::Ply);
  read_error("truncated_end.ply", ply.substr(0, ply.size() - 3), ErrorKind::BadFormat);
  read_error("truncated_mid.ply", ply.substr(0, ply.size() - 60), ErrorKind::BadFormat);
  const std::string stl = serialize_mesh(float_mesh(), MeshFormat::Stl);
  read_error("truncated.stl", stl.substr(0, stl.size() - 10), ErrorKind::BadFormat);
  read_error("header_only.stl", stl.substr(0, 50), ErrorKind::BadFormat);
}

TEST(IoErrors, NonFiniteCoordinates) {
  const std::string message = read_error("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n",
                                         ErrorKind::NonFiniteCoordinate);
  EXPECT_NE(message.find("vertex 1 (line 2)"), std::string::npos) << message;
  read_error("inf.off", "OFF\n3 1 0\n0 0 0\n1 -inf 0\n0 1 0\n3 0 1 2\n",
             ErrorKind::NonFiniteCoordinate);
  read_error("overflow.obj", "v 0 0 1e999\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
             ErrorKind::NonFiniteCoordinate);
  std::string ply = serialize_mesh(double_mesh(), MeshFormat::Ply, {false});
  ply.replace(ply.find("1e+300"), 6, "inf");
  read_error("inf.ply", ply, ErrorKind::NonFiniteCoordinate);
  auto facets = kTwoFacets;
  facets[1][4] = std::numeric_limits<float>::quiet_NaN();
  read_error("nan.stl", binary_stl("nan", facets), ErrorKind::NonFiniteCoordinate);
}

TEST(IoErrors, FaceIndexOutOfRange) {
  const std::string message =
      read_error("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 57\n", ErrorKind::BadFace);
  EXPECT_NE(message.find("line 5: face vertex 56 out of range (mesh has 3 vertices; OBJ index 57)"),
            std::string::npos)
      << message;
  read_error("negative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", ErrorKind::BadFace);
  read_error("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", ErrorKind::BadFace);
  read_error("range.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", ErrorKind::BadFace);
  // serialize_mesh refuses such a mesh, so patch the bytes of a valid one.
  std::string ply = serialize_mesh(double_mesh(), MeshFormat::Ply);
  ply[ply.size() - 4 - 13] = 9;  // last index of the second face (little endian)
  read_error("range.ply", ply, ErrorKind::BadFace);
}

TEST(IoErrors, FaceWithTwoVertices) {
  read_error("two.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", ErrorKind::BadFace);
  read_error("two.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", ErrorKind::BadFace);
  read_error("two.ply",
             "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
             "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
             "end_header\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n",
             ErrorKind::BadFace);
}

TEST(IoErrors, FaceWithRepeatedVertex) {
  read_error("repeat.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 2\n", ErrorKind::BadFace);
  read_error("repeat.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 0\n", ErrorKind::BadFace);
  read_error("repeat.stl", binary_stl("x", {{0, 0, 0, 1, 0, 0, 1, 0, 0}}), ErrorKind::BadFace);
}

TEST(IoErrors, HugeClaimedCounts) {
  const char* vertex_header =
      "element vertex 4000000000\nproperty double x\nproperty double y\nproperty double z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  read_error("huge_binary.ply",
             std::string("ply\nformat binary_little_endian 1.0\n") + vertex_header + "0123456789",
             ErrorKind::BadFormat);
  read_error("huge_ascii.ply",
             std::string("ply\nformat ascii 1.0\n") + vertex_header + "0 0 0\n0 0 0\n",
             ErrorKind::BadFormat);
  read_error("huge_list.ply",
             "ply\nformat binary_little_endian 1.0\nelement face 1\n"
             "property list uint int vertex_indices\nend_header\n\xff\xff\xff\xff\x01",
             ErrorKind::BadFormat);
  read_error("huge.off", "OFF\n2000000000 2000000000 0\n0 0 0\n", ErrorKind::BadFormat);
  read_error("huge_faces.off", "OFF\n3 2000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
             ErrorKind::BadFormat);
  std::string stl = binary_stl("huge", kTwoFacets);
  stl.replace(80, 4, "\xff\xff\xff\x7f");
  read_error("huge.stl", stl, ErrorKind::BadFormat);
}

// `text` (ASCII) as UTF-16 with a byte order mark.
std::string utf16(const std::string& text, bool big_endian) {
  std::string out = big_endian ? "\xFE\xFF" : "\xFF\xFE";
  for (char c : text) {
    if (big_endian) out += '\0';
    out += c;
    if (!big_endian) out += '\0';
  }
  return out;
}

TEST(IoErrors, Utf16IsRefusedByName) {
  const std::pair<const char*, std::string> files[] = {
      {"utf16.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"},
      {"utf16.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
      {"utf16.ply", ascii_ply(kXyz, kTriangleBody)},
      {"utf16.stl", ascii_stl({{"0", "0", "0", "1", "0", "0", "1", "1", "0"}})}};
  for (const auto& [name, text] : files) {
    for (bool big_endian : {false, true}) {
      const std::string message = read_error(name, utf16(text, big_endian), ErrorKind::BadFormat);
      EXPECT_NE(message.find("UTF-16 text is not supported; save it as UTF-8 or ASCII"),
                std::string::npos)
          << message;
    }
  }
}

TEST(IoErrors, MessagesCountVerticesFromZeroAndLinesFromOne) {
  const auto expect_in = [](const std::string& message, const std::string& part) {
    EXPECT_NE(message.find(part), std::string::npos) << message;
  };
  expect_in(read_error("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n",
                       ErrorKind::NonFiniteCoordinate),
            "vertex 1 (line 2) has a non-finite coordinate");
  expect_in(read_error("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", ErrorKind::BadFace),
            "line 4: face vertex 3 out of range (mesh has 3 vertices; OBJ index 4)");
  expect_in(read_error("repeat.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 -1 3\n", ErrorKind::BadFace),
            "line 4: face repeats vertex 2 (OBJ index 3)");
  expect_in(read_error("nan.off", "OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n",
                       ErrorKind::NonFiniteCoordinate),
            "vertex 1 (line 4) has a non-finite coordinate");
  expect_in(
      read_error("range.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", ErrorKind::BadFace),
      "line 6: face vertex 3 out of range (mesh has 3 vertices)");
  expect_in(read_error("nan.ply", ascii_ply(kXyz, "0 0 0\n1 0 0\n0 nan 0\n3 0 1 2\n"),
                       ErrorKind::NonFiniteCoordinate),
            "vertex 2 (line 12) has a non-finite coordinate");
  std::string ply = serialize_mesh(double_mesh(), MeshFormat::Ply);
  ply[ply.size() - 4 - 13] = 9;  // last index of the second face (little endian)
  expect_in(read_error("range.ply", ply, ErrorKind::BadFace),
            "face 1: face vertex 9 out of range (mesh has 4 vertices)");
  expect_in(read_error("nan.stl",
                       ascii_stl({{"0", "0", "0", "1", "0", "0", "1", "1", "0"},
                                  {"0", "0", "0", "1", "1", "0", "nan", "1", "0"}}),
                       ErrorKind::NonFiniteCoordinate),
            "vertex 3 (line 13) has a non-finite coordinate");
  expect_in(
      read_error("repeat.stl", binary_stl("x", {{0, 0, 0, 1, 0, 0, 1, 0, 0}}), ErrorKind::BadFace),
      "face 0: face repeats vertex 1");
}

TEST(IoErrors, FractionalCountsAndIndicesNeedAnInteger) {
  const auto expect_integer_needed = [](const std::string& name, const std::string& bytes,
                                        const std::string& found) {
    const std::string message = read_error(name, bytes, ErrorKind::BadFormat);
    EXPECT_NE(message.find("an integer is needed, found '" + found + "'"), std::string::npos)
        << message;
  };
  expect_integer_needed("count.off", "OFF\n4.5 2 0\n0 0 0\n", "4.5");
  expect_integer_needed("index.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1.5 2\n", "1.5");
  expect_integer_needed("corners.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3e0 0 1 2\n", "3e0");
  expect_integer_needed("index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2.5 3\n", "2.5");
  expect_integer_needed("texcoord.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1.0 3/1\n",
                        "1.0");
  expect_integer_needed(
      "count.ply",
      "ply\nformat ascii 1.0\nelement vertex 3.5\n" + std::string(kXyz) + "end_header\n", "3.5");
  expect_integer_needed("index.ply", ascii_ply(kXyz, "0 0 0\n1 0 0\n0 1 0\n3 0 1 2.0\n"), "2.0");
}

TEST(IoErrors, CrOnlyLineEndsAreRefused) {
  const std::pair<const char*, std::string> files[] = {
      {"mac.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"},
      {"mac.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
      {"mac_ascii.ply", ascii_ply(kXyz, kTriangleBody)},
      {"mac_binary.ply", serialize_mesh(double_mesh(), MeshFormat::Ply)},
      {"mac.stl", ascii_stl({{"0", "0", "0", "1", "0", "0", "1", "1", "0"}})}};
  for (auto [name, bytes] : files) {
    // The text of the file, the header alone in a binary PLY, gets CR line ends.
    const size_t header_end = bytes.find("end_header\n");
    const size_t text_end = std::string(name) == "mac_binary.ply" ? header_end + 11 : bytes.size();
    std::replace(bytes.begin(), bytes.begin() + text_end, '\n', '\r');
    const std::string message = read_error(name, bytes, ErrorKind::BadFormat);
    EXPECT_NE(message.find("line ends are CR only (classic Mac text); convert them to LF"),
              std::string::npos)
        << message;
  }
}

// Every prefix of every valid file either parses or throws a typed Error.
TEST(IoErrors, EveryTruncationIsHandled) {
  for (MeshFormat format : {MeshFormat::Obj, MeshFormat::Ply, MeshFormat::Off, MeshFormat::Stl}) {
    for (bool binary : {true, false}) {
      const std::string bytes = serialize_mesh(float_mesh(), format, {binary});
      for (size_t size = 0; size < bytes.size(); ++size) {
        try {
          parse_mesh(std::string_view(bytes).substr(0, size), format, "prefix");
        } catch (const Error& error) {
          EXPECT_NE(ErrorKind::Internal, error.kind());
        }
      }
    }
  }
}

// --------------------------------------------------------------------- writes

TEST(IoWrite, MissingFolderThrowsCannotWriteAndLeavesNothing) {
  const fs::path dir = testing::scratch_dir("io_write_missing");
  const std::string path = (dir / "absent" / "mesh.obj").string();
  try {
    write_mesh(double_mesh(), path);
    ADD_FAILURE() << "no error";
  } catch (const Error& error) {
    EXPECT_EQ(ErrorKind::CannotWrite, error.kind());
    EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
  }
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(IoWrite, OntoAFolderThrowsCannotWriteAndLeavesNoTemporary) {
  const fs::path dir = testing::scratch_dir("io_write_onto_folder");
  fs::create_directory(dir / "taken.ply");
  try {
    write_mesh(double_mesh(), (dir / "taken.ply").string());
    ADD_FAILURE() << "no error";
  } catch (const Error& error) {
    EXPECT_EQ(ErrorKind::CannotWrite, error.kind());
  }
  EXPECT_EQ(1, std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

TEST(IoWrite, ReplacesTheFileAndLeavesNoTemporary) {
  const fs::path dir = testing::scratch_dir("io_write_replace");
  const std::string path = (dir / "mesh.off").string();
  write_bytes(path, "old content");
  write_mesh(double_mesh(), path);
  std::vector<fs::path> entries(fs::directory_iterator(dir), fs::directory_iterator{});
  ASSERT_EQ(1u, entries.size());
  EXPECT_EQ("mesh.off", entries[0].filename());
  expect_same_mesh(double_mesh(), read_mesh(path));
}

// Files are written in chunks of about 1 MiB as they are produced; the bytes
// must be those of the whole-string serializer, whatever the format.
TEST(IoWrite, LargeFilesWrittenInChunksEqualTheWholeSerialization) {
  FoldedSheetOptions options;
  options.edge_length = 0.02;  // 30k vertices, 60k faces: several chunks in every format
  const Mesh mesh = make_folded_sheet(options).mesh;
  const fs::path dir = testing::scratch_dir("io_write_chunks");
  for (const FormatCase& format_case :
       {FormatCase{"obj", true, false}, FormatCase{"ply", true, false},
        FormatCase{"ply", false, false}, FormatCase{"off", true, false},
        FormatCase{"stl", true, true}, FormatCase{"stl", false, true}}) {
    const std::string path =
        (dir /
         (std::string("large_") + (format_case.binary ? "bin." : "ascii.") + format_case.extension))
            .string();
    write_mesh(mesh, path, {format_case.binary});
    const std::string whole = serialize_mesh(mesh, format_from_path(path), {format_case.binary});
    EXPECT_GT(whole.size(), size_t{3} << 19) << path;  // more than one chunk
    EXPECT_EQ(whole, read_file(path)) << path;
  }
}

TEST(IoWrite, AFailingProducerLeavesNoFile) {
  const fs::path dir = testing::scratch_dir("io_write_producer_throws");
  const std::string path = (dir / "partial.bin").string();
  EXPECT_THROW(write_file_atomically(path,
                                     [](const ByteConsumer& write) {
                                       write(std::string(3 << 20, 'x'));
                                       throw InternalError("stopped halfway");
                                     }),
               Error);
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(IoWrite, RefusesAnInvalidMesh) {
  Mesh mesh = double_mesh();
  mesh.faces.push_back({0, 1, 7});
  const fs::path dir = testing::scratch_dir("io_write_invalid");
  EXPECT_THROW(write_mesh(mesh, (dir / "bad.stl").string()), Error);
  EXPECT_TRUE(fs::is_empty(dir));
}

}  // namespace
}  // namespace foldfill
