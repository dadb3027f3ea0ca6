// Stanford PLY: ascii, binary_little_endian and binary_big_endian. Reads x, y, z
// of the `vertex` element and the `vertex_indices` (or `vertex_index`) list of
// the `face` element, and carries the other scalar properties of both into
// the mesh (Mesh::vertex_properties, face_properties); list properties other
// than the indices and the other elements are skipped with a warning.
#include <algorithm>
#include <cmath>
#include <limits>

#include "io/io_detail.h"

namespace foldfill::io_detail {
namespace {

using PlyType = ScalarType;

// The marks of new elements (Mesh::vertex_hole, face_hole) in a PLY file.
constexpr std::string_view kHoleProperty = "foldfill_hole";

// The names of each type, the one written first.
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

std::string_view type_name(PlyType type) {
  for (const PlyTypeName& entry : kPlyTypeNames) {
    if (entry.type == type) return entry.name;
  }
  return "double";
}

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
enum class PlyRole { X, Y, Z, FaceIndices, Carry, Hole, Skip };

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
// elements have what we need. The other scalars of vertices and faces are
// carried, an integer `foldfill_hole` as the marks; what is skipped gets a
// warning in `warnings`.
std::vector<PlyRole> property_roles(const PlyElement& element, const std::string& source,
                                    std::vector<std::string>& warnings) {
  std::vector<PlyRole> roles(element.properties.size(), PlyRole::Skip);
  const bool is_vertex = element.name == "vertex";
  const bool is_face = element.name == "face";
  if (is_vertex) assign_coordinate_roles(element, roles, source);
  if (is_face) assign_face_role(element, roles, source);
  if (!is_vertex && !is_face) {
    if (element.count > 0 && !element.properties.empty()) {
      warnings.push_back(source + ": PLY element '" + element.name +
                         "' is not carried to the output");
    }
    return roles;
  }
  bool has_marks = false;
  for (size_t p = 0; p < roles.size(); ++p) {
    const PlyProperty& property = element.properties[p];
    if (roles[p] != PlyRole::Skip) continue;
    if (property.is_list) {
      warnings.push_back(source + ": PLY " + element.name + " property '" + property.name +
                         "' is a list; it is not carried to the output");
    } else if (property.name == kHoleProperty) {
      // Carried, it would clash with the marks the output gets.
      if (!is_integer(property.type) || has_marks) {
        warnings.push_back(source + ": PLY " + element.name + " property '" + property.name +
                           "' is not an integer or is repeated; it is not carried to the output");
        continue;
      }
      roles[p] = PlyRole::Hole;
      has_marks = true;
    } else {
      roles[p] = PlyRole::Carry;
    }
  }
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

  // A float property's value is the float nearest to its text, as in a
  // binary file.
  double number(PlyType type) {
    if (type == PlyType::Float32) return cursor_.next_number<float>();
    return cursor_.next_number<double>();
  }
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

// Reads a polygon and appends its fan; returns the number of triangles.
template <class Input>
size_t read_polygon(Input& input, const PlyProperty& property, std::vector<int>& corners,
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
  return corners.size() - 2;
}

// Where the carried properties of `element` go: the mesh's vertex or face
// properties, or nowhere (nullptr) for another element.
std::vector<ScalarProperty>* carried_of(const PlyElement& element, Mesh& mesh) {
  if (element.name == "vertex") return &mesh.vertex_properties;
  if (element.name == "face") return &mesh.face_properties;
  return nullptr;
}

// Appends the properties of `element` that are carried to `carried`; returns
// each property's position among them (or -1).
std::vector<int> carried_properties(const PlyElement& element, const std::vector<PlyRole>& roles,
                                    std::vector<ScalarProperty>& carried) {
  std::vector<int> slot(roles.size(), -1);
  for (size_t p = 0; p < roles.size(); ++p) {
    if (roles[p] != PlyRole::Carry) continue;
    slot[p] = static_cast<int>(carried.size());
    carried.push_back({element.properties[p].name, element.properties[p].type, {}});
    carried.back().values.reserve(static_cast<size_t>(element.count));
  }
  return slot;
}

template <class Input>
void read_element(Input& input, const PlyElement& element, const std::vector<PlyRole>& roles,
                  ParsedMesh& parsed) {
  if (element.properties.empty()) return;  // no bytes, whatever the count
  input.require_items(element);
  const bool is_vertex = element.name == "vertex";
  if (is_vertex) parsed.mesh.positions.reserve(static_cast<size_t>(element.count));
  std::vector<ScalarProperty> none;  // an element whose properties are not carried
  std::vector<ScalarProperty>* target = carried_of(element, parsed.mesh);
  std::vector<ScalarProperty>& carried = target ? *target : none;
  const std::vector<int> slot = carried_properties(element, roles, carried);
  std::vector<int>* marks = nullptr;
  if (std::find(roles.begin(), roles.end(), PlyRole::Hole) != roles.end())
    marks = is_vertex ? &parsed.mesh.vertex_hole : &parsed.mesh.face_hole;
  std::vector<int> corners;
  std::vector<double> values(carried.size());  // of the item's carried properties
  for (long long item = 0; item < element.count; ++item) {
    Vec3 position{};
    size_t triangles = 1;  // the mesh elements the item becomes
    long long hole = -1;   // its mark
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
          triangles = read_polygon(input, property, corners, parsed);
          break;
        case PlyRole::Carry:
          values[static_cast<size_t>(slot[p])] = input.number(property.type);
          break;
        case PlyRole::Hole:
          hole = input.integer(property.type);
          if (hole < -1 || hole > INT_MAX) {
            input.fail(ErrorKind::BadFormat,
                       "PLY foldfill_hole " + std::to_string(hole) + " is not -1 or a loop id");
          }
          break;
        case PlyRole::Skip:
          input.skip(property.type, property.is_list ? read_list_length(input, property) : 1);
          break;
      }
    }
    // Every triangle of a polygon's fan has the polygon's values.
    for (size_t k = 0; k < values.size(); ++k)
      carried[k].values.insert(carried[k].values.end(), triangles, values[k]);
    if (marks) marks->insert(marks->end(), triangles, static_cast<int>(hole));
    if (is_vertex) {
      parsed.mesh.positions.push_back(position);
      if (Input::kHasLines) parsed.vertex_lines.push_back(input.line());
    }
  }
}

// Float32 when x, y and z are all float, else Float64 (integer coordinates
// are written as doubles, which hold them and the new vertices' exactly).
PlyType coordinate_type(const PlyElement& vertex) {
  for (const PlyProperty& property : vertex.properties) {
    if ((property.name == "x" || property.name == "y" || property.name == "z") &&
        property.type != PlyType::Float32)
      return PlyType::Float64;
  }
  return PlyType::Float32;
}

// Reads every element, then refuses data after the last one that has any:
// a count lower than the items that follow would silently drop them (faces
// lost open a false hole).
template <class Input>
ParsedMesh read_body(Input input, const PlyHeader& header, const std::string& source) {
  ParsedMesh parsed;
  const PlyElement* last = nullptr;
  for (const PlyElement& element : header.elements) {
    read_element(input, element, property_roles(element, source, parsed.warnings), parsed);
    if (element.name == "vertex") parsed.mesh.coordinate_type = coordinate_type(element);
    if (!element.properties.empty()) last = &element;
  }
  if (last) input.require_end(*last);
  return parsed;
}

// `value` in `type`: integers rounded to the nearest and clamped to the
// type's range (NaN becomes 0), float rounded to the nearest float.
template <class T>
T to_scalar(double value) {
  if constexpr (std::is_integral_v<T>) {
    if (std::isnan(value)) return T{0};
    const double rounded = std::round(value);
    if (rounded <= static_cast<double>(std::numeric_limits<T>::min()))
      return std::numeric_limits<T>::min();
    if (rounded >= static_cast<double>(std::numeric_limits<T>::max()))
      return std::numeric_limits<T>::max();
    return static_cast<T>(rounded);
  } else {
    return static_cast<T>(value);
  }
}

template <class T>
void append_as(std::string& out, double value, bool binary) {
  const T scalar = to_scalar<T>(value);
  if (binary) {
    append_little_endian(out, scalar);
  } else if constexpr (sizeof(T) == 1) {
    append_number(out, static_cast<int>(scalar));  // a number, not a character
  } else {
    append_number(out, scalar);
  }
}

// Appends `value` as a `type` value: binary, or as the shortest text that
// reads back as it.
void append_scalar(std::string& out, PlyType type, double value, bool binary) {
  switch (type) {
    case PlyType::Int8:
      return append_as<int8_t>(out, value, binary);
    case PlyType::UInt8:
      return append_as<uint8_t>(out, value, binary);
    case PlyType::Int16:
      return append_as<int16_t>(out, value, binary);
    case PlyType::UInt16:
      return append_as<uint16_t>(out, value, binary);
    case PlyType::Int32:
      return append_as<int32_t>(out, value, binary);
    case PlyType::UInt32:
      return append_as<uint32_t>(out, value, binary);
    case PlyType::Float32:
      return append_as<float>(out, value, binary);
    case PlyType::Float64:
      return append_as<double>(out, value, binary);
  }
}

void append_property(std::string& out, PlyType type, std::string_view name) {
  out += "property ";
  out += type_name(type);
  out += ' ';
  out += name;
  out += '\n';
}

void append_header(std::string& out, const Mesh& mesh, bool binary) {
  out += "ply\nformat ";
  out += binary ? "binary_little_endian" : "ascii";
  out += " 1.0\ncomment written by foldfill\nelement vertex ";
  append_number(out, mesh.positions.size());
  out += '\n';
  for (const char* axis : {"x", "y", "z"}) append_property(out, mesh.coordinate_type, axis);
  for (const ScalarProperty& property : mesh.vertex_properties)
    append_property(out, property.type, property.name);
  if (!mesh.vertex_hole.empty()) append_property(out, PlyType::Int32, kHoleProperty);
  out += "element face ";
  append_number(out, mesh.faces.size());
  out += "\nproperty list uchar int vertex_indices\n";
  for (const ScalarProperty& property : mesh.face_properties)
    append_property(out, property.type, property.name);
  if (!mesh.face_hole.empty()) append_property(out, PlyType::Int32, kHoleProperty);
  out += "end_header\n";
}

// The bytes of one vertex or face after its geometry: its carried
// properties, then its mark.
void append_extras(std::string& out, const std::vector<ScalarProperty>& properties,
                   const std::vector<int>& hole, size_t element, bool binary) {
  for (const ScalarProperty& property : properties) {
    if (!binary) out += ' ';
    append_scalar(out, property.type, property.values[element], binary);
  }
  if (!hole.empty()) {
    if (!binary) out += ' ';
    append_scalar(out, PlyType::Int32, hole[element], binary);
  }
  if (!binary) out += '\n';
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

// Positions in the input's coordinate type (doubles by default), so that
// the original vertices read back bit for bit.
void serialize_ply(const Mesh& mesh, bool binary, ByteSink& sink) {
  std::string& out = sink.bytes();
  const size_t vertex_bytes = (mesh.coordinate_type == PlyType::Float32 ? 12 : 24) +
                              mesh.vertex_properties.size() * 8 +
                              (mesh.vertex_hole.empty() ? 0 : 4);
  const size_t face_bytes = 13 + mesh.face_properties.size() * 8 + (mesh.face_hole.empty() ? 0 : 4);
  sink.expect(256 + mesh.positions.size() * (binary ? vertex_bytes : 3 * vertex_bytes) +
              mesh.faces.size() * (binary ? face_bytes : 3 * face_bytes));
  append_header(out, mesh, binary);
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    for (int k = 0; k < 3; ++k) {
      if (!binary && k > 0) out += ' ';
      append_scalar(out, mesh.coordinate_type, mesh.positions[v][k], binary);
    }
    append_extras(out, mesh.vertex_properties, mesh.vertex_hole, v, binary);
    sink.record_done();
  }
  for (size_t f = 0; f < mesh.faces.size(); ++f) {
    if (binary) {
      append_little_endian(out, uint8_t{3});
      for (int v : mesh.faces[f]) append_little_endian(out, int32_t{v});
    } else {
      out += '3';
      for (int v : mesh.faces[f]) {
        out += ' ';
        append_number(out, v);
      }
    }
    append_extras(out, mesh.face_properties, mesh.face_hole, f, binary);
    sink.record_done();
  }
}

}  // namespace foldfill::io_detail
