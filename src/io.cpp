// Mesh reading and writing: format dispatch and the validation shared by every
// format (files are read whole and written atomically by foldfill/file.h).
#include "foldfill/io.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "foldfill/file.h"
#include "io_detail.h"

namespace foldfill {
namespace io_detail {

void fail(ErrorKind kind, const std::string& source, const std::string& problem) {
  throw Error(kind, source + ": " + problem);
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

namespace {

// Where a face is, for messages: "line 12: " in a text file, else "face 7: ".
std::string face_location(size_t face, const std::vector<int>& face_lines) {
  if (!face_lines.empty()) return "line " + std::to_string(face_lines[face]) + ": ";
  return "face " + std::to_string(face) + ": ";
}

void validate_positions(const Mesh& mesh, const std::string& source, int index_base) {
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    for (double coordinate : mesh.positions[v]) {
      if (!std::isfinite(coordinate)) {
        fail(ErrorKind::NonFiniteCoordinate, source,
             "vertex " + std::to_string(v + index_base) + " has a non-finite coordinate (" +
                 std::to_string(coordinate) + ")");
      }
    }
  }
}

void validate_faces(const Mesh& mesh, const std::string& source, const std::vector<int>& face_lines,
                    int index_base) {
  const int vertex_count = mesh.vertex_count();
  for (size_t f = 0; f < mesh.faces.size(); ++f) {
    const Tri& face = mesh.faces[f];
    for (int v : face) {
      if (v < 0 || v >= vertex_count) {
        fail(ErrorKind::BadFace, source,
             face_location(f, face_lines) + "face index " +
                 std::to_string(int64_t{v} + index_base) + " out of range (mesh has " +
                 std::to_string(vertex_count) + " vertices)");
      }
    }
    if (face[0] == face[1] || face[1] == face[2] || face[2] == face[0]) {
      const int repeated = face[1] == face[2] ? face[1] : face[0];
      fail(ErrorKind::BadFace, source,
           face_location(f, face_lines) + "face repeats vertex " +
               std::to_string(int64_t{repeated} + index_base));
    }
  }
}

// Checks per-face attribute indices (-1: absent) against `attribute_count`.
void validate_face_attributes(const Mesh& mesh, const std::vector<Tri>& face_attributes,
                              size_t attribute_count, const char* attribute,
                              const std::string& source, const std::vector<int>& face_lines,
                              int index_base) {
  if (face_attributes.empty()) return;
  if (face_attributes.size() != mesh.faces.size()) {
    fail(ErrorKind::BadFace, source,
         std::string(attribute) + " indices given for " + std::to_string(face_attributes.size()) +
             " faces but the mesh has " + std::to_string(mesh.faces.size()));
  }
  for (size_t f = 0; f < face_attributes.size(); ++f) {
    for (int index : face_attributes[f]) {
      if (index < -1 || (index >= 0 && static_cast<size_t>(index) >= attribute_count)) {
        fail(ErrorKind::BadFace, source,
             face_location(f, face_lines) + attribute + " index " +
                 std::to_string(int64_t{index} + index_base) + " out of range (mesh has " +
                 std::to_string(attribute_count) + ")");
      }
    }
  }
}

}  // namespace

void validate_mesh(const Mesh& mesh, const std::string& source, const std::vector<int>& face_lines,
                   int index_base) {
  validate_positions(mesh, source, index_base);
  validate_faces(mesh, source, face_lines, index_base);
  validate_face_attributes(mesh, mesh.face_texcoords, mesh.texcoords.size(), "texture coordinate",
                           source, face_lines, index_base);
  validate_face_attributes(mesh, mesh.face_normals, mesh.normals.size(), "normal", source,
                           face_lines, index_base);
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

Mesh parse_mesh(std::string_view bytes, MeshFormat format, const std::string& source) {
  if (std::all_of(bytes.begin(), bytes.end(), io_detail::is_space)) {
    fail(ErrorKind::BadFormat, source, "empty file");
  }
  ParsedMesh parsed = parse_format(bytes, format, source);
  if (parsed.mesh.faces.empty()) fail(ErrorKind::BadFormat, source, "no faces");
  io_detail::validate_mesh(parsed.mesh, source, parsed.face_lines, parsed.index_base);
  return std::move(parsed.mesh);
}

Mesh read_mesh(const std::string& path) {
  const MeshFormat format = format_from_path(path);
  return parse_mesh(read_file(path), format, path);
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

std::string serialize_mesh(const Mesh& mesh, MeshFormat format, const WriteOptions& options) {
  io_detail::validate_mesh(mesh, "mesh");
  io_detail::ByteSink sink;
  serialize_into(mesh, format, options, sink);
  return sink.finish();
}

}  // namespace foldfill
