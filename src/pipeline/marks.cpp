// The marks of a fill's new elements and the values of the carried data on
// them, computed from the report's counts once the patches are appended.
#include "foldfill/marks.h"

#include <cmath>
#include <string>

#include "foldfill/error.h"
#include "foldfill/metrics.h"

namespace foldfill {
namespace {

// Names of the vertex properties whose value on a new vertex is the mean
// over its hole's loop; the normal's three are renormalised together.
bool is_colour(const std::string& name) {
  return name == "red" || name == "green" || name == "blue" || name == "alpha";
}
int normal_axis(const std::string& name) {
  if (name == "nx") return 0;
  if (name == "ny") return 1;
  if (name == "nz") return 2;
  return -1;
}

// `value` as the property's type holds it: integers rounded, float rounded
// to a float (the writer writes it exactly).
double in_type(double value, ScalarType type) {
  switch (type) {
    case ScalarType::Float32:
      return static_cast<float>(value);
    case ScalarType::Float64:
      return value;
    default:
      return std::round(value);
  }
}

double loop_mean(const ScalarProperty& property, const BoundaryLoop& loop) {
  double sum = 0;
  for (int v : loop.vertices) sum += property.values[static_cast<size_t>(v)];
  return loop.vertices.empty() ? 0 : sum / static_cast<double>(loop.vertices.size());
}

// The values of the vertex properties on the new vertices of one hole.
std::vector<double> new_vertex_values(const std::vector<ScalarProperty>& properties,
                                      const BoundaryLoop& loop) {
  std::vector<double> values(properties.size(), 0.0);
  int normal[3] = {-1, -1, -1};  // the property of each axis
  for (size_t p = 0; p < properties.size(); ++p) {
    const int axis = normal_axis(properties[p].name);
    if (axis >= 0) normal[axis] = static_cast<int>(p);
    if (axis >= 0 || is_colour(properties[p].name)) values[p] = loop_mean(properties[p], loop);
  }
  if (normal[0] >= 0 && normal[1] >= 0 && normal[2] >= 0) {
    const double length =
        std::sqrt(values[normal[0]] * values[normal[0]] + values[normal[1]] * values[normal[1]] +
                  values[normal[2]] * values[normal[2]]);
    if (length > 0)
      for (int index : normal) values[index] /= length;
  }
  for (size_t p = 0; p < properties.size(); ++p) values[p] = in_type(values[p], properties[p].type);
  return values;
}

}  // namespace

void mark_new_elements(Mesh& mesh, const std::vector<BoundaryLoop>& loops, FillReport& report) {
  int new_vertices = 0, new_faces = 0;
  for (const HoleReport& hole : report.holes) {
    if (!hole.filled) continue;
    new_vertices += hole.patch_vertex_count;
    new_faces += hole.patch_face_count;
  }
  const int input_vertices = mesh.vertex_count() - new_vertices;
  const int input_faces = mesh.face_count() - new_faces;
  const auto carried_count = [](const std::vector<ScalarProperty>& properties, int fallback) {
    return properties.empty() ? fallback : static_cast<int>(properties.front().values.size());
  };
  if (input_vertices < 0 || input_faces < 0 ||
      carried_count(mesh.vertex_properties, input_vertices) != input_vertices ||
      carried_count(mesh.face_properties, input_faces) != input_faces) {
    throw InternalError("the fill's report counts " + std::to_string(new_vertices) +
                        " new vertices and " + std::to_string(new_faces) +
                        " new faces, which do not match its output");
  }
  mesh.vertex_hole.assign(static_cast<size_t>(input_vertices), -1);
  mesh.face_hole.assign(static_cast<size_t>(input_faces), -1);
  int next_vertex = input_vertices, next_face = input_faces;
  for (HoleReport& hole : report.holes) {
    if (!hole.filled) continue;
    hole.new_vertices = {next_vertex, next_vertex + hole.patch_vertex_count};
    hole.new_faces = {next_face, next_face + hole.patch_face_count};
    next_vertex = hole.new_vertices.end;
    next_face = hole.new_faces.end;
    hole.patch_area =
        total_area(mesh.positions, std::vector<Tri>(mesh.faces.begin() + hole.new_faces.first,
                                                    mesh.faces.begin() + hole.new_faces.end));
    mesh.vertex_hole.insert(mesh.vertex_hole.end(), hole.new_vertices.size(), hole.loop_id);
    mesh.face_hole.insert(mesh.face_hole.end(), hole.new_faces.size(), hole.loop_id);
    const std::vector<double> values =
        new_vertex_values(mesh.vertex_properties, loops.at(static_cast<size_t>(hole.loop_id)));
    for (size_t p = 0; p < values.size(); ++p) {
      std::vector<double>& carried = mesh.vertex_properties[p].values;
      carried.insert(carried.end(), hole.new_vertices.size(), values[p]);
    }
  }
  for (ScalarProperty& property : mesh.face_properties)
    property.values.resize(static_cast<size_t>(mesh.face_count()), 0.0);
}

}  // namespace foldfill
