// Wavefront OBJ: `v`, `vt`, `vn` and `f` statements, and the statements that
// set the state of the faces after them (mtllib, o, g, usemtl, s), kept to be
// written back; every other statement (l, p, vp, curves, ...) is ignored.
#include <algorithm>
#include <climits>

#include "io/io_detail.h"

namespace foldfill::io_detail {
namespace {

class ObjParser {
 public:
  ObjParser(std::string_view bytes, const std::string& source)
      : cursor_(bytes, source, TextCursor::Separator::Blanks), source_(source) {}

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
      } else if (is_face_state(keyword)) {
        keep_statement(keyword);
      }
      cursor_.next_line();  // also skips what follows the numbers (w, colours)
    }
    drop_missing_references();
    parsed_.obj_indices = true;
    return std::move(parsed_);
  }

 private:
  // An attribute index that refers to nothing (0, or a relative one before
  // the first): dropped with the references past the file's last item.
  static constexpr int kMissing = INT_MAX;

  Mesh& mesh() { return parsed_.mesh; }

  static bool is_face_state(std::string_view keyword) {
    return keyword == "mtllib" || keyword == "o" || keyword == "g" || keyword == "usemtl" ||
           keyword == "s";
  }

  // Records the current line, from `keyword`, as the statement before the
  // next face.
  void keep_statement(std::string_view keyword) {
    std::string_view rest = cursor_.rest();
    rest = rest.substr(0, rest.find('\n'));
    while (!rest.empty() && is_space(rest.back())) rest.remove_suffix(1);
    mesh().obj_statements.push_back(
        {mesh().face_count(), std::string(keyword) + std::string(rest)});
  }

  // Sets the texture coordinate and normal references that point past the
  // file's items (or at nothing) to -1, with one warning for the faces that
  // had any; a face attribute array left without any reference is cleared.
  void drop_missing_references() {
    int broken_faces = 0;
    int last_broken_line = -1;
    for (size_t f = 0; f < mesh().face_texcoords.size(); ++f) {
      const bool texcoord_dropped = drop_missing(mesh().face_texcoords[f], mesh().texcoords.size());
      const bool normal_dropped = drop_missing(mesh().face_normals[f], mesh().normals.size());
      const bool broken = texcoord_dropped || normal_dropped;
      // The triangles of one polygon share its line; count polygons.
      if (broken && parsed_.face_lines[f] != last_broken_line) {
        ++broken_faces;
        last_broken_line = parsed_.face_lines[f];
      }
    }
    clear_if_unused(mesh().face_texcoords);
    clear_if_unused(mesh().face_normals);
    if (broken_faces > 0) {
      parsed_.warnings.push_back(
          source_ + ": " + count_of(broken_faces, "face references", "faces reference") +
          " texture coordinates or normals the file does not have; those references were "
          "dropped");
    }
  }

  static bool drop_missing(Tri& corners, size_t defined) {
    bool dropped = false;
    for (int& index : corners) {
      if (index >= 0 && static_cast<size_t>(index) >= defined) {
        index = -1;
        dropped = true;
      }
    }
    return dropped;
  }

  static void clear_if_unused(std::vector<Tri>& face_attributes) {
    const bool used = std::any_of(face_attributes.begin(), face_attributes.end(),
                                  [](const Tri& t) { return t[0] >= 0 || t[1] >= 0 || t[2] >= 0; });
    if (!used) face_attributes.clear();
  }

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
      if (cursor_.peek() != '/') texcoord = read_attribute_index(mesh().texcoords.size());
      if (cursor_.peek() == '/') {
        cursor_.advance();
        normal = read_attribute_index(mesh().normals.size());
      }
    }
    if (!cursor_.at_token_end()) {
      cursor_.fail(ErrorKind::BadFormat, "bad face corner (expected p, p/t, p//n or p/t/n)");
    }
    texcoords_.push_back(texcoord);
    normals_.push_back(normal);
  }

  // A 1-based or negative (relative to the `defined` items so far) index,
  // made 0-based; `index` is -1 for one that refers to nothing.
  static long long resolve(long long index, size_t defined) {
    const long long resolved = index < 0 ? static_cast<long long>(defined) + index : index - 1;
    return index == 0 || resolved < 0 || resolved >= INT_MAX ? -1 : resolved;
  }

  // A vertex index. Positive indices are range-checked by validation. The
  // message quotes the index as written, named as OBJ's own.
  int read_index(const char* what, size_t defined) {
    const long long index = cursor_.number_prefix<long long>();
    const long long resolved = resolve(index, defined);
    if (resolved < 0) {
      cursor_.fail(ErrorKind::BadFace, std::string("OBJ ") + what + " index " +
                                           std::to_string(index) + " out of range (" +
                                           std::to_string(defined) + " defined so far)");
    }
    return static_cast<int>(resolved);
  }

  // A texture coordinate or normal index; one that refers to nothing is
  // kMissing, dropped at the end (a positive one may refer to an item that
  // follows).
  int read_attribute_index(size_t defined) {
    const long long resolved = resolve(cursor_.number_prefix<long long>(), defined);
    return resolved < 0 ? kMissing : static_cast<int>(resolved);
  }

  TextCursor cursor_;
  const std::string& source_;
  ParsedMesh parsed_;
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
// The kept statements come back before the faces they were before (`mtllib`
// among them: after the vertices, where OBJ allows it too); each run of new
// faces follows them under `g foldfill_hole_<loop id>` and so takes the
// material and smoothing group in effect after the last original face.
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
  size_t next_statement = 0;
  int group_hole = -1;  // the hole whose group the faces are in, -1 for none
  for (size_t f = 0; f < mesh.faces.size(); ++f) {
    for (; next_statement < mesh.obj_statements.size() &&
           mesh.obj_statements[next_statement].before_face <= static_cast<int>(f);
         ++next_statement) {
      out += mesh.obj_statements[next_statement].text;
      out += '\n';
    }
    const int hole = mesh.face_hole.empty() ? -1 : mesh.face_hole[f];
    if (hole >= 0 && hole != group_hole) {
      out += "g foldfill_hole_";
      append_number(out, hole);
      out += '\n';
    }
    group_hole = hole;
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
  for (; next_statement < mesh.obj_statements.size(); ++next_statement) {
    out += mesh.obj_statements[next_statement].text;
    out += '\n';
  }
}

}  // namespace foldfill::io_detail
