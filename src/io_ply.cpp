// Stanford PLY: ascii, binary_little_endian and binary_big_endian. Reads x, y, z
// of the `vertex` element and the `vertex_indices` (or `vertex_index`) list of
// the `face` element; every other property and element is skipped.
#include "io_detail.h"

namespace foldfill::io_detail {
namespace {

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

struct PlyTypeName {
  std::string_view name;
  PlyType type;
};

constexpr PlyTypeName kPlyTypeNames[] = {
    {"char", PlyType::Int8},      {"int8", PlyType::Int8},       {"uchar", PlyType::UInt8},
    {"uint8", PlyType::UInt8},    {"short", PlyType::Int16},     {"int16", PlyType::Int16},
    {"ushort", PlyType::UInt16},  {"uint16", PlyType::UInt16},   {"int", PlyType::Int32},
    {"int32", PlyType::Int32},    {"uint", PlyType::UInt32},     {"uint32", PlyType::UInt32},
    {"float", PlyType::Float32},  {"float32", PlyType::Float32}, {"double", PlyType::Float64},
    {"float64", PlyType::Float64}};

size_t type_size(PlyType type) {
  switch (type) {
    case PlyType::Int8:
    case PlyType::UInt8:
      return 1;
    case PlyType::Int16:
    case PlyType::UInt16:
      return 2;
    case PlyType::Int32:
    case PlyType::UInt32:
    case PlyType::Float32:
      return 4;
    case PlyType::Float64:
      return 8;
  }
  return 0;
}

bool is_integer(PlyType type) { return type != PlyType::Float32 && type != PlyType::Float64; }

struct PlyProperty {
  std::string name;
  PlyType type;  // of the value, or of the items of a list
  bool is_list = false;
  PlyType count_type = PlyType::UInt8;
};

struct PlyElement {
  std::string name;
  long long count = 0;
  std::vector<PlyProperty> properties;
};

enum class PlyEncoding { Ascii, BinaryLittleEndian, BinaryBigEndian };

struct PlyHeader {
  PlyEncoding encoding = PlyEncoding::Ascii;
  std::vector<PlyElement> elements;
};

// What the reader does with the values of one property.
enum class PlyRole { X, Y, Z, FaceIndices, Skip };

PlyType parse_type(const TextCursor& cursor, std::string_view name) {
  for (const PlyTypeName& entry : kPlyTypeNames) {
    if (entry.name == name) return entry.type;
  }
  cursor.fail(ErrorKind::BadFormat, "unknown PLY type " + excerpt(name));
}

PlyEncoding parse_encoding(const TextCursor& cursor, std::string_view name) {
  if (name == "ascii") return PlyEncoding::Ascii;
  if (name == "binary_little_endian") return PlyEncoding::BinaryLittleEndian;
  if (name == "binary_big_endian") return PlyEncoding::BinaryBigEndian;
  cursor.fail(ErrorKind::BadFormat, "unsupported PLY format " + excerpt(name));
}

// `property TYPE NAME` or `property list COUNT_TYPE ITEM_TYPE NAME`.
PlyProperty parse_property(TextCursor& cursor) {
  PlyProperty property;
  std::string_view type = cursor.next_word();
  if (type == "list") {
    property.is_list = true;
    property.count_type = parse_type(cursor, cursor.next_word());
    if (!is_integer(property.count_type)) {
      cursor.fail(ErrorKind::BadFormat, "PLY list count type must be an integer type");
    }
    type = cursor.next_word();
  }
  property.type = parse_type(cursor, type);
  property.name = std::string(cursor.next_word());
  if (property.name.empty()) cursor.fail(ErrorKind::BadFormat, "PLY property without a name");
  return property;
}

// `element NAME COUNT`; `vertex` and `face` may appear once.
PlyElement parse_element(TextCursor& cursor, const std::vector<PlyElement>& previous) {
  PlyElement element;
  element.name = std::string(cursor.next_word());
  element.count = cursor.next_number<long long>();
  if (element.count < 0) cursor.fail(ErrorKind::BadFormat, "negative PLY element count");
  const bool is_mesh_element = element.name == "vertex" || element.name == "face";
  for (const PlyElement& other : previous) {
    if (is_mesh_element && other.name == element.name) {
      cursor.fail(ErrorKind::BadFormat, "PLY header repeats element '" + element.name + "'");
    }
  }
  return element;
}

// Reads the header up to and including the `end_header` line.
PlyHeader parse_header(TextCursor& cursor) {
  if (cursor.next_word() != "ply" || !cursor.at_line_end()) {
    cursor.fail(ErrorKind::BadFormat, "not a PLY file (the first line must be 'ply')");
  }
  cursor.next_line();
  PlyHeader header;
  bool has_format = false;
  for (;; cursor.next_line()) {
    if (cursor.at_end()) cursor.fail(ErrorKind::BadFormat, "PLY header has no end_header line");
    const std::string_view keyword = cursor.next_word();
    if (keyword == "format") {
      header.encoding = parse_encoding(cursor, cursor.next_word());
      has_format = true;
    } else if (keyword == "element") {
      header.elements.push_back(parse_element(cursor, header.elements));
    } else if (keyword == "property") {
      if (header.elements.empty()) {
        cursor.fail(ErrorKind::BadFormat, "PLY property before any element");
      }
      header.elements.back().properties.push_back(parse_property(cursor));
    } else if (keyword == "end_header") {
      cursor.next_line();
      break;
    } else if (keyword != "comment" && keyword != "obj_info" && !keyword.empty()) {
      cursor.fail(ErrorKind::BadFormat, "unexpected PLY header keyword " + excerpt(keyword));
    }
  }
  if (!has_format) cursor.fail(ErrorKind::BadFormat, "PLY header has no format line");
  return header;
}

// Gives the vertex properties x, y and z their roles: each must be there once,
// as a scalar, since a repeated one would read into the same coordinate and
// leave another at 0.
void assign_coordinate_roles(const PlyElement& element, std::vector<PlyRole>& roles,
                             const std::string& source) {
  constexpr std::pair<const char*, PlyRole> kAxes[] = {
      {"x", PlyRole::X}, {"y", PlyRole::Y}, {"z", PlyRole::Z}};
  for (const auto& [name, role] : kAxes) {
    bool found = false;
    for (size_t p = 0; p < roles.size(); ++p) {
      const PlyProperty& property = element.properties[p];
      if (property.name != name) continue;
      if (property.is_list) {
        fail(ErrorKind::BadFormat, source,
             std::string("PLY vertex property '") + name + "' is a list; it must be a scalar");
      }
      if (found) {
        fail(ErrorKind::BadFormat, source,
             std::string("PLY vertex element has two '") + name + "' properties");
      }
      roles[p] = role;
      found = true;
    }
    if (!found) {
      fail(ErrorKind::BadFormat, source,
           std::string("PLY vertex element has no '") + name + "' property");
    }
  }
}

// Gives the face element's list of vertex indices its role: exactly one.
void assign_face_role(const PlyElement& element, std::vector<PlyRole>& roles,
                      const std::string& source) {
  const PlyProperty* found = nullptr;
  for (size_t p = 0; p < roles.size(); ++p) {
    const PlyProperty& property = element.properties[p];
    if (property.name != "vertex_indices" && property.name != "vertex_index") continue;
    if (!property.is_list) {
      fail(ErrorKind::BadFormat, source,
           "PLY face property '" + property.name + "' must be a list");
    }
    if (!is_integer(property.type)) {
      fail(ErrorKind::BadFormat, source, "PLY face indices must have an integer type");
    }
    if (found) {
      fail(ErrorKind::BadFormat, source,
           "PLY face element has two vertex index lists ('" + found->name + "' and '" +
               property.name + "')");
    }
    roles[p] = PlyRole::FaceIndices;
    found = &property;
  }
  if (!found) fail(ErrorKind::BadFormat, source, "PLY face element has no vertex_indices list");
}

// The role of each property of `element`; checks that the vertex and face
// elements have what we need.
std::vector<PlyRole> property_roles(const PlyElement& element, const std::string& source) {
  std::vector<PlyRole> roles(element.properties.size(), PlyRole::Skip);
  if (element.name == "vertex") assign_coordinate_roles(element, roles, source);
  if (element.name == "face") assign_face_role(element, roles, source);
  return roles;
}

// "the 3 faces", "the 1 item of element 'edge'": what `element` declares.
std::string declared_items(const PlyElement& element) {
  if (element.name == "vertex") return "the " + count_of(element.count, "vertex", "vertices");
  if (element.name == "face") return "the " + count_of(element.count, "face", "faces");
  return "the " + count_of(element.count, "item", "items") + " of element '" + element.name + "'";
}

// The body of an ASCII PLY file: whitespace-separated numbers.
class AsciiPlyInput {
 public:
  static constexpr bool kHasLines = true;

  AsciiPlyInput(std::string_view body, const std::string& source, int first_line)
      : cursor_(body, source, TextCursor::Separator::Lines, first_line) {}

  double number(PlyType) { return cursor_.next_number<double>(); }
  long long integer(PlyType) { return cursor_.next_number<long long>(); }
  void skip(PlyType, long long count) {
    for (long long i = 0; i < count; ++i) cursor_.next_number<double>();
  }
  void require_items(const PlyElement& element) const {
    cursor_.require_items(element.count, static_cast<int>(element.properties.size()),
                          ("items in PLY element '" + element.name + "'").c_str());
  }
  int line() const { return cursor_.line(); }
  // Throws BadFormat unless only blank space follows `last`, the last element.
  void require_end(const PlyElement& last) {
    cursor_.skip_separators();
    if (!cursor_.at_end()) {
      fail(ErrorKind::BadFormat, "data beyond " + declared_items(last) + " the header declares");
    }
  }
  [[noreturn]] void fail(ErrorKind kind, const std::string& problem) const {
    cursor_.fail(kind, problem);
  }

 private:
  TextCursor cursor_;
};

// The body of a binary PLY file, in either byte order.
class BinaryPlyInput {
 public:
  static constexpr bool kHasLines = false;

  BinaryPlyInput(std::string_view body, const std::string& source, bool little_endian)
      : bytes_(body, source, little_endian) {}

  double number(PlyType type) { return read_as<double>(type); }
  long long integer(PlyType type) { return read_as<long long>(type); }
  void skip(PlyType type, long long count) {
    bytes_.skip(static_cast<uint64_t>(count) * type_size(type));
  }
  // Each item takes at least the bytes of its scalars and list counts.
  void require_items(const PlyElement& element) const {
    uint64_t item_bytes = 0;
    for (const PlyProperty& property : element.properties) {
      item_bytes += type_size(property.is_list ? property.count_type : property.type);
    }
    if (static_cast<uint64_t>(element.count) > bytes_.remaining() / item_bytes ||
        element.count > INT_MAX) {
      fail(ErrorKind::BadFormat, "file is truncated: PLY element '" + element.name + "' claims " +
                                     std::to_string(element.count) + " items");
    }
  }
  int line() const { return 0; }
  // Throws BadFormat when bytes follow `last`, the last element. Binary data
  // has no blank space to allow for, and bytes left over mean that a count
  // lies, as data beyond an ASCII body does.
  void require_end(const PlyElement& last) const {
    if (bytes_.remaining() > 0) {
      fail(ErrorKind::BadFormat,
           count_of(static_cast<long long>(bytes_.remaining()), "byte", "bytes") + " beyond " +
               declared_items(last) + " the header declares");
    }
  }
  [[noreturn]] void fail(ErrorKind kind, const std::string& problem) const {
    bytes_.fail(kind, problem);
  }

 private:
  template <class Result>
  Result read_as(PlyType type) {
    switch (type) {
      case PlyType::Int8:
        return static_cast<Result>(bytes_.read<int8_t>());
      case PlyType::UInt8:
        return static_cast<Result>(bytes_.read<uint8_t>());
      case PlyType::Int16:
        return static_cast<Result>(bytes_.read<int16_t>());
      case PlyType::UInt16:
        return static_cast<Result>(bytes_.read<uint16_t>());
      case PlyType::Int32:
        return static_cast<Result>(bytes_.read<int32_t>());
      case PlyType::UInt32:
        return static_cast<Result>(bytes_.read<uint32_t>());
      case PlyType::Float32:
        return static_cast<Result>(bytes_.read<float>());
      case PlyType::Float64:
        return static_cast<Result>(bytes_.read<double>());
    }
    return Result{};
  }

  ByteCursor bytes_;
};

template <class Input>
long long read_list_length(Input& input, const PlyProperty& property) {
  const long long length = input.integer(property.count_type);
  if (length < 0) input.fail(ErrorKind::BadFormat, "negative PLY list length");
  return length;
}

template <class Input>
void read_polygon(Input& input, const PlyProperty& property, std::vector<int>& corners,
                  ParsedMesh& parsed) {
  const long long corner_count = input.integer(property.count_type);
  require_polygon(input, corner_count);
  corners.clear();
  for (long long c = 0; c < corner_count; ++c) {
    const long long index = input.integer(property.type);
    if (index < 0 || index > INT_MAX) {
      input.fail(ErrorKind::BadFace, "face vertex " + std::to_string(index) + " out of range");
    }
    corners.push_back(static_cast<int>(index));
  }
  append_fan(corners, parsed.mesh.faces);
  if (Input::kHasLines) {
    parsed.face_lines.insert(parsed.face_lines.end(), corners.size() - 2, input.line());
  }
}

template <class Input>
void read_element(Input& input, const PlyElement& element, const std::vector<PlyRole>& roles,
                  ParsedMesh& parsed) {
  if (element.properties.empty()) return;  // no bytes, whatever the count
  input.require_items(element);
  const bool is_vertex = element.name == "vertex";
  if (is_vertex) parsed.mesh.positions.reserve(static_cast<size_t>(element.count));
  std::vector<int> corners;
  for (long long item = 0; item < element.count; ++item) {
    Vec3 position{};
    for (size_t p = 0; p < roles.size(); ++p) {
      const PlyProperty& property = element.properties[p];
      switch (roles[p]) {
        case PlyRole::X:
        case PlyRole::Y:
        case PlyRole::Z:
          position[static_cast<int>(roles[p]) - static_cast<int>(PlyRole::X)] =
              input.number(property.type);
          break;
        case PlyRole::FaceIndices:
          read_polygon(input, property, corners, parsed);
          break;
        case PlyRole::Skip:
          input.skip(property.type, property.is_list ? read_list_length(input, property) : 1);
          break;
      }
    }
    if (is_vertex) {
      parsed.mesh.positions.push_back(position);
      if (Input::kHasLines) parsed.vertex_lines.push_back(input.line());
    }
  }
}

// Reads every element, then refuses data after the last one that has any:
// a count lower than the items that follow would silently drop them (faces
// lost open a false hole).
template <class Input>
ParsedMesh read_body(Input input, const PlyHeader& header, const std::string& source) {
  ParsedMesh parsed;
  const PlyElement* last = nullptr;
  for (const PlyElement& element : header.elements) {
    read_element(input, element, property_roles(element, source), parsed);
    if (!element.properties.empty()) last = &element;
  }
  if (last) input.require_end(*last);
  return parsed;
}

void append_header(std::string& out, const Mesh& mesh, bool binary) {
  out += "ply\nformat ";
  out += binary ? "binary_little_endian" : "ascii";
  out += " 1.0\ncomment written by foldfill\nelement vertex ";
  append_number(out, mesh.positions.size());
  out += "\nproperty double x\nproperty double y\nproperty double z\nelement face ";
  append_number(out, mesh.faces.size());
  out += "\nproperty list uchar int vertex_indices\nend_header\n";
}

}  // namespace

ParsedMesh parse_ply(std::string_view bytes, const std::string& source) {
  bytes = skip_byte_order_mark(bytes, source);
  require_line_feeds(bytes.substr(0, bytes.find("end_header")), source);  // the header's text
  TextCursor cursor(bytes, source, TextCursor::Separator::Blanks);
  const PlyHeader header = parse_header(cursor);
  if (header.encoding == PlyEncoding::Ascii) {
    require_text(cursor.rest(), source);
    return read_body(AsciiPlyInput(cursor.rest(), source, cursor.line()), header, source);
  }
  const bool little_endian = header.encoding == PlyEncoding::BinaryLittleEndian;
  return read_body(BinaryPlyInput(cursor.rest(), source, little_endian), header, source);
}

// Positions as doubles so that they read back bit for bit.
void serialize_ply(const Mesh& mesh, bool binary, ByteSink& sink) {
  std::string& out = sink.bytes();
  sink.expect(256 + mesh.positions.size() * (binary ? 24 : 64) +
              mesh.faces.size() * (binary ? 13 : 32));
  append_header(out, mesh, binary);
  for (const Vec3& p : mesh.positions) {
    if (binary) {
      for (double coordinate : p) append_little_endian(out, coordinate);
    } else {
      append_numbers_line(out, p);
    }
    sink.record_done();
  }
  for (const Tri& face : mesh.faces) {
    if (binary) {
      append_little_endian(out, uint8_t{3});
      for (int v : face) append_little_endian(out, int32_t{v});
    } else {
      out += "3 ";
      append_numbers_line(out, face);
    }
    sink.record_done();
  }
}

}  // namespace foldfill::io_detail
