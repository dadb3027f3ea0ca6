// Wavefront OBJ: `v`, `vt`, `vn` and `f` statements; every other statement
// (mtllib, o, g, s, usemtl, l, ...) is ignored.
#include <algorithm>
#include <climits>

#include "io_detail.h"

namespace foldfill::io_detail {
namespace {

class ObjParser {
 public:
  ObjParser(std::string_view bytes, const std::string& source)
      : cursor_(bytes, source, TextCursor::Separator::Blanks) {}

  ParsedMesh parse() {
    while (!cursor_.at_end()) {
      const std::string_view keyword = cursor_.next_word();
      if (keyword == "v") {
        mesh().positions.push_back(read_numbers<3>());
        parsed_.vertex_lines.push_back(cursor_.line());
      } else if (keyword == "vt") {
        read_texcoord();
      } else if (keyword == "vn") {
        mesh().normals.push_back(read_numbers<3>());
      } else if (keyword == "f") {
        read_face();
      }
      cursor_.next_line();  // also skips what follows the numbers (w, colours)
    }
    if (!any_texcoord_) mesh().face_texcoords.clear();
    if (!any_normal_) mesh().face_normals.clear();
    parsed_.obj_indices = true;
    return std::move(parsed_);
  }

 private:
  Mesh& mesh() { return parsed_.mesh; }

  template <size_t N>
  std::array<double, N> read_numbers() {
    std::array<double, N> values;
    for (double& value : values) value = cursor_.next_number<double>();
    return values;
  }

  // `vt u [v [w]]`: keeps (u, v), v defaulting to 0.
  void read_texcoord() {
    const double u = cursor_.next_number<double>();
    const double v = cursor_.at_line_end() ? 0.0 : cursor_.next_number<double>();
    mesh().texcoords.push_back({u, v});
  }

  // `f c0 c1 c2 ...`, each corner `p`, `p/t`, `p//n` or `p/t/n`; split into a fan.
  void read_face() {
    positions_.clear();
    texcoords_.clear();
    normals_.clear();
    while (!cursor_.at_line_end()) read_corner();
    require_polygon(cursor_, static_cast<long long>(positions_.size()));
    append_fan(positions_, mesh().faces);
    append_fan(texcoords_, mesh().face_texcoords);
    append_fan(normals_, mesh().face_normals);
    parsed_.face_lines.insert(parsed_.face_lines.end(), positions_.size() - 2, cursor_.line());
  }

  void read_corner() {
    positions_.push_back(read_index("vertex", mesh().positions.size()));
    int texcoord = -1;
    int normal = -1;
    if (cursor_.peek() == '/') {
      cursor_.advance();
      if (cursor_.peek() != '/') {
        texcoord = read_index("texture coordinate", mesh().texcoords.size());
        any_texcoord_ = true;
      }
      if (cursor_.peek() == '/') {
        cursor_.advance();
        normal = read_index("normal", mesh().normals.size());
        any_normal_ = true;
      }
    }
    if (!cursor_.at_token_end()) {
      cursor_.fail(ErrorKind::BadFormat, "bad face corner (expected p, p/t, p//n or p/t/n)");
    }
    texcoords_.push_back(texcoord);
    normals_.push_back(normal);
  }

  // A 1-based or negative (relative to the `defined` items so far) index,
  // made 0-based. Positive indices are range-checked by validation. The
  // message quotes the index as written, named as OBJ's own.
  int read_index(const char* what, size_t defined) {
    const long long index = cursor_.number_prefix<long long>();
    const long long resolved = index < 0 ? static_cast<long long>(defined) + index : index - 1;
    if (index == 0 || resolved < 0 || resolved > INT_MAX) {
      cursor_.fail(ErrorKind::BadFace, std::string("OBJ ") + what + " index " +
                                           std::to_string(index) + " out of range (" +
                                           std::to_string(defined) + " defined so far)");
    }
    return static_cast<int>(resolved);
  }

  TextCursor cursor_;
  ParsedMesh parsed_;
  bool any_texcoord_ = false;
  bool any_normal_ = false;
  std::vector<int> positions_, texcoords_, normals_;  // corners of the current face
};

bool has_all(const std::vector<Tri>& face_attributes, size_t face) {
  if (face_attributes.empty()) return false;
  const Tri& corners = face_attributes[face];
  return std::all_of(corners.begin(), corners.end(), [](int index) { return index >= 0; });
}

}  // namespace

ParsedMesh parse_obj(std::string_view bytes, const std::string& source) {
  return ObjParser(text_content(bytes, source), source).parse();
}

// A face corner gets its texture coordinate / normal only when all three
// corners of the face have one, since an OBJ face cannot mix corner forms.
void serialize_obj(const Mesh& mesh, ByteSink& sink) {
  std::string& out = sink.bytes();
  sink.expect(mesh.positions.size() * 64 + mesh.faces.size() * 32);
  for (const Vec3& p : mesh.positions) {
    out += "v ";
    append_numbers_line(out, p);
    sink.record_done();
  }
  for (const Vec2& t : mesh.texcoords) {
    out += "vt ";
    append_numbers_line(out, t);
    sink.record_done();
  }
  for (const Vec3& n : mesh.normals) {
    out += "vn ";
    append_numbers_line(out, n);
    sink.record_done();
  }
  for (size_t f = 0; f < mesh.faces.size(); ++f) {
    const bool with_texcoords = has_all(mesh.face_texcoords, f);
    const bool with_normals = has_all(mesh.face_normals, f);
    out += 'f';
    for (int c = 0; c < 3; ++c) {
      out += ' ';
      append_number(out, mesh.faces[f][c] + 1);
      if (with_texcoords || with_normals) out += '/';
      if (with_texcoords) append_number(out, mesh.face_texcoords[f][c] + 1);
      if (with_normals) {
        out += '/';
        append_number(out, mesh.face_normals[f][c] + 1);
      }
    }
    out += '\n';
    sink.record_done();
  }
}

}  // namespace foldfill::io_detail
