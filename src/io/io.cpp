// Mesh reading and writing: format dispatch and the validation shared by every
// format (files are read whole and written atomically by foldfill/file.h).
#include "foldfill/io.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "foldfill/file.h"
#include "io/io_detail.h"

namespace foldfill {
namespace io_detail {

void fail(ErrorKind kind, const std::string& source, const std::string& problem) {
  throw_error(kind, source + ": " + problem);
}

std::string excerpt(std::string_view text) {
  constexpr size_t kMaxLength = 24;
  std::string out = "'";
  for (size_t i = 0; i < std::min(text.size(), kMaxLength); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    out += (c >= 0x20 && c < 0x7f) ? static_cast<char>(c) : '?';
  }
  if (text.size() > kMaxLength) out += "...";
  return out + "'";
}

void require_text(std::string_view bytes, const std::string& source) {
  const size_t nul = bytes.find('\0');
  if (nul != std::string_view::npos) {
    fail(ErrorKind::BadFormat, source,
         "binary data in a text file (NUL byte at offset " + std::to_string(nul) + ")");
  }
}

std::string_view skip_byte_order_mark(std::string_view bytes, const std::string& source) {
  if (starts_with(bytes, kUtf8ByteOrderMark)) return bytes.substr(kUtf8ByteOrderMark.size());
  // UTF-32's marks begin with UTF-16's little-endian one, so they come first.
  constexpr std::pair<std::string_view, const char*> kOtherMarks[] = {
      {{"\xFF\xFE\0\0", 4}, "UTF-32"},
      {{"\0\0\xFE\xFF", 4}, "UTF-32"},
      {"\xFF\xFE", "UTF-16"},
      {"\xFE\xFF", "UTF-16"}};
  for (const auto& [mark, encoding] : kOtherMarks) {
    if (starts_with(bytes, mark)) {
      fail(ErrorKind::BadFormat, source,
           std::string(encoding) + " text is not supported; save it as UTF-8 or ASCII");
    }
  }
  return bytes;
}

void require_line_feeds(std::string_view text, const std::string& source) {
  if (text.find('\n') == std::string_view::npos && text.find('\r') != std::string_view::npos) {
    fail(ErrorKind::BadFormat, source,
         "line ends are CR only (classic Mac text); convert them to LF");
  }
}

std::string_view text_content(std::string_view bytes, const std::string& source) {
  const std::string_view text = skip_byte_order_mark(bytes, source);
  require_text(text, source);
  require_line_feeds(text, source);
  return text;
}

namespace {

// Where the vertices and faces of a mesh are in its file, for messages.
struct Locations {
  const std::vector<int>& vertex_lines;  // or empty
  const std::vector<int>& face_lines;    // or empty
  bool obj_indices;
};

// A face, for messages: "line 12: " in a text file, else "face 7: ".
std::string face_location(size_t face, const Locations& where) {
  if (!where.face_lines.empty()) return "line " + std::to_string(where.face_lines[face]) + ": ";
  return "face " + std::to_string(face) + ": ";
}

// The file's own number of the item `index` (from 0) when it counts from 1.
std::string obj_index(int64_t index, const Locations& where) {
  return where.obj_indices ? "OBJ index " + std::to_string(index + 1) : "";
}

void validate_positions(const Mesh& mesh, const std::string& source, const Locations& where) {
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    for (double coordinate : mesh.positions[v]) {
      if (!std::isfinite(coordinate)) {
        const std::string line = where.vertex_lines.empty()
                                     ? ""
                                     : " (line " + std::to_string(where.vertex_lines[v]) + ")";
        fail(ErrorKind::NonFiniteCoordinate, source,
             "vertex " + std::to_string(v) + line + " has a non-finite coordinate (" +
                 std::to_string(coordinate) + ")");
      }
    }
  }
}

void validate_faces(const Mesh& mesh, const std::string& source, const Locations& where) {
  const int vertex_count = mesh.vertex_count();
  for (size_t f = 0; f < mesh.faces.size(); ++f) {
    const Tri& face = mesh.faces[f];
    for (int v : face) {
      if (v < 0 || v >= vertex_count) {
        const std::string file_index = obj_index(v, where);
        fail(ErrorKind::BadFace, source,
             face_location(f, where) + "face vertex " + std::to_string(v) +
                 " out of range (mesh has " + count_of(vertex_count, "vertex", "vertices") +
                 (file_index.empty() ? "" : "; " + file_index) + ")");
      }
    }
    if (face[0] == face[1] || face[1] == face[2] || face[2] == face[0]) {
      const int repeated = face[1] == face[2] ? face[1] : face[0];
      const std::string file_index = obj_index(repeated, where);
      fail(ErrorKind::BadFace, source,
           face_location(f, where) + "face repeats vertex " + std::to_string(repeated) +
               (file_index.empty() ? "" : " (" + file_index + ")"));
    }
  }
}

// Checks per-face attribute indices (-1: absent) against `attribute_count`.
void validate_face_attributes(const Mesh& mesh, const std::vector<Tri>& face_attributes,
                              size_t attribute_count, const char* attribute,
                              const std::string& source, const Locations& where) {
  if (face_attributes.empty()) return;
  if (face_attributes.size() != mesh.faces.size()) {
    fail(ErrorKind::BadFace, source,
         std::string(attribute) + " indices given for " + std::to_string(face_attributes.size()) +
             " faces but the mesh has " + std::to_string(mesh.faces.size()));
  }
  for (size_t f = 0; f < face_attributes.size(); ++f) {
    for (int index : face_attributes[f]) {
      if (index < -1 || (index >= 0 && static_cast<size_t>(index) >= attribute_count)) {
        const std::string file_index = obj_index(index, where);
        fail(ErrorKind::BadFace, source,
             face_location(f, where) + attribute + " " + std::to_string(index) +
                 " out of range (mesh has " + std::to_string(attribute_count) +
                 (file_index.empty() ? "" : "; " + file_index) + ")");
      }
    }
  }
}

// Throws InternalError unless `values` has `count` entries (or none, with
// `may_be_empty`): the per-element data that comes with a mesh, which a fill
// extends over what it appends (foldfill/marks.h).
template <class T>
void require_per_element(const std::vector<T>& values, size_t count, bool may_be_empty,
                         const std::string& what, const std::string& source) {
  if (values.size() != count && !(may_be_empty && values.empty())) {
    fail(ErrorKind::Internal, source,
         what + " has " + std::to_string(values.size()) + " entries for " + std::to_string(count) +
             " elements");
  }
}

void validate_extras(const Mesh& mesh, const std::string& source) {
  for (const ScalarProperty& property : mesh.vertex_properties)
    require_per_element(property.values, mesh.positions.size(), false,
                        "vertex property '" + property.name + "'", source);
  for (const ScalarProperty& property : mesh.face_properties)
    require_per_element(property.values, mesh.faces.size(), false,
                        "face property '" + property.name + "'", source);
  require_per_element(mesh.vertex_hole, mesh.positions.size(), true, "vertex_hole", source);
  require_per_element(mesh.face_hole, mesh.faces.size(), true, "face_hole", source);
  int previous = 0;
  for (const ObjStatement& statement : mesh.obj_statements) {
    if (statement.before_face < previous || statement.before_face > mesh.face_count()) {
      fail(ErrorKind::Internal, source,
           "OBJ statement '" + statement.text + "' before face " +
               std::to_string(statement.before_face) + " is out of order");
    }
    previous = statement.before_face;
  }
}

void validate(const Mesh& mesh, const std::string& source, const Locations& where) {
  validate_positions(mesh, source, where);
  validate_faces(mesh, source, where);
  validate_face_attributes(mesh, mesh.face_texcoords, mesh.texcoords.size(), "texture coordinate",
                           source, where);
  validate_face_attributes(mesh, mesh.face_normals, mesh.normals.size(), "normal", source, where);
  validate_extras(mesh, source);
}

}  // namespace

void validate_parsed(const ParsedMesh& parsed, const std::string& source) {
  validate(parsed.mesh, source, {parsed.vertex_lines, parsed.face_lines, parsed.obj_indices});
}

void validate_mesh(const Mesh& mesh, const std::string& source) {
  const std::vector<int> none;
  validate(mesh, source, {none, none, false});
}

}  // namespace io_detail

namespace {

using io_detail::fail;
using io_detail::ParsedMesh;

ParsedMesh parse_format(std::string_view bytes, MeshFormat format, const std::string& source) {
  switch (format) {
    case MeshFormat::Obj:
      return io_detail::parse_obj(bytes, source);
    case MeshFormat::Ply:
      return io_detail::parse_ply(bytes, source);
    case MeshFormat::Off:
      return io_detail::parse_off(bytes, source);
    case MeshFormat::Stl:
      return io_detail::parse_stl(bytes, source);
  }
  fail(ErrorKind::Internal, source, "unknown mesh format");
}

// Puts the file bytes of `mesh` (validated before) into `sink`.
void serialize_into(const Mesh& mesh, MeshFormat format, const WriteOptions& options,
                    io_detail::ByteSink& sink) {
  switch (format) {
    case MeshFormat::Obj:
      return io_detail::serialize_obj(mesh, sink);
    case MeshFormat::Ply:
      return io_detail::serialize_ply(mesh, options.binary, sink);
    case MeshFormat::Off:
      return io_detail::serialize_off(mesh, sink);
    case MeshFormat::Stl:
      return io_detail::serialize_stl(mesh, options.binary, sink);
  }
}

}  // namespace

MeshFormat format_from_path(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".obj") return MeshFormat::Obj;
  if (extension == ".ply") return MeshFormat::Ply;
  if (extension == ".off") return MeshFormat::Off;
  if (extension == ".stl") return MeshFormat::Stl;
  fail(ErrorKind::Usage, path, "unknown mesh format (expected .obj, .ply, .off or .stl)");
}

Mesh parse_mesh(std::string_view bytes, MeshFormat format, const std::string& source,
                std::vector<std::string>* warnings) {
  const std::string_view content = io_detail::starts_with(bytes, io_detail::kUtf8ByteOrderMark)
                                       ? bytes.substr(io_detail::kUtf8ByteOrderMark.size())
                                       : bytes;
  if (std::all_of(content.begin(), content.end(), io_detail::is_space)) {
    fail(ErrorKind::BadFormat, source, "empty file");
  }
  ParsedMesh parsed = parse_format(bytes, format, source);
  if (parsed.mesh.faces.empty()) fail(ErrorKind::BadFormat, source, "no faces");
  io_detail::validate_parsed(parsed, source);
  if (warnings) {
    warnings->insert(warnings->end(), parsed.warnings.begin(), parsed.warnings.end());
  }
  return std::move(parsed.mesh);
}

Mesh read_mesh(const std::string& path, std::vector<std::string>* warnings) {
  const MeshFormat format = format_from_path(path);
  return parse_mesh(read_file(path), format, path, warnings);
}

// The file is written in chunks as it is produced: a 2M-triangle mesh's
// 49 MiB PLY took 51 MiB of memory on top of the mesh when built whole first.
void write_mesh(const Mesh& mesh, const std::string& path, const WriteOptions& options) {
  const MeshFormat format = format_from_path(path);
  io_detail::validate_mesh(mesh, path);
  write_file_atomically(path, [&](const ByteConsumer& write) {
    io_detail::ByteSink sink(write);
    serialize_into(mesh, format, options, sink);
    sink.finish();
  });
}

void validate_mesh(const Mesh& mesh, const std::string& source) {
  io_detail::validate_mesh(mesh, source);
}

std::string serialize_mesh(const Mesh& mesh, MeshFormat format, const WriteOptions& options) {
  io_detail::validate_mesh(mesh, "mesh");
  io_detail::ByteSink sink;
  serialize_into(mesh, format, options, sink);
  return sink.finish();
}

}  // namespace foldfill
