// What comes in besides the geometry comes out again, and what a fill adds is
// marked: PLY properties (colours, normals, custom scalars) in their own
// types, OBJ groups, materials and smoothing groups, the marks of new
// elements (PLY `foldfill_hole`, OBJ `g foldfill_hole_<id>`) and the report's
// ranges of them, through the library and through the CLI.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "foldfill/examples.h"
#include "foldfill/holes.h"
#include "foldfill/inpaint.h"
#include "foldfill/io.h"
#include "foldfill/liepa.h"
#include "foldfill/report.h"
#include "support/cli_run.h"
#include "test_geometry.h"
#include "test_support.h"

namespace foldfill {

bool operator==(const ObjStatement& a, const ObjStatement& b) {
  return a.before_face == b.before_face && a.text == b.text;
}

namespace {

namespace fs = std::filesystem;
using testing::CliRun;
using testing::run_cli;
using testing::slurp;

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

void write_bytes(const fs::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

int line_count(const std::string& text) {
  return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
}

// A small folded sheet with one hole; with `float32`, positions that are
// float values (as a float PLY holds them).
Mesh sheet_with_hole(bool float32 = false) {
  Mesh mesh = cut_disk_hole(testing::small_folded_sheet(0.15), {1.5, 1.0}, 0.45).cut.mesh;
  if (float32) {
    // One value at a time: GCC 12.2 at -O3 vectorises this loop wrongly and
    // leaves the last few coordinates unrounded.
    for (Vec3& p : mesh.positions) {
      for (double& c : p) {
        volatile float rounded = static_cast<float>(c);
        c = rounded;
      }
    }
  }
  return mesh;
}

FillResult fill_default(const Mesh& mesh) {
  const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh);
  return fill_holes(mesh, loops, select_holes(loops, HoleSelection{}).fill);
}

// ------------------------------------------------------------- PLY by hand

// The attributes a test PLY gives vertex v and face f.
uint8_t colour(int v, int channel) { return static_cast<uint8_t>((v * 37 + channel * 91) % 256); }
Vec3 normal(int v) {
  const double a = 0.1 * v;
  return {std::cos(a) * 0.6, std::sin(a) * 0.6, 0.8};
}
float quality(int v) { return 0.1f * static_cast<float>(v) + 1.0f / 3.0f; }
int32_t label(int f) { return 1000 - 7 * f; }
uint8_t flags(int f) { return static_cast<uint8_t>(f % 5 + 1); }

enum class Encoding { Ascii, BinaryLittleEndian };

struct PlyCase {
  Encoding encoding;
  bool float_coordinates;
};

std::string case_name(const PlyCase& c) {
  return std::string(c.encoding == Encoding::Ascii ? "ascii" : "binary") +
         (c.float_coordinates ? "_float" : "_double");
}

template <class T>
void put(std::string& out, T value, Encoding encoding) {
  if (encoding == Encoding::Ascii) {
    std::ostringstream text;
    text.precision(17);
    if constexpr (std::is_same_v<T, uint8_t>)
      text << static_cast<int>(value);
    else if constexpr (std::is_same_v<T, float>)
      text << std::setprecision(9) << value;
    else
      text << value;
    out += text.str() + " ";
  } else {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    out.append(bytes, sizeof(T));
  }
}

// A PLY of `mesh` written independently of foldfill's writer: vertices with
// x y z nx ny nz red green blue quality, faces with a uchar `flags` before
// the index list and an int `label` after it, and an `edge` element.
std::string ply_with_attributes(const Mesh& mesh, const PlyCase& c) {
  const char* coordinate = c.float_coordinates ? "float" : "double";
  std::string out = "ply\nformat ";
  out += c.encoding == Encoding::Ascii ? "ascii" : "binary_little_endian";
  out += " 1.0\nelement vertex " + std::to_string(mesh.vertex_count()) + "\n";
  for (const char* axis : {"x", "y", "z"})
    out += std::string("property ") + coordinate + " " + axis + "\n";
  out +=
      "property float nx\nproperty float ny\nproperty float nz\nproperty uchar red\n"
      "property uchar green\nproperty uchar blue\nproperty float quality\nelement face " +
      std::to_string(mesh.face_count()) +
      "\nproperty uchar flags\nproperty list uchar int vertex_indices\nproperty int label\n"
      "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n";
  const auto line_end = [&] {
    if (c.encoding == Encoding::Ascii) out.back() = '\n';
  };
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    for (double x : mesh.positions[v]) {
      if (c.float_coordinates)
        put(out, static_cast<float>(x), c.encoding);
      else
        put(out, x, c.encoding);
    }
    for (double n : normal(v)) put(out, static_cast<float>(n), c.encoding);
    for (int channel = 0; channel < 3; ++channel) put(out, colour(v, channel), c.encoding);
    put(out, quality(v), c.encoding);
    line_end();
  }
  for (int f = 0; f < mesh.face_count(); ++f) {
    put(out, flags(f), c.encoding);
    put(out, uint8_t{3}, c.encoding);
    for (int v : mesh.faces[f]) put(out, int32_t{v}, c.encoding);
    put(out, label(f), c.encoding);
    line_end();
  }
  put(out, int32_t{0}, c.encoding);
  put(out, int32_t{1}, c.encoding);
  line_end();
  return out;
}

const ScalarProperty& property(const std::vector<ScalarProperty>& properties,
                               const std::string& name) {
  for (const ScalarProperty& p : properties)
    if (p.name == name) return p;
  ADD_FAILURE() << "no property " << name;
  static const ScalarProperty none;
  return none;
}

// `out`'s first vertices and faces are `in`'s, bit for bit, and so are
// their carried properties (same names, types and values).
void expect_originals_kept(const Mesh& in, const Mesh& out) {
  ASSERT_GE(out.vertex_count(), in.vertex_count());
  ASSERT_GE(out.face_count(), in.face_count());
  for (int v = 0; v < in.vertex_count(); ++v)
    for (int k = 0; k < 3; ++k)
      ASSERT_TRUE(same_bits(in.positions[v][k], out.positions[v][k])) << "vertex " << v;
  EXPECT_TRUE(std::equal(in.faces.begin(), in.faces.end(), out.faces.begin()));
  EXPECT_EQ(in.coordinate_type, out.coordinate_type);
  const auto same_properties = [](const std::vector<ScalarProperty>& a,
                                  const std::vector<ScalarProperty>& b) {
    ASSERT_EQ(a.size(), b.size());
    for (size_t p = 0; p < a.size(); ++p) {
      EXPECT_EQ(a[p].name, b[p].name);
      EXPECT_EQ(a[p].type, b[p].type) << a[p].name;
      ASSERT_GE(b[p].values.size(), a[p].values.size());
      for (size_t e = 0; e < a[p].values.size(); ++e)
        ASSERT_TRUE(same_bits(a[p].values[e], b[p].values[e])) << a[p].name << " " << e;
    }
  };
  same_properties(in.vertex_properties, out.vertex_properties);
  same_properties(in.face_properties, out.face_properties);
}

// The marks of `out` (a fill of `in`): -1 on `in`'s elements, the loop id
// on the ranges `holes` give, which follow one another to the end.
void expect_marks(const Mesh& in, const Mesh& out, const nlohmann::json& holes) {
  ASSERT_EQ(out.vertex_hole.size(), out.positions.size());
  ASSERT_EQ(out.face_hole.size(), out.faces.size());
  std::vector<int> vertex_hole(in.positions.size(), -1), face_hole(in.faces.size(), -1);
  int filled = 0;
  for (const nlohmann::json& hole : holes) {
    if (!hole["filled"].get<bool>()) continue;
    ++filled;
    const int id = hole["loop_id"];
    const std::array<int, 2> vertices = hole["new_vertices"], faces = hole["new_faces"];
    EXPECT_EQ(vertices[0], static_cast<int>(vertex_hole.size()));
    EXPECT_EQ(faces[0], static_cast<int>(face_hole.size()));
    EXPECT_EQ(vertices[1] - vertices[0], hole["patch_vertex_count"].get<int>());
    EXPECT_EQ(faces[1] - faces[0], hole["patch_face_count"].get<int>());
    vertex_hole.insert(vertex_hole.end(), vertices[1] - vertices[0], id);
    face_hole.insert(face_hole.end(), faces[1] - faces[0], id);
  }
  EXPECT_GT(filled, 0);
  EXPECT_EQ(vertex_hole, out.vertex_hole);
  EXPECT_EQ(face_hole, out.face_hole);
}

// The values fill_holes gives the new vertices and faces: colours and
// normals averaged over the loop (normals of unit length), 0 elsewhere.
void expect_new_element_values(const Mesh& in, const Mesh& out) {
  ASSERT_GT(out.vertex_count(), in.vertex_count());
  const ScalarProperty& nx = property(out.vertex_properties, "nx");
  const ScalarProperty& ny = property(out.vertex_properties, "ny");
  const ScalarProperty& nz = property(out.vertex_properties, "nz");
  const ScalarProperty& red = property(out.vertex_properties, "red");
  for (int v = in.vertex_count(); v < out.vertex_count(); ++v) {
    const double length = std::sqrt(nx.values[v] * nx.values[v] + ny.values[v] * ny.values[v] +
                                    nz.values[v] * nz.values[v]);
    EXPECT_NEAR(length, 1.0, 1e-6);
    EXPECT_GT(nz.values[v], 0.7);
    EXPECT_EQ(red.values[v], std::round(red.values[v]));
    EXPECT_EQ(property(out.vertex_properties, "quality").values[v], 0.0);
  }
  for (int f = in.face_count(); f < out.face_count(); ++f) {
    EXPECT_EQ(property(out.face_properties, "label").values[f], 0.0);
    EXPECT_EQ(property(out.face_properties, "flags").values[f], 0.0);
  }
}

class PlyAttributes : public ::testing::TestWithParam<PlyCase> {
 protected:
  void SetUp() override {
    dir_ = testing::scratch_dir("attributes_" + case_name(GetParam()));
    mesh_ = sheet_with_hole(GetParam().float_coordinates);
    bytes_ = ply_with_attributes(mesh_, GetParam());
    write_bytes(dir_ / "in.ply", bytes_);
  }
  fs::path dir_;
  Mesh mesh_;
  std::string bytes_;
};

TEST_P(PlyAttributes, AreReadInTheirTypes) {
  std::vector<std::string> warnings;
  const Mesh mesh = parse_mesh(bytes_, MeshFormat::Ply, "in.ply", &warnings);
  ASSERT_EQ(mesh.positions.size(), mesh_.positions.size());
  for (int v = 0; v < mesh.vertex_count(); ++v)
    for (int k = 0; k < 3; ++k)
      ASSERT_TRUE(same_bits(mesh.positions[v][k], mesh_.positions[v][k]))
          << "vertex " << v << " coordinate " << k;
  EXPECT_EQ(mesh.coordinate_type,
            GetParam().float_coordinates ? ScalarType::Float32 : ScalarType::Float64);
  ASSERT_EQ(mesh.vertex_properties.size(), 7u);
  EXPECT_EQ(property(mesh.vertex_properties, "red").type, ScalarType::UInt8);
  EXPECT_EQ(property(mesh.vertex_properties, "nx").type, ScalarType::Float32);
  ASSERT_EQ(mesh.face_properties.size(), 2u);
  EXPECT_EQ(mesh.face_properties[0].name, "flags");
  EXPECT_EQ(property(mesh.face_properties, "label").type, ScalarType::Int32);
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    EXPECT_EQ(property(mesh.vertex_properties, "green").values[v], colour(v, 1));
    EXPECT_TRUE(same_bits(property(mesh.vertex_properties, "quality").values[v], quality(v)));
    EXPECT_TRUE(same_bits(property(mesh.vertex_properties, "ny").values[v], float(normal(v)[1])));
  }
  for (int f = 0; f < mesh.face_count(); ++f)
    EXPECT_EQ(property(mesh.face_properties, "label").values[f], label(f));
  // The edge element is not carried, and says so.
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("in.ply: PLY element 'edge'"), std::string::npos) << warnings[0];
}

TEST_P(PlyAttributes, SurviveAFillThroughTheLibrary) {
  const Mesh in = parse_mesh(bytes_, MeshFormat::Ply, "in.ply");
  const FillResult result = fill_default(in);
  const nlohmann::json report = to_json(result.report);
  expect_originals_kept(in, result.mesh);
  expect_marks(in, result.mesh, report["holes"]);
  expect_new_element_values(in, result.mesh);
  // Written and read back: the same, new vertices rounded to the input's
  // coordinate type.
  const bool binary = GetParam().encoding == Encoding::BinaryLittleEndian;
  const std::string bytes = serialize_mesh(result.mesh, MeshFormat::Ply, {binary});
  const Mesh out = parse_mesh(bytes, MeshFormat::Ply, "out.ply");
  expect_originals_kept(in, out);
  expect_marks(in, out, report["holes"]);
  expect_new_element_values(in, out);
  for (size_t p = 0; p < out.vertex_properties.size(); ++p)
    EXPECT_EQ(result.mesh.vertex_properties[p].values, out.vertex_properties[p].values);
  for (int v = in.vertex_count(); v < out.vertex_count(); ++v)
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(out.positions[v][k], result.mesh.positions[v][k],
                  GetParam().float_coordinates ? 1e-6 : 0.0);
  const std::string header = bytes.substr(0, bytes.find("end_header"));
  EXPECT_NE(
      header.find(GetParam().float_coordinates ? "property float x\n" : "property double x\n"),
      std::string::npos);
  EXPECT_NE(header.find("property uchar red\n"), std::string::npos);
  EXPECT_NE(header.find("property int label\nproperty int foldfill_hole\n"), std::string::npos);
  EXPECT_EQ(2, [&] {
    int n = 0;
    for (size_t at = header.find("property int foldfill_hole\n"); at != std::string::npos;
         at = header.find("property int foldfill_hole\n", at + 1))
      ++n;
    return n;
  }());
}

TEST_P(PlyAttributes, SurviveAFillThroughTheCli) {
  const fs::path out = dir_ / "out.ply", report_path = dir_ / "r.json";
  const bool ascii = GetParam().encoding == Encoding::Ascii;
  const CliRun run = run_cli("fill " + (dir_ / "in.ply").string() + " -o " + out.string() +
                                 " --report " + report_path.string() + (ascii ? " --ascii" : ""),
                             dir_);
  ASSERT_EQ(run.code, 0) << run.err;
  // The one warning: the edge element.
  EXPECT_EQ(line_count(run.err), 1) << run.err;
  EXPECT_NE(run.err.find("element 'edge'"), std::string::npos) << run.err;
  const nlohmann::json report = nlohmann::json::parse(slurp(report_path));
  EXPECT_EQ(report["warnings"].size(), 1u);
  const Mesh in = parse_mesh(bytes_, MeshFormat::Ply, "in.ply");
  const std::string bytes = slurp(out);
  EXPECT_EQ(bytes.find("format ascii") != std::string::npos, ascii);
  const Mesh filled = parse_mesh(bytes, MeshFormat::Ply, "out.ply");
  expect_originals_kept(in, filled);
  expect_marks(in, filled, report["holes"]);
  expect_new_element_values(in, filled);
}

INSTANTIATE_TEST_SUITE_P(EncodingsAndCoordinates, PlyAttributes,
                         ::testing::Values(PlyCase{Encoding::Ascii, true},
                                           PlyCase{Encoding::Ascii, false},
                                           PlyCase{Encoding::BinaryLittleEndian, true},
                                           PlyCase{Encoding::BinaryLittleEndian, false}),
                         [](const ::testing::TestParamInfo<PlyCase>& param) {
                           return case_name(param.param);
                         });

TEST(PlyAttributesReading, ListsOtherThanTheIndicesAreDroppedWithAWarning) {
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nproperty list uchar float weights\nelement face 2\n"
      "property list uchar int vertex_indices\nproperty list uchar float texcoord\n"
      "property short part\nend_header\n"
      "0 0 0 1 0.5\n1 0 0 0\n1 1 0 2 1 1\n0 1 0 0\n"
      "4 0 1 2 3 2 0.1 0.2 -3\n3 3 2 0 0 9\n";
  std::vector<std::string> warnings;
  const Mesh mesh = parse_mesh(ply, MeshFormat::Ply, "lists.ply", &warnings);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_NE(warnings[0].find("lists.ply: PLY vertex property 'weights' is a list"),
            std::string::npos);
  EXPECT_NE(warnings[1].find("PLY face property 'texcoord' is a list"), std::string::npos);
  EXPECT_TRUE(mesh.vertex_properties.empty());
  // The quad's two triangles both have its value.
  ASSERT_EQ(mesh.face_properties.size(), 1u);
  EXPECT_EQ(mesh.face_properties[0].values, (std::vector<double>{-3, -3, 9}));
  EXPECT_EQ(mesh.face_properties[0].type, ScalarType::Int16);
}

TEST(PlyAttributesReading, AnAsciiFloatIsTheFloatNearestItsText) {
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nproperty float q\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n"
      "0.1 0 0 0.3\n1 0 0 0\n0 1 0.123456789012 0\n3 0 1 2\n";
  const Mesh mesh = parse_mesh(ply, MeshFormat::Ply, "floats.ply");
  EXPECT_TRUE(same_bits(mesh.positions[0][0], 0.1f));
  EXPECT_TRUE(same_bits(mesh.positions[2][2], 0.123456789012f));
  EXPECT_TRUE(same_bits(mesh.vertex_properties[0].values[0], 0.3f));
  // Written back as the same text.
  const std::string out = serialize_mesh(mesh, MeshFormat::Ply, {false});
  EXPECT_NE(out.find("\n0.1 0 0 0.3\n"), std::string::npos) << out;
}

TEST(PlyAttributesReading, MarksOfAnEarlierFillAreReadAndReplacedByTheNext) {
  const Mesh in = sheet_with_hole();
  const FillResult first = fill_default(in);
  const Mesh read = parse_mesh(serialize_mesh(first.mesh, MeshFormat::Ply), MeshFormat::Ply, "f");
  EXPECT_EQ(read.vertex_hole, first.mesh.vertex_hole);
  EXPECT_EQ(read.face_hole, first.mesh.face_hole);
  // Nothing left to fill: the output of a fill of it is all original.
  const FillResult second = fill_holes(read, find_boundary_loops(read), {});
  EXPECT_EQ(second.mesh.vertex_hole, std::vector<int>(read.positions.size(), -1));
  EXPECT_EQ(second.mesh.face_hole, std::vector<int>(read.faces.size(), -1));
}

TEST(PlyAttributesReading, AFoldfillHoleThatCannotBeMarksIsDroppedWithAWarning) {
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nproperty float foldfill_hole\nelement face 1\n"
      "property list uchar int vertex_indices\nproperty int foldfill_hole\n"
      "property int foldfill_hole\nend_header\n"
      "0 0 0 0.5\n1 0 0 1\n0 1 0 2\n3 0 1 2 4 5\n";
  std::vector<std::string> warnings;
  const Mesh mesh = parse_mesh(ply, MeshFormat::Ply, "marks.ply", &warnings);
  EXPECT_EQ(warnings.size(), 2u);
  EXPECT_TRUE(mesh.vertex_properties.empty());
  EXPECT_TRUE(mesh.vertex_hole.empty());
  EXPECT_EQ(mesh.face_hole, std::vector<int>{4});
  EXPECT_TRUE(mesh.face_properties.empty());
}

TEST(PlyAttributesReading, LiepasFillIsMarkedToo) {
  const Mesh in = sheet_with_hole();
  const std::vector<BoundaryLoop> loops = find_boundary_loops(in);
  const std::vector<int> ids = select_holes(loops, HoleSelection{}).fill;
  const FillResult result = fill_holes_liepa(in, loops, ids, "mesh", {});
  expect_marks(in, result.mesh, to_json(result.report)["holes"]);
}

// --------------------------------------------------------------------- OBJ

// `mesh` as an OBJ with a material library, an object, two groups with a
// material and a smoothing group each, and texture coordinates on the
// second group's faces.
std::string obj_with_groups(const Mesh& mesh) {
  std::ostringstream obj;
  obj.precision(17);
  obj << "# by hand\nmtllib cloth.mtl\no sheet\n";
  for (const Vec3& p : mesh.positions) obj << "v " << p[0] << " " << p[1] << " " << p[2] << "\n";
  for (const Vec3& p : mesh.positions) obj << "vt " << p[0] << " " << p[1] << "\n";
  const int half = mesh.face_count() / 2;
  for (int f = 0; f < mesh.face_count(); ++f) {
    if (f == 0) obj << "g front\nusemtl red\ns 1\n";
    if (f == half) obj << "g back  \t\nusemtl blue\ns off\n";
    const Tri& t = mesh.faces[f];
    if (f < half) {
      obj << "f " << t[0] + 1 << " " << t[1] + 1 << " " << t[2] + 1 << "\n";
    } else {
      obj << "f " << t[0] + 1 << "/" << t[0] + 1 << " " << t[1] + 1 << "/" << t[1] + 1 << " "
          << t[2] + 1 << "/" << t[2] + 1 << "\n";
    }
  }
  return obj.str();
}

std::vector<ObjStatement> expected_statements(const Mesh& mesh) {
  const int half = mesh.face_count() / 2;
  return {{0, "mtllib cloth.mtl"}, {0, "o sheet"}, {0, "g front"},
          {0, "usemtl red"},       {0, "s 1"},     {half, "g back"},
          {half, "usemtl blue"},   {half, "s off"}};
}

// The faces of `obj` (text) under each `g` line: the group in effect at
// every face, in order.
std::vector<std::string> groups_of_faces(const std::string& obj) {
  std::vector<std::string> groups;
  std::istringstream lines(obj);
  std::string group = "default";
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("g ", 0) == 0) group = line.substr(2);
    if (line.rfind("f ", 0) == 0) groups.push_back(group);
  }
  return groups;
}

// `out` (read from a filled OBJ) has `in`'s geometry, texture coordinates
// and statements, then the hole's group over exactly the new faces.
void expect_obj_kept_and_marked(const Mesh& in, const Mesh& out, const std::string& out_text,
                                const nlohmann::json& holes) {
  expect_originals_kept(in, out);
  EXPECT_EQ(in.texcoords, out.texcoords);
  ASSERT_EQ(out.face_texcoords.size(), out.faces.size());
  EXPECT_TRUE(
      std::equal(in.face_texcoords.begin(), in.face_texcoords.end(), out.face_texcoords.begin()));
  ASSERT_EQ(holes.size(), 1u);
  const int id = holes[0]["loop_id"];
  const std::array<int, 2> faces = holes[0]["new_faces"];
  EXPECT_EQ(faces[0], in.face_count());
  EXPECT_EQ(faces[1], out.face_count());
  std::vector<ObjStatement> statements = expected_statements(in);
  statements.push_back({in.face_count(), "g foldfill_hole_" + std::to_string(id)});
  EXPECT_EQ(out.obj_statements, statements);
  const std::vector<std::string> groups = groups_of_faces(out_text);
  ASSERT_EQ(static_cast<int>(groups.size()), out.face_count());
  for (int f = 0; f < out.face_count(); ++f) {
    const std::string expected = f >= faces[0]             ? "foldfill_hole_" + std::to_string(id)
                                 : f < in.face_count() / 2 ? "front"
                                                           : "back";
    ASSERT_EQ(groups[f], expected) << "face " << f;
  }
}

TEST(ObjAttributes, StatementsAreReadWithTheFaceTheyPrecede) {
  const Mesh mesh = sheet_with_hole();
  const Mesh read = parse_mesh(obj_with_groups(mesh), MeshFormat::Obj, "groups.obj");
  EXPECT_EQ(read.obj_statements, expected_statements(mesh));
  // Written back and read again: the same.
  const Mesh again =
      parse_mesh(serialize_mesh(read, MeshFormat::Obj), MeshFormat::Obj, "again.obj");
  EXPECT_EQ(again.obj_statements, read.obj_statements);
  EXPECT_EQ(again.face_texcoords, read.face_texcoords);
}

TEST(ObjAttributes, SurviveAFillThroughTheLibrary) {
  const Mesh in = parse_mesh(obj_with_groups(sheet_with_hole()), MeshFormat::Obj, "groups.obj");
  const FillResult result = fill_default(in);
  const nlohmann::json report = to_json(result.report);
  expect_marks(in, result.mesh, report["holes"]);
  const std::string text = serialize_mesh(result.mesh, MeshFormat::Obj);
  const Mesh out = parse_mesh(text, MeshFormat::Obj, "out.obj");
  expect_obj_kept_and_marked(in, out, text, report["holes"]);
}

TEST(ObjAttributes, SurviveAFillThroughTheCli) {
  const fs::path dir = testing::scratch_dir("attributes_obj_cli");
  const std::string obj = obj_with_groups(sheet_with_hole());
  write_bytes(dir / "in.obj", obj);
  const CliRun run =
      run_cli("fill " + (dir / "in.obj").string() + " -o " + (dir / "out.obj").string() +
                  " --report " + (dir / "r.json").string(),
              dir);
  ASSERT_EQ(run.code, 0) << run.err;
  EXPECT_EQ(run.err, "");
  const nlohmann::json report = nlohmann::json::parse(slurp(dir / "r.json"));
  const std::string text = slurp(dir / "out.obj");
  expect_obj_kept_and_marked(parse_mesh(obj, MeshFormat::Obj, "in.obj"),
                             parse_mesh(text, MeshFormat::Obj, "out.obj"), text, report["holes"]);
}

TEST(ObjAttributes, AnotherFormatKeepsTheMarksItCanHold) {
  const fs::path dir = testing::scratch_dir("attributes_across");
  const Mesh mesh = sheet_with_hole();
  write_bytes(dir / "in.obj", obj_with_groups(mesh));
  write_bytes(dir / "in.ply", ply_with_attributes(mesh, {Encoding::BinaryLittleEndian, false}));
  // OBJ in, PLY out: the marks.
  ASSERT_EQ(run_cli("fill " + (dir / "in.obj").string() + " -o " + (dir / "from_obj.ply").string() +
                        " --report " + (dir / "a.json").string(),
                    dir)
                .code,
            0);
  const Mesh ply = read_mesh((dir / "from_obj.ply").string());
  expect_marks(mesh, ply, nlohmann::json::parse(slurp(dir / "a.json"))["holes"]);
  // PLY in, OBJ out: a group over the new faces.
  ASSERT_EQ(run_cli("fill " + (dir / "in.ply").string() + " -o " + (dir / "from_ply.obj").string() +
                        " --report " + (dir / "b.json").string(),
                    dir)
                .code,
            0);
  const nlohmann::json holes = nlohmann::json::parse(slurp(dir / "b.json"))["holes"];
  const std::vector<std::string> groups = groups_of_faces(slurp(dir / "from_ply.obj"));
  const int first_new = holes[0]["new_faces"][0];
  ASSERT_EQ(first_new, mesh.face_count());
  for (size_t f = 0; f < groups.size(); ++f)
    EXPECT_EQ(groups[f], static_cast<int>(f) < first_new
                             ? "default"
                             : "foldfill_hole_" + std::to_string(holes[0]["loop_id"].get<int>()));
}

// ------------------------------------------- OBJ references to nothing

TEST(ObjMissingReferences, AreDroppedWithOneWarning) {
  const std::string obj =
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
      "f 1/1 2/2 3/3\n"        // fine
      "f 2/5/7 4/5/7 3/5/7\n"  // no such vt or vn
      "f 1/0 2/-9 3/1\n"       // nothing and before the first
      "f 2/1 4/2 3/3 1/9\n";   // a quad, one corner past the end
  std::vector<std::string> warnings;
  const Mesh mesh = parse_mesh(obj, MeshFormat::Obj, "broken.obj", &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0],
            "broken.obj: 3 faces reference texture coordinates or normals the file does not "
            "have; those references were dropped");
  EXPECT_EQ(mesh.face_count(), 5);
  EXPECT_EQ(mesh.face_texcoords,
            (std::vector<Tri>{{0, 1, 2}, {-1, -1, -1}, {-1, -1, 0}, {0, 1, 2}, {0, 2, -1}}));
  EXPECT_TRUE(mesh.face_normals.empty());
  // Without a warnings list, the same mesh.
  EXPECT_EQ(parse_mesh(obj, MeshFormat::Obj, "broken.obj").face_texcoords, mesh.face_texcoords);
}

TEST(ObjMissingReferences, DoNotStopTheCli) {
  const fs::path dir = testing::scratch_dir("attributes_obj_missing");
  // Every face refers to texture coordinate 5 and normal 7, which are not there.
  std::string obj;
  const Mesh mesh = sheet_with_hole();
  std::ostringstream text;
  text.precision(17);
  for (const Vec3& p : mesh.positions) text << "v " << p[0] << " " << p[1] << " " << p[2] << "\n";
  for (const Tri& t : mesh.faces)
    text << "f " << t[0] + 1 << "/5/7 " << t[1] + 1 << "/5/7 " << t[2] + 1 << "/5/7\n";
  write_bytes(dir / "in.obj", text.str());
  const CliRun run =
      run_cli("fill " + (dir / "in.obj").string() + " -o " + (dir / "out.obj").string() +
                  " --report " + (dir / "r.json").string(),
              dir);
  ASSERT_EQ(run.code, 0) << run.err;
  EXPECT_EQ(line_count(run.err), 1) << run.err;
  EXPECT_NE(run.err.find("in.obj: " + std::to_string(mesh.face_count()) +
                         " faces reference texture coordinates or normals"),
            std::string::npos)
      << run.err;
  const nlohmann::json report = nlohmann::json::parse(slurp(dir / "r.json"));
  EXPECT_EQ(report["warnings"].size(), 1u);
  EXPECT_TRUE(report["holes"][0]["filled"].get<bool>());
  const Mesh out = read_mesh((dir / "out.obj").string());
  expect_originals_kept(mesh, out);
  EXPECT_GT(out.face_count(), mesh.face_count());
}

}  // namespace
}  // namespace foldfill
