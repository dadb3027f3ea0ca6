// Reading and writing triangle meshes: OBJ, PLY (ASCII / binary), OFF, STL.
#pragma once

#include <string>
#include <string_view>

#include "foldfill/mesh.h"

namespace foldfill {

enum class MeshFormat { Obj, Ply, Off, Stl };

// The format named by a path's extension (case-insensitive); throws
// Error(Usage) for an unknown extension.
MeshFormat format_from_path(const std::string& path);

// Parses a whole file held in memory. `source` names it in error messages.
// Polygons are split into triangle fans; STL corners with equal positions
// (+0 and -0 alike) are welded. Text may start with a UTF-8 byte order mark;
// counts in headers must match the data. Validates the result (finite
// coordinates, face indices in range, three distinct vertices per face) and
// throws a typed Error otherwise; messages count vertices and faces from 0.
Mesh parse_mesh(std::string_view bytes, MeshFormat format, const std::string& source);

// Reads `path` (format from its extension). Throws Error(CannotRead) if it
// cannot be opened, otherwise as parse_mesh.
Mesh read_mesh(const std::string& path);

struct WriteOptions {
  bool binary = true;  // PLY and STL: binary (PLY little endian) or ASCII
};

// Writes `mesh` to `path` in the format of its extension. Positions are written
// with round-trip precision (PLY as doubles; STL is a float32 format). The file
// is written to a temporary name beside `path` and renamed into place, so a
// failure leaves no partial file. Throws Error(CannotWrite).
void write_mesh(const Mesh& mesh, const std::string& path, const WriteOptions& options = {});

// Same as write_mesh but to a string (used by tests and fuzzers).
std::string serialize_mesh(const Mesh& mesh, MeshFormat format, const WriteOptions& options = {});

}  // namespace foldfill
