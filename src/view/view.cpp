// The page of `foldfill view`: HTML with three.js, the page's own script and
// the meshes as one base64 binary blob described by a JSON header.
#include "foldfill/view.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <numeric>
#include <optional>
#include <string_view>
#include <unordered_map>
#include <utility>

#include "foldfill/error.h"
#include "foldfill/holes.h"
#include "foldfill/vec3.h"

namespace foldfill {
namespace assets {
// Generated at build time (src/view/embed_assets.cpp): the files of src/view/ and
// three.js (empty when the build had no node_modules/three).
std::string_view view_html();
std::string_view view_css();
std::string_view view_js();
std::string_view three_js();
}  // namespace assets

namespace {

uint64_t edge_key(int a, int b) {
  const auto lo = static_cast<uint32_t>(std::min(a, b)), hi = static_cast<uint32_t>(std::max(a, b));
  return (static_cast<uint64_t>(lo) << 32) | hi;
}

// Vertices on an edge that only one face has.
std::vector<char> boundary_vertices(const Mesh& mesh) {
  std::vector<uint64_t> edges;
  edges.reserve(mesh.faces.size() * 3);
  for (const Tri& f : mesh.faces)
    for (int k = 0; k < 3; ++k) edges.push_back(edge_key(f[k], f[(k + 1) % 3]));
  std::sort(edges.begin(), edges.end());
  std::vector<char> boundary(mesh.positions.size(), 0);
  for (size_t i = 0; i < edges.size();) {
    size_t j = i + 1;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if (j - i == 1) {
      boundary[edges[i] >> 32] = 1;
      boundary[edges[i] & 0xffffffffu] = 1;
    }
    i = j;
  }
  return boundary;
}

int find_root(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// The bytes of the page's buffers, each at a multiple of 4 bytes so that the
// page can view it as a typed array in place.
class Blob {
 public:
  enum class Type { Float32, Uint32, Uint8 };

  // Returns the buffer's description for the page's header.
  template <typename T>
  nlohmann::json add(const std::vector<T>& values, Type type) {
    while (bytes_.size() % 4 != 0) bytes_.push_back(0);
    const size_t offset = bytes_.size();
    bytes_.resize(offset + values.size() * sizeof(T));
    if (!values.empty())
      std::memcpy(bytes_.data() + offset, values.data(), values.size() * sizeof(T));
    static constexpr const char* kNames[] = {"float32", "uint32", "uint8"};
    return {
        {"type", kNames[static_cast<int>(type)]}, {"offset", offset}, {"length", values.size()}};
  }
  const std::vector<unsigned char>& bytes() const { return bytes_; }

 private:
  std::vector<unsigned char> bytes_;
};

// Curvature values as bytes: 0 for none (NaN), 1..255 for [-range, range],
// clamped.
std::vector<uint8_t> quantized(const std::vector<float>& values, double range) {
  std::vector<uint8_t> out(values.size(), 0);
  for (size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) continue;
    const double t = std::clamp(values[i] / range, -1.0, 1.0);
    out[i] = static_cast<uint8_t>(1 + std::lround((t + 1) / 2 * 254));
  }
  return out;
}

// The colour range of a curvature: the 95th percentile of its magnitude over
// every mesh, so that a few spikes do not wash out the rest.
double robust_range(const std::vector<const std::vector<float>*>& all) {
  std::vector<float> magnitudes;
  for (const auto* values : all)
    for (float v : *values)
      if (std::isfinite(v)) magnitudes.push_back(std::abs(v));
  if (magnitudes.empty()) return 1;
  const size_t k = std::min(magnitudes.size() - 1, magnitudes.size() * 95 / 100);
  std::nth_element(magnitudes.begin(), magnitudes.begin() + static_cast<long>(k), magnitudes.end());
  const double range = magnitudes[k];
  return range > 0 && std::isfinite(range) ? range : 1;
}

bool starts_with(const Mesh& filled, const Mesh& input) {
  if (filled.positions.size() < input.positions.size() || filled.faces.size() < input.faces.size())
    return false;
  return std::equal(input.positions.begin(), input.positions.end(), filled.positions.begin()) &&
         std::equal(input.faces.begin(), input.faces.end(), filled.faces.begin());
}

// What the page shows of one mesh, before it goes into the blob.
struct Panel {
  std::string name;
  const Mesh* mesh = nullptr;
  std::vector<uint32_t> index;  // faces, the input's own first, then hole by hole
  nlohmann::json groups = nlohmann::json::array();
  std::vector<int> holes;  // the hole ids of its groups
  Curvatures curvatures;
  bool shows_loops = false;  // the input's loops index its vertices
};

Panel make_panel(const ViewMesh& view_mesh, int input_face_count,
                 const std::vector<std::vector<int>>& loop_vertices,
                 const std::vector<int>& loop_ids) {
  Panel panel;
  panel.name = view_mesh.name;
  panel.mesh = view_mesh.mesh;
  const Mesh& mesh = *view_mesh.mesh;
  const std::vector<int> hole = face_holes(mesh, input_face_count, loop_vertices, loop_ids);
  // The input's faces (-1) first, then by loop id, unknown holes last.
  auto rank = [](int h) { return h == kUnknownHole ? std::numeric_limits<int>::max() : h; };
  std::vector<int> order(mesh.faces.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return rank(hole[a]) < rank(hole[b]); });
  panel.index.reserve(mesh.faces.size() * 3);
  for (size_t i = 0; i < order.size();) {
    size_t j = i;
    while (j < order.size() && hole[order[j]] == hole[order[i]]) ++j;
    panel.groups.push_back({{"hole", hole[order[i]]}, {"start", i}, {"count", j - i}});
    if (hole[order[i]] != -1) panel.holes.push_back(hole[order[i]]);
    i = j;
  }
  for (int f : order)
    for (int k = 0; k < 3; ++k) panel.index.push_back(static_cast<uint32_t>(mesh.faces[f][k]));
  panel.curvatures = vertex_curvatures(mesh);
  return panel;
}

std::vector<float> float_positions(const Mesh& mesh) {
  std::vector<float> out;
  out.reserve(mesh.positions.size() * 3);
  for (const Vec3& p : mesh.positions)
    for (double c : p) out.push_back(static_cast<float>(c));
  return out;
}

// The per-hole figures of a report that the page's table shows, by loop id.
nlohmann::json report_rows(const nlohmann::json& report) {
  nlohmann::json rows = nlohmann::json::array();
  if (!report.is_object() || !report.contains("holes") || !report["holes"].is_array()) return rows;
  auto at = [](const nlohmann::json& object, std::initializer_list<const char*> path) {
    const nlohmann::json* node = &object;
    for (const char* key : path) {
      if (!node->is_object() || !node->contains(key)) return nlohmann::json(nullptr);
      node = &(*node)[key];
    }
    return *node;
  };
  for (const nlohmann::json& hole : report["holes"]) {
    rows.push_back({{"loop_id", at(hole, {"loop_id"})},
                    {"filled", at(hole, {"filled"})},
                    {"patch_vertex_count", at(hole, {"patch_vertex_count"})},
                    {"patch_face_count", at(hole, {"patch_face_count"})},
                    {"iterations", at(hole, {"iterations"})},
                    {"stop_reason", at(hole, {"stop_reason"})},
                    {"seconds", at(hole, {"seconds", "total"})},
                    {"energy", at(hole, {"energy", "final", "total"})},
                    {"area_ratio_to_flat", at(hole, {"area_ratio_to_flat"})},
                    {"edge_length_rms_rel", at(hole, {"edge_length_rms_rel", "final"})},
                    {"gaussian_curvature", at(hole, {"gaussian_curvature", "final", "mean_abs"})},
                    {"min_angle_deg", at(hole, {"patch_min_angle_deg"})},
                    {"min_distance", at(hole, {"min_distance"})},
                    {"self_intersections", at(hole, {"self_intersections"})},
                    {"warning", at(hole, {"warning"})}});
  }
  return rows;
}

// JSON that can sit inside a <script> element: "</" cannot end it early.
std::string script_safe_json(const nlohmann::json& value) {
  const std::string text = value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '<' && i + 1 < text.size() && text[i + 1] == '/') {
      out += "<\\/";
      ++i;
    } else {
      out += text[i];
    }
  }
  return out;
}

std::string html_escaped(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

// Text that an HTML <script> element holds as it is: nothing in it could end
// the element or switch the parser's script states.
bool script_safe(std::string_view text) {
  std::string lower(text);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return lower.find("</script") == std::string::npos && lower.find("<!--") == std::string::npos;
}

}  // namespace

Curvatures vertex_curvatures(const Mesh& mesh) {
  const size_t n = mesh.positions.size();
  std::vector<double> angle_sum(n, 0), area(n, 0);
  std::vector<Vec3> laplacian(n, Vec3{0, 0, 0}), normal(n, Vec3{0, 0, 0});
  for (const Tri& f : mesh.faces) {
    const Vec3 p[3] = {mesh.positions[f[0]], mesh.positions[f[1]], mesh.positions[f[2]]};
    const Vec3 face_normal = cross(sub(p[1], p[0]), sub(p[2], p[0]));  // twice the area
    const double face_area = 0.5 * norm(face_normal);
    for (int k = 0; k < 3; ++k) {
      const int i = f[k], j = f[(k + 1) % 3], l = f[(k + 2) % 3];
      const Vec3 u = sub(p[(k + 1) % 3], p[k]), v = sub(p[(k + 2) % 3], p[k]);
      const double sine = norm(cross(u, v)), cosine = dot(u, v);
      angle_sum[i] += std::atan2(sine, cosine);
      area[i] += face_area / 3;
      for (int c = 0; c < 3; ++c) normal[i][c] += face_normal[c];
      // The angle at i weighs the opposite edge (j, l).
      if (sine > 0) {
        const double weight = 0.5 * cosine / sine;
        const Vec3 d = sub(mesh.positions[l], mesh.positions[j]);
        for (int c = 0; c < 3; ++c) {
          laplacian[j][c] += weight * d[c];
          laplacian[l][c] -= weight * d[c];
        }
      }
    }
  }
  const std::vector<char> boundary = boundary_vertices(mesh);
  Curvatures out;
  out.gaussian.assign(n, NAN);
  out.mean.assign(n, NAN);
  for (size_t i = 0; i < n; ++i) {
    const double length = norm(normal[i]);
    if (boundary[i] || !(area[i] > 0) || !(length > 0)) continue;
    out.gaussian[i] = static_cast<float>((2 * M_PI - angle_sum[i]) / area[i]);
    const Vec3 unit{normal[i][0] / length, normal[i][1] / length, normal[i][2] / length};
    out.mean[i] = static_cast<float>(-0.5 * dot(laplacian[i], unit) / area[i]);
  }
  return out;
}

std::vector<int> face_holes(const Mesh& filled, int input_face_count,
                            const std::vector<std::vector<int>>& loop_vertices,
                            const std::vector<int>& loop_ids) {
  const int face_count = filled.face_count();
  if (!filled.face_hole.empty() && filled.face_hole.size() == filled.faces.size()) {
    std::vector<int> marks = filled.face_hole;
    for (int& mark : marks)
      if (mark < -1) mark = kUnknownHole;
    return marks;
  }
  std::vector<int> hole(face_count, -1);
  const int first = std::clamp(input_face_count, 0, face_count);
  if (first == face_count) return hole;
  std::unordered_map<uint64_t, int> loop_of_edge;
  for (size_t l = 0; l < loop_vertices.size(); ++l) {
    const std::vector<int>& loop = loop_vertices[l];
    for (size_t k = 0; k < loop.size(); ++k)
      loop_of_edge.emplace(edge_key(loop[k], loop[(k + 1) % loop.size()]), loop_ids[l]);
  }
  // The pieces of new faces, through their shared edges.
  const int count = face_count - first;
  std::vector<int> parent(count), label(count, kUnknownHole);
  std::iota(parent.begin(), parent.end(), 0);
  std::unordered_map<uint64_t, int> face_of_edge;
  face_of_edge.reserve(static_cast<size_t>(count) * 2);
  for (int f = 0; f < count; ++f) {
    const Tri& tri = filled.faces[first + f];
    for (int k = 0; k < 3; ++k) {
      const uint64_t key = edge_key(tri[k], tri[(k + 1) % 3]);
      if (const auto loop = loop_of_edge.find(key); loop != loop_of_edge.end())
        label[f] = loop->second;
      const auto [other, inserted] = face_of_edge.emplace(key, f);
      if (!inserted) parent[find_root(parent, f)] = find_root(parent, other->second);
    }
  }
  std::vector<int> piece_label(count, kUnknownHole);
  for (int f = 0; f < count; ++f) {
    if (label[f] != kUnknownHole) piece_label[find_root(parent, f)] = label[f];
  }
  for (int f = 0; f < count; ++f) hole[first + f] = piece_label[find_root(parent, f)];
  return hole;
}

bool view_available() { return !assets::three_js().empty(); }

std::string base64(const void* data, size_t size) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* bytes = static_cast<const unsigned char*>(data);
  std::string out;
  out.resize((size + 2) / 3 * 4);
  size_t o = 0, i = 0;
  for (; i + 2 < size; i += 3) {
    const uint32_t v = (bytes[i] << 16) | (bytes[i + 1] << 8) | bytes[i + 2];
    out[o++] = kAlphabet[v >> 18];
    out[o++] = kAlphabet[(v >> 12) & 63];
    out[o++] = kAlphabet[(v >> 6) & 63];
    out[o++] = kAlphabet[v & 63];
  }
  if (i < size) {
    const uint32_t v = (bytes[i] << 16) | (i + 1 < size ? bytes[i + 1] << 8 : 0);
    out[o++] = kAlphabet[v >> 18];
    out[o++] = kAlphabet[(v >> 12) & 63];
    out[o++] = i + 1 < size ? kAlphabet[(v >> 6) & 63] : '=';
    out[o++] = '=';
  }
  return out;
}

std::string view_page(const ViewMesh& input, const std::vector<ViewMesh>& filled,
                      const ViewOptions& options, std::vector<std::string>* warnings) {
  if (!view_available()) {
    throw UsageError(kViewUnavailable);
  }
  if (!script_safe(assets::three_js()) || !script_safe(assets::view_js())) {
    throw InternalError("the page's scripts cannot be inlined as they are");
  }

  // The input's loops, outlined in every panel whose mesh starts with the input.
  std::vector<BoundaryLoop> loops;
  try {
    loops = find_boundary_loops(*input.mesh, input.name);
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::NonManifold) throw;
    if (warnings) warnings->push_back(std::string(e.what()) + "; its loops are not outlined");
  }
  std::vector<std::vector<int>> loop_vertices;
  std::vector<int> loop_ids;
  for (const BoundaryLoop& loop : loops) {
    loop_vertices.push_back(loop.vertices);
    loop_ids.push_back(loop.id);
  }

  std::vector<Panel> panels;
  panels.push_back(make_panel(input, input.mesh->face_count(), loop_vertices, loop_ids));
  panels.front().shows_loops = true;
  for (const ViewMesh& view_mesh : filled) {
    // Without marks, the faces past the input's are new, in a fill that
    // starts with the input; another mesh has none.
    const bool extends_input = starts_with(*view_mesh.mesh, *input.mesh);
    panels.push_back(make_panel(
        view_mesh, extends_input ? input.mesh->face_count() : view_mesh.mesh->face_count(),
        loop_vertices, loop_ids));
    panels.back().shows_loops = extends_input;
  }

  std::vector<const std::vector<float>*> gaussians, means;
  for (const Panel& panel : panels) {
    gaussians.push_back(&panel.curvatures.gaussian);
    means.push_back(&panel.curvatures.mean);
  }
  const double gaussian_range = robust_range(gaussians), mean_range = robust_range(means);

  Blob blob;
  nlohmann::json meshes = nlohmann::json::array();
  // The input's positions and index are the first fill's that starts with it.
  std::optional<size_t> shared;
  for (size_t p = 1; p < panels.size() && !shared; ++p) {
    const Panel& panel = panels[p];
    if (panel.shows_loops &&
        std::equal(panels[0].index.begin(), panels[0].index.end(), panel.index.begin()))
      shared = p;
  }
  std::vector<nlohmann::json> positions(panels.size()), indices(panels.size());
  for (size_t p = shared ? 1 : 0; p < panels.size(); ++p) {
    positions[p] = blob.add(float_positions(*panels[p].mesh), Blob::Type::Float32);
    indices[p] = blob.add(panels[p].index, Blob::Type::Uint32);
  }
  if (shared) {
    positions[0] = positions[*shared];
    positions[0]["length"] = panels[0].mesh->positions.size() * 3;
    indices[0] = indices[*shared];
    indices[0]["length"] = panels[0].index.size();
  }
  std::vector<int> all_holes;
  for (size_t p = 0; p < panels.size(); ++p) {
    const Panel& panel = panels[p];
    meshes.push_back(
        {{"name", panel.name},
         {"role", p == 0 ? "input" : "filled"},
         {"vertex_count", panel.mesh->vertex_count()},
         {"face_count", panel.mesh->face_count()},
         {"positions", positions[p]},
         {"index", indices[p]},
         {"groups", panel.groups},
         {"gaussian",
          blob.add(quantized(panel.curvatures.gaussian, gaussian_range), Blob::Type::Uint8)},
         {"mean", blob.add(quantized(panel.curvatures.mean, mean_range), Blob::Type::Uint8)},
         {"shows_loops", panel.shows_loops}});
    all_holes.insert(all_holes.end(), panel.holes.begin(), panel.holes.end());
  }
  std::sort(all_holes.begin(), all_holes.end());
  all_holes.erase(std::unique(all_holes.begin(), all_holes.end()), all_holes.end());

  std::vector<uint32_t> loop_buffer;
  nlohmann::json loop_list = nlohmann::json::array();
  for (const BoundaryLoop& loop : loops) {
    loop_list.push_back({{"id", loop.id},
                         {"kind", json_name(loop.kind)},
                         {"kind_text", to_string(loop.kind)},
                         {"offset", loop_buffer.size()},
                         {"vertex_count", loop.vertices.size()},
                         {"length", loop.length},
                         {"centroid", loop.centroid}});
    for (int v : loop.vertices) loop_buffer.push_back(static_cast<uint32_t>(v));
  }
  const nlohmann::json loop_vertex_buffer = blob.add(loop_buffer, Blob::Type::Uint32);

  const nlohmann::json meta = {
      {"title", options.title},
      {"layout", options.layout == ViewLayout::Overlay ? "overlay" : "side_by_side"},
      {"meshes", meshes},
      {"holes", all_holes},
      {"loops", loop_list},
      {"loop_vertices", loop_vertex_buffer},
      {"curvature", {{"gaussian", {{"range", gaussian_range}}}, {"mean", {{"range", mean_range}}}}},
      {"report", report_rows(options.report)},
      {"report_source", options.report.is_object() && options.report.contains("output")
                            ? options.report["output"]
                            : nlohmann::json(nullptr)},
      {"blob_size", blob.bytes().size()}};

  // The template's markers, in the order they appear in it.
  const std::string_view html = assets::view_html();
  const std::pair<std::string_view, std::string> parts[] = {
      {"@TITLE@", html_escaped(options.title)},
      {"@STYLE@", std::string(assets::view_css())},
      {"@META@", script_safe_json(meta)},
      {"@BLOB@", base64(blob.bytes().data(), blob.bytes().size())},
      {"@THREE@", std::string(assets::three_js())},
      {"@SCRIPT@", std::string(assets::view_js())}};
  std::string page;
  size_t reserve = html.size();
  for (const auto& part : parts) reserve += part.second.size();
  page.reserve(reserve);
  size_t at = 0;
  for (const auto& [marker, text] : parts) {
    const size_t found = html.find(marker, at);
    if (found == std::string_view::npos)
      throw InternalError("the page template has no " + std::string(marker));
    page.append(html.substr(at, found - at));
    page += text;
    at = found + marker.size();
  }
  page.append(html.substr(at));
  return page;
}

}  // namespace foldfill
