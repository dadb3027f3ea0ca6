// STL, ASCII or binary (80-byte header, uint32 facet count, 50 bytes per
// facet). STL is a float32 format by nature: positions are read as float32 and
// written as float32, so only float32-representable positions round-trip.
// Facets carry their own corners; corners with equal positions are welded into
// one vertex, vertices numbered by first occurrence.
#include <cmath>

#include "io/io_detail.h"

namespace foldfill::io_detail {
namespace {

using StlPoint = std::array<float, 3>;

constexpr size_t kHeaderBytes = 80;
constexpr size_t kFacetBytes = 50;  // normal, 3 corners (12 floats), uint16 attribute

uint64_t mix_bits(uint64_t bits) {
  bits ^= bits >> 33;
  bits *= 0xff51afd7ed558ccdULL;
  bits ^= bits >> 33;
  return bits;
}

// Equal points hash alike: -0 is hashed as +0, the one pair of distinct float
// bit patterns that compare equal.
uint64_t hash_point(const StlPoint& point) {
  uint32_t bits[3];
  for (int k = 0; k < 3; ++k) {
    const float value = point[k] == 0 ? 0.0f : point[k];
    std::memcpy(&bits[k], &value, sizeof(float));
  }
  return mix_bits((uint64_t{bits[0]} << 32 | bits[1]) ^ mix_bits(bits[2]));
}

// Corners are the same vertex when they compare equal, so that +0 and -0 weld
// (exporters write both, and a sheet would crack along a zero coordinate), or
// when their bits are identical, so that a repeated NaN corner stays one vertex;
// validation then refuses the NaN.
bool same_point(const StlPoint& a, const StlPoint& b) {
  return (a[0] == b[0] && a[1] == b[1] && a[2] == b[2]) ||
         std::memcmp(a.data(), b.data(), sizeof(StlPoint)) == 0;
}

// Welds `corners` (three per facet) by an open-addressing table; each vertex
// keeps the bits of its first corner. `corner_lines` (ASCII) gives the lines
// of the vertices.
ParsedMesh weld(const std::vector<StlPoint>& corners, std::vector<int> face_lines,
                const std::vector<int>& corner_lines = {}) {
  ParsedMesh parsed;
  parsed.face_lines = std::move(face_lines);
  size_t capacity = 16;
  while (capacity < 2 * corners.size()) capacity *= 2;
  std::vector<int> slots(capacity, -1);  // vertex index, or -1 when free
  std::vector<size_t> first_corner;      // of each vertex
  std::vector<int> corner_vertex(corners.size());
  for (size_t c = 0; c < corners.size(); ++c) {
    size_t slot = hash_point(corners[c]) & (capacity - 1);
    while (slots[slot] >= 0 && !same_point(corners[first_corner[slots[slot]]], corners[c])) {
      slot = (slot + 1) & (capacity - 1);
    }
    if (slots[slot] < 0) {
      slots[slot] = static_cast<int>(first_corner.size());
      first_corner.push_back(c);
      const StlPoint& p = corners[c];
      parsed.mesh.positions.push_back({p[0], p[1], p[2]});
      if (!corner_lines.empty()) parsed.vertex_lines.push_back(corner_lines[c]);
    }
    corner_vertex[c] = slots[slot];
  }
  parsed.mesh.faces.resize(corners.size() / 3);
  for (size_t f = 0; f < parsed.mesh.faces.size(); ++f) {
    parsed.mesh.faces[f] = {corner_vertex[3 * f], corner_vertex[3 * f + 1],
                            corner_vertex[3 * f + 2]};
  }
  return parsed;
}

// The facet count of a binary STL when `bytes` has exactly the size it implies.
bool is_binary_stl(std::string_view bytes, uint64_t& facet_count) {
  if (bytes.size() < kHeaderBytes + 4) return false;
  uint32_t count;
  std::memcpy(&count, bytes.data() + kHeaderBytes, 4);
  facet_count = kHostLittleEndian ? count : byte_swapped(count);
  return bytes.size() == kHeaderBytes + 4 + kFacetBytes * facet_count;
}

ParsedMesh parse_binary(std::string_view bytes, uint64_t facet_count, const std::string& source) {
  if (facet_count > INT_MAX / 3) fail(ErrorKind::BadFormat, source, "too many STL facets");
  ByteCursor cursor(bytes, source, true);
  cursor.skip(kHeaderBytes + 4);
  std::vector<StlPoint> corners(3 * facet_count);
  for (size_t c = 0; c < corners.size(); c += 3) {
    cursor.skip(3 * sizeof(float));  // the stored normal, recomputed on writing
    for (size_t k = 0; k < 3; ++k) {
      for (float& coordinate : corners[c + k]) coordinate = cursor.read<float>();
    }
    cursor.skip(2);  // attribute byte count
  }
  return weld(corners, {});
}

// `facet normal nx ny nz outer loop vertex x y z (x3) endloop endfacet`, after `facet`.
void read_ascii_facet(TextCursor& cursor, std::vector<StlPoint>& corners,
                      std::vector<int>& corner_lines) {
  cursor.expect_word("normal");
  for (int i = 0; i < 3; ++i) cursor.next_number<float>();
  cursor.expect_word("outer");
  cursor.expect_word("loop");
  for (int k = 0; k < 3; ++k) {
    cursor.expect_word("vertex");
    StlPoint corner;
    for (float& coordinate : corner) coordinate = cursor.next_number<float>();
    corners.push_back(corner);
    corner_lines.push_back(cursor.line());
  }
  cursor.expect_word("endloop");
  cursor.expect_word("endfacet");
}

// One or more `solid NAME ... endsolid NAME` blocks in `text` (without a byte
// order mark or NUL bytes).
ParsedMesh parse_ascii(std::string_view text, const std::string& source) {
  TextCursor cursor(text, source, TextCursor::Separator::Lines);
  std::vector<StlPoint> corners;
  std::vector<int> corner_lines;
  std::vector<int> face_lines;
  std::string_view word = cursor.next_word();
  do {
    if (word != "solid")
      cursor.fail(ErrorKind::BadFormat, "expected 'solid', found " + excerpt(word));
    cursor.next_line();  // the solid's name
    while ((word = cursor.next_word()) == "facet") {
      face_lines.push_back(cursor.line());
      read_ascii_facet(cursor, corners, corner_lines);
    }
    if (word != "endsolid") {
      cursor.fail(ErrorKind::BadFormat, "expected 'facet' or 'endsolid', found " +
                                            (word.empty() ? "the end of the file" : excerpt(word)));
    }
    cursor.next_line();
    word = cursor.next_word();
  } while (!word.empty());
  return weld(corners, std::move(face_lines), corner_lines);
}

bool starts_with_solid(std::string_view bytes) {
  const size_t start = bytes.find_first_not_of(" \t\r\n");
  return start != std::string_view::npos && bytes.substr(start, 5) == "solid";
}

// "solid" as UTF-16 text after its byte order mark, in either byte order.
bool starts_with_utf16_solid(std::string_view bytes) {
  return starts_with(bytes, {"\xFF\xFEs\0o\0l\0i\0d\0", 12}) ||
         starts_with(bytes, {"\xFE\xFF\0s\0o\0l\0i\0d", 12});
}

// Why `bytes`, not of the size their facet count implies, are no binary STL.
std::string binary_size_problem(std::string_view bytes) {
  if (bytes.size() < kHeaderBytes + 4) {
    return "too short: it has " + std::to_string(bytes.size()) + " bytes, fewer than the " +
           std::to_string(kHeaderBytes + 4) + " of its header and facet count";
  }
  uint64_t facet_count = 0;
  is_binary_stl(bytes, facet_count);
  return "truncated or padded: it claims " + std::to_string(facet_count) + " facets (" +
         std::to_string(kHeaderBytes + 4 + kFacetBytes * facet_count) + " bytes) but has " +
         std::to_string(bytes.size()) + " bytes";
}

// A file that starts with `solid` is ASCII STL, unless it is not text: some
// binary STL headers start with `solid` too, and a truncated one would
// otherwise be reported as binary data in a text file. Text that fails as
// ASCII STL but is long enough for binary STL gets both readings' problems.
ParsedMesh parse_solid(std::string_view bytes, std::string_view text, const std::string& source) {
  if (text.find('\0') != std::string_view::npos) {
    fail(ErrorKind::BadFormat, source, "binary STL is " + binary_size_problem(bytes));
  }
  require_line_feeds(text, source);
  try {
    return parse_ascii(text, source);
  } catch (const Error& error) {
    if (bytes.size() < kHeaderBytes + 4) throw;
    const std::string problem = std::string(error.what()).substr(source.size() + 2);
    fail(
        ErrorKind::BadFormat, source,
        "not valid ASCII STL (" + problem + "); as binary STL it is " + binary_size_problem(bytes));
  }
}

// The unit normal of `face` in float32, or zero for a degenerate face.
StlPoint facet_normal(const Mesh& mesh, const Tri& face) {
  const Vec3& a = mesh.positions[face[0]];
  const Vec3& b = mesh.positions[face[1]];
  const Vec3& c = mesh.positions[face[2]];
  const Vec3 ab{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const Vec3 ac{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const Vec3 n{ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2],
               ab[0] * ac[1] - ab[1] * ac[0]};
  const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (!(length > 0)) return {0.0f, 0.0f, 0.0f};
  return {static_cast<float>(n[0] / length), static_cast<float>(n[1] / length),
          static_cast<float>(n[2] / length)};
}

StlPoint to_float(const Vec3& p) {
  return {static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])};
}

void serialize_binary(const Mesh& mesh, ByteSink& sink) {
  std::string& out = sink.bytes();
  sink.expect(kHeaderBytes + 4 + kFacetBytes * mesh.faces.size());
  out += "binary STL written by foldfill";  // must not start with "solid"
  out.resize(kHeaderBytes, ' ');
  append_little_endian(out, static_cast<uint32_t>(mesh.faces.size()));
  for (const Tri& face : mesh.faces) {
    for (float coordinate : facet_normal(mesh, face)) append_little_endian(out, coordinate);
    for (int v : face) {
      for (float coordinate : to_float(mesh.positions[v])) append_little_endian(out, coordinate);
    }
    append_little_endian(out, uint16_t{0});
    sink.record_done();
  }
}

void serialize_ascii(const Mesh& mesh, ByteSink& sink) {
  std::string& out = sink.bytes();
  out += "solid foldfill\n";
  for (const Tri& face : mesh.faces) {
    out += "  facet normal ";
    append_numbers_line(out, facet_normal(mesh, face));
    out += "    outer loop\n";
    for (int v : face) {
      out += "      vertex ";
      append_numbers_line(out, to_float(mesh.positions[v]));
    }
    out += "    endloop\n  endfacet\n";
    sink.record_done();
  }
  out += "endsolid foldfill\n";
}

}  // namespace

// Binary or ASCII is decided first, by the size: a binary header is 80
// arbitrary bytes, which may start with a byte order mark or `solid`.
ParsedMesh parse_stl(std::string_view bytes, const std::string& source) {
  uint64_t facet_count = 0;
  if (is_binary_stl(bytes, facet_count)) return parse_binary(bytes, facet_count, source);
  const std::string_view text =
      starts_with(bytes, kUtf8ByteOrderMark) ? bytes.substr(kUtf8ByteOrderMark.size()) : bytes;
  if (starts_with_solid(text)) return parse_solid(bytes, text, source);
  if (starts_with_utf16_solid(bytes)) skip_byte_order_mark(bytes, source);  // refuses it
  if (bytes.size() < kHeaderBytes + 4) {
    fail(ErrorKind::BadFormat, source, "not an STL file (no 'solid' and too short for binary)");
  }
  fail(ErrorKind::BadFormat, source, "binary STL is " + binary_size_problem(bytes));
}

void serialize_stl(const Mesh& mesh, bool binary, ByteSink& sink) {
  if (binary) {
    serialize_binary(mesh, sink);
  } else {
    serialize_ascii(mesh, sink);
  }
}

}  // namespace foldfill::io_detail
