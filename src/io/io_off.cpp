// Object File Format: an `OFF` header, the counts `V F [E]`, V vertex lines and
// F face lines `n i0 ... i(n-1)`, with `#` comments. Values after the
// coordinates or indices on a line (colours, normals of COFF / NOFF) are skipped.
#include "io/io_detail.h"

namespace foldfill::io_detail {
namespace {

// "OFF", optionally prefixed by the letters of its variants (ST, C, N).
bool is_off_header(std::string_view word) {
  constexpr std::string_view kOff = "OFF";
  if (word.size() < kOff.size() || word.substr(word.size() - kOff.size()) != kOff) return false;
  const std::string_view prefix = word.substr(0, word.size() - kOff.size());
  return prefix.find_first_not_of("STCN") == std::string_view::npos;
}

void read_vertices(TextCursor& cursor, long long vertex_count, ParsedMesh& parsed) {
  cursor.require_items(vertex_count, 3, "vertices");
  parsed.mesh.positions.resize(static_cast<size_t>(vertex_count));
  parsed.vertex_lines.reserve(static_cast<size_t>(vertex_count));
  for (Vec3& position : parsed.mesh.positions) {
    for (double& coordinate : position) coordinate = cursor.next_number<double>();
    parsed.vertex_lines.push_back(cursor.line());
    cursor.next_line();
  }
}

void read_faces(TextCursor& cursor, long long face_count, ParsedMesh& parsed) {
  cursor.require_items(face_count, 1, "faces");  // a too-short face is a BadFace
  parsed.mesh.faces.reserve(static_cast<size_t>(face_count));
  parsed.face_lines.reserve(static_cast<size_t>(face_count));
  const int vertex_count = parsed.mesh.vertex_count();
  std::vector<int> corners;
  for (long long f = 0; f < face_count; ++f) {
    const auto corner_count = cursor.next_number<long long>();
    require_polygon(cursor, corner_count);
    corners.clear();
    for (long long c = 0; c < corner_count; ++c) {
      const auto index = cursor.next_number<long long>();
      if (index < 0 || index >= vertex_count) {
        cursor.fail(ErrorKind::BadFace, "face vertex " + std::to_string(index) +
                                            " out of range (mesh has " +
                                            count_of(vertex_count, "vertex", "vertices") + ")");
      }
      corners.push_back(static_cast<int>(index));
    }
    append_fan(corners, parsed.mesh.faces);
    parsed.face_lines.insert(parsed.face_lines.end(), corners.size() - 2, cursor.line());
    cursor.next_line();
  }
  // A count lower than the faces that follow would silently drop faces, which
  // opens a false hole; so anything but comments after them is refused.
  cursor.skip_separators();
  if (!cursor.at_end()) {
    cursor.fail(ErrorKind::BadFormat, "data beyond the " + count_of(face_count, "face", "faces") +
                                          " the header declares");
  }
}

}  // namespace

ParsedMesh parse_off(std::string_view bytes, const std::string& source) {
  TextCursor cursor(text_content(bytes, source), source, TextCursor::Separator::HashComments);
  const std::string_view header = cursor.next_word();
  if (!is_off_header(header)) {
    cursor.fail(ErrorKind::BadFormat, "expected an OFF header, found " + excerpt(header));
  }
  const auto vertex_count = cursor.next_number<long long>();
  const auto face_count = cursor.next_number<long long>();
  cursor.next_line();  // the edge count, unused
  ParsedMesh parsed;
  read_vertices(cursor, vertex_count, parsed);
  read_faces(cursor, face_count, parsed);
  return parsed;
}

void serialize_off(const Mesh& mesh, ByteSink& sink) {
  std::string& out = sink.bytes();
  sink.expect(mesh.positions.size() * 64 + mesh.faces.size() * 32);
  out += "OFF\n";
  append_numbers_line(out, std::array<size_t, 3>{mesh.positions.size(), mesh.faces.size(), 0});
  for (const Vec3& p : mesh.positions) {
    append_numbers_line(out, p);
    sink.record_done();
  }
  for (const Tri& face : mesh.faces) {
    out += "3 ";
    append_numbers_line(out, face);
    sink.record_done();
  }
}

}  // namespace foldfill::io_detail
