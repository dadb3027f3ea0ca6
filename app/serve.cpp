// `foldfill serve`: the web app's server over cpp-httplib (serve.h).
#include "serve.h"

#include <fmt/core.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <filesystem>
#include <functional>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string_view>
#include <thread>

#include "foldfill/edit.h"
#include "foldfill/error.h"
#include "foldfill/file.h"
#include "foldfill/fill.h"
#include "foldfill/io.h"
#include "foldfill/obstacles.h"
#include "foldfill/view.h"

// After Eigen (through fill.h): <resolv.h>, which httplib.h includes, defines
// `_res`, a name Eigen uses.
#ifdef FOLDFILL_HAVE_HTTPLIB
#include <httplib.h>
#endif

namespace fs = std::filesystem;

namespace foldfill {
namespace assets {
// Generated at build time (src/embed_assets.cpp, in foldfill_view): the page of
// `serve`, its script and three.js (empty without node_modules/three).
std::string_view serve_html();
std::string_view serve_js();
std::string_view view_css();
std::string_view three_js();
}  // namespace assets
}  // namespace foldfill

namespace foldfill::cli {

bool is_loopback(const std::string& address) {
  std::string_view a = address;
  constexpr std::string_view kMapped = "::ffff:";
  if (a.substr(0, kMapped.size()) == kMapped) a.remove_prefix(kMapped.size());
  return a == "::1" || a.substr(0, 4) == "127.";
}

#ifdef FOLDFILL_HAVE_HTTPLIB

namespace {

nlohmann::json error_json(const std::string& message) { return {{"error", message}}; }

void send_json(httplib::Response& res, const nlohmann::json& body, int status = 200) {
  res.status = status;
  res.set_content(body.dump(), "application/json");
}

// The mesh's positions (float32), triangle indices (uint32) and, with marks,
// each face's hole (int32, -1 for the input's), base64 as the view page holds
// them.
nlohmann::json mesh_buffers(const Mesh& mesh) {
  std::vector<float> positions;
  positions.reserve(mesh.positions.size() * 3);
  for (const Vec3& p : mesh.positions)
    for (int k = 0; k < 3; ++k) positions.push_back(static_cast<float>(p[k]));
  std::vector<uint32_t> index;
  index.reserve(mesh.faces.size() * 3);
  for (const Tri& f : mesh.faces)
    for (int k = 0; k < 3; ++k) index.push_back(static_cast<uint32_t>(f[k]));
  nlohmann::json out = {{"vertex_count", mesh.vertex_count()},
                        {"face_count", mesh.face_count()},
                        {"positions", base64(positions.data(), positions.size() * sizeof(float))},
                        {"index", base64(index.data(), index.size() * sizeof(uint32_t))},
                        {"face_hole", nullptr}};
  if (mesh.face_hole.size() == mesh.faces.size()) {
    const std::vector<int32_t> holes(mesh.face_hole.begin(), mesh.face_hole.end());
    out["face_hole"] = base64(holes.data(), holes.size() * sizeof(int32_t));
  }
  return out;
}

// The positions (float32, base64) of output vertices [first, end): a patch
// as an edit leaves it.
nlohmann::json patch_buffer(const Mesh& mesh, IndexRange range) {
  std::vector<float> positions;
  positions.reserve(static_cast<size_t>(range.size()) * 3);
  for (int v = range.first; v < range.end; ++v)
    for (int k = 0; k < 3; ++k) positions.push_back(static_cast<float>(mesh.positions[v][k]));
  return {{"first", range.first},
          {"count", range.size()},
          {"positions", base64(positions.data(), positions.size() * sizeof(float))}};
}

// A JSON object body, or nothing (an empty body is {}).
std::optional<nlohmann::json> object_body(const std::string& text) {
  nlohmann::json body =
      text.empty() ? nlohmann::json::object() : nlohmann::json::parse(text, nullptr, false);
  if (body.is_discarded() || !body.is_object()) return std::nullopt;
  return body;
}

// The obstacles as triangles for the page: a mesh obstacle's own, a sphere,
// cylinder or plane tessellated near `box` (the mesh's, grown).
nlohmann::json obstacle_buffers(const std::vector<Obstacle>& obstacles, const Box3& box) {
  nlohmann::json out = nlohmann::json::array();
  double diagonal = 0;
  for (int c = 0; c < 3; ++c) diagonal += (box.high[c] - box.low[c]) * (box.high[c] - box.low[c]);
  diagonal = std::sqrt(diagonal);
  for (const Obstacle& o : obstacles) {
    const Mesh triangles = o.type == Obstacle::Type::Mesh
                               ? o.mesh->mesh()
                               : tessellate_obstacle(o, box, std::max(diagonal, 1e-9) / 40, 0);
    nlohmann::json item = mesh_buffers(triangles);
    item["type"] = o.type == Obstacle::Type::Mesh       ? "mesh"
                   : o.type == Obstacle::Type::Sphere   ? "sphere"
                   : o.type == Obstacle::Type::Cylinder ? "cylinder"
                                                        : "plane";
    out.push_back(std::move(item));
  }
  return out;
}

// The parameters' defaults, for the page's inputs.
nlohmann::json defaults_json() {
  const FillOptions options;
  return {{"lambda", options.energy.lambda},
          {"shrink", options.arap.shrink},
          {"density", options.triangulate.density},
          {"repulsion", options.energy.repulsion}};
}

// A number field of the fill's request: absent gives `fallback`; otherwise a
// finite number of at least `low` (above it when `above`).
double number_field(const nlohmann::json& body, const char* key, double fallback, double low,
                    bool above) {
  if (!body.contains(key) || body[key].is_null()) return fallback;
  const nlohmann::json& value = body[key];
  if (!value.is_number() || !std::isfinite(value.get<double>()))
    throw UsageError(fmt::format("{}: {} is not a finite number", key, value.dump()));
  const double number = value.get<double>();
  if (above ? number <= low : number < low)
    throw UsageError(
        fmt::format("{}: {} is not {} {}", key, number, above ? "above" : "at least", low));
  return number;
}

std::string string_field(const nlohmann::json& body, const char* key, const std::string& fallback,
                         std::initializer_list<const char*> choices) {
  if (!body.contains(key) || body[key].is_null()) return fallback;
  if (body[key].is_string()) {
    const std::string value = body[key].get<std::string>();
    for (const char* choice : choices)
      if (value == choice) return value;
  }
  std::string list;
  for (const char* choice : choices)
    list += (list.empty() ? "'" : ", '") + std::string(choice) + "'";
  throw UsageError(fmt::format("{}: {} is not one of {}", key, body[key].dump(), list));
}

// The fill's request as the CLI's options give it (app/fill.cpp), from the
// JSON of POST /api/fill. Throws UsageError for a field that is not one.
FillRequest fill_request(const nlohmann::json& body, const std::string& source) {
  if (!body.is_object()) throw UsageError("the request is not a JSON object");
  FillRequest request;
  request.source = source;
  FillOptions& options = request.options;
  options.energy.lambda = number_field(body, "lambda", options.energy.lambda, 0, false);
  options.arap.shrink = number_field(body, "shrink", options.arap.shrink, 0, true);
  options.triangulate.density = number_field(body, "density", options.triangulate.density, 0, true);
  options.energy.repulsion = number_field(body, "repulsion", options.energy.repulsion, 0, false);
  options.energy.bending =
      string_field(body, "bending", "quadratic", {"quadratic", "two-ring"}) == "two-ring"
          ? BendingModel::TwoRing
          : BendingModel::Quadratic;
  request.algorithm = string_field(body, "method", "foldfill", {"foldfill", "liepa"}) == "liepa"
                          ? FillAlgorithm::Liepa
                          : FillAlgorithm::Fabric;
  if (body.contains("holes") && !body["holes"].is_null() && body["holes"] != "default") {
    const nlohmann::json& holes = body["holes"];
    if (!holes.is_array())
      throw UsageError("holes: " + holes.dump() + " is not \"default\" or a list of ids");
    request.selection.mode = HoleSelection::Mode::Ids;
    for (const nlohmann::json& id : holes) {
      if (!id.is_number_integer() || id.get<int>() < 0)
        throw UsageError("holes: " + id.dump() + " is not a loop id");
      request.selection.ids.push_back(id.get<int>());
    }
    if (request.selection.ids.empty()) throw UsageError("holes: no loop chosen");
  }
  return request;
}

}  // namespace

struct Server::State {
  httplib::Server http;

  std::mutex mutex;  // guards everything below
  std::string name;  // the mesh's file name
  std::optional<Mesh> mesh;
  nlohmann::json mesh_reply;  // what GET /api/mesh answers

  // The latest fill.
  int job = 0;
  bool running = false, done = false;
  std::atomic<bool> cancel{false};
  int hole = -1, iteration = 0;
  double energy = 0;
  std::string error;  // the fill threw this
  FillRequest request;
  std::optional<FillOutput> result;
  nlohmann::json report;
  std::thread worker;
  // CGAL's Liepa fill of the same holes, when the fill asked for it.
  bool compare_liepa = false;
  std::optional<FillOutput> liepa;
  nlohmann::json liepa_report;

  // The obstacles of the next fills: those of the obstacles JSON and an
  // uploaded mesh.
  std::vector<Obstacle> obstacles;
  std::optional<Obstacle> mesh_obstacle;

  // The edit tool: the editor of the hole last grabbed (built on the first
  // grab of that hole, kept while its patch is edited), the drag under way
  // and the states before each edit.
  struct Undo {
    int hole = -1;                // index into the report's holes
    std::vector<Vec3> positions;  // the patch's new vertices
    HoleReport report;
  };
  std::unique_ptr<PatchEditor> editor;
  bool dragging = false;
  Undo before_drag;
  std::vector<Undo> undo;
  int edits = 0;
  static constexpr size_t kMaxUndo = 64;

  void reset_edits() {
    editor.reset();
    dragging = false;
    undo.clear();
    edits = 0;
  }

  std::vector<Obstacle> all_obstacles() const {
    std::vector<Obstacle> all = obstacles;
    if (mesh_obstacle) all.push_back(*mesh_obstacle);
    return all;
  }

  // The box obstacles are shown in: the mesh's, grown by a quarter of its diagonal.
  Box3 view_box() const {
    if (!mesh || mesh->positions.empty()) return {{-1, -1, -1}, {1, 1, 1}};
    Box3 box{mesh->positions[0], mesh->positions[0]};
    for (const Vec3& p : mesh->positions)
      for (int c = 0; c < 3; ++c) {
        box.low[c] = std::min(box.low[c], p[c]);
        box.high[c] = std::max(box.high[c], p[c]);
      }
    double diagonal = 0;
    for (int c = 0; c < 3; ++c) diagonal += (box.high[c] - box.low[c]) * (box.high[c] - box.low[c]);
    const double grow = 0.25 * std::sqrt(diagonal);
    for (int c = 0; c < 3; ++c) {
      box.low[c] -= grow;
      box.high[c] += grow;
    }
    return box;
  }

  nlohmann::json obstacles_reply() const {
    return {{"obstacles", obstacle_buffers(all_obstacles(), view_box())},
            {"mesh_obstacle", mesh_obstacle.has_value()}};
  }

  void open(const std::string& bytes, const std::string& file_name) {
    std::vector<std::string> warnings;
    Mesh parsed = parse_mesh(bytes, format_from_path(file_name), file_name, &warnings);
    FillRequest defaults;
    defaults.source = file_name;
    const ChosenHoles chosen = choose_holes(parsed, defaults);
    nlohmann::json loops = nlohmann::json::array();
    for (const BoundaryLoop& loop : chosen.loops) loops.push_back(loop_json(loop, chosen.choice));
    for (const std::string& warning : chosen.choice.warnings) warnings.push_back(warning);
    nlohmann::json reply = mesh_buffers(parsed);
    reply["name"] = file_name;
    reply["loops"] = loops;
    reply["default_holes"] = chosen.choice.fill;
    reply["warnings"] = warnings;
    reply["defaults"] = defaults_json();
    std::lock_guard<std::mutex> lock(mutex);
    if (running) throw UsageError("a fill is running: cancel it first");
    name = file_name;
    mesh = std::move(parsed);
    mesh_reply = std::move(reply);
    result.reset();
    report = nullptr;
    liepa.reset();
    liepa_report = nullptr;
    reset_edits();
    done = false;
    error.clear();
  }

  // Starts the fill; returns its job id. Throws UsageError as fill_request.
  int start(const nlohmann::json& body) {
    std::lock_guard<std::mutex> lock(mutex);
    if (!mesh) throw UsageError("no mesh: upload one first");
    if (running) throw UsageError("a fill is running: cancel it first");
    request = fill_request(body, name);
    compare_liepa = false;
    if (body.contains("compare_liepa") && !body["compare_liepa"].is_null()) {
      if (!body["compare_liepa"].is_boolean())
        throw UsageError("compare_liepa: " + body["compare_liepa"].dump() +
                         " is not true or false");
      compare_liepa = body["compare_liepa"].get<bool>();
    }
    request.options.obstacles = all_obstacles();
    request.options.progress = [this](int id, const SolverProgress& progress) {
      std::lock_guard<std::mutex> progress_lock(mutex);
      hole = id;
      iteration = progress.iteration;
      energy = progress.energy;
      return !cancel.load();
    };
    if (worker.joinable()) worker.join();
    ++job;
    running = true;
    done = false;
    cancel = false;
    hole = -1;
    iteration = 0;
    energy = 0;
    error.clear();
    result.reset();
    report = nullptr;
    liepa.reset();
    liepa_report = nullptr;
    reset_edits();
    worker = std::thread([this] { run(); });
    return job;
  }

  void run() {
    // The mesh is not replaced while running is set.
    const Mesh& input = *mesh;
    std::optional<FillOutput> output;
    nlohmann::json json;
    std::string failure;
    std::optional<FillOutput> smooth;
    nlohmann::json smooth_json;
    try {
      output = fill(input, request);
      json = report_json(input, *output, request);
      if (compare_liepa && !output->report.cancelled && !cancel.load()) {
        FillRequest same = request;
        same.algorithm = FillAlgorithm::Liepa;
        same.options.progress = nullptr;
        smooth = fill(input, same);
        smooth_json = report_json(input, *smooth, same);
      }
    } catch (const std::exception& e) {
      failure = e.what();
    }
    std::lock_guard<std::mutex> lock(mutex);
    result = std::move(output);
    report = std::move(json);
    liepa = std::move(smooth);
    liepa_report = std::move(smooth_json);
    error = failure;
    running = false;
    done = true;
  }

  nlohmann::json progress() {
    std::lock_guard<std::mutex> lock(mutex);
    return {{"job", job},
            {"running", running},
            {"done", done},
            {"hole", hole},
            {"iteration", iteration},
            {"energy", energy},
            {"cancelled", cancel.load()},
            {"error", error.empty() ? nlohmann::json(nullptr) : nlohmann::json(error)}};
  }

  // The edit tool (POST /api/edit/...); each throws Error(Usage) for a
  // request it cannot take, with the reason. Called with the mutex held.
  void check_editable() const {
    if (running) throw UsageError("a fill is running: wait for it or cancel it");
    if (!result) throw UsageError("no fill yet: fill first, then edit its patches");
  }

  nlohmann::json begin_edit(const nlohmann::json& body) {
    check_editable();
    // A drag whose end never came (the page lost the pointer) ends here.
    if (dragging) end_edit();
    if (!body.contains("vertex") || !body["vertex"].is_number_integer())
      throw UsageError("vertex: not given as a vertex index of the result");
    const int vertex = body["vertex"].get<int>();
    const std::vector<HoleReport>& holes = result->report.holes;
    int index = -1;
    for (int h = 0; h < static_cast<int>(holes.size()); ++h)
      if (holes[h].filled && vertex >= holes[h].new_vertices.first &&
          vertex < holes[h].new_vertices.end)
        index = h;
    if (index < 0)
      throw UsageError("vertex " + std::to_string(vertex) +
                       " is not a new vertex of a patch: only those move");
    if (body.contains("hole") && body["hole"] != holes[index].loop_id)
      throw UsageError("vertex " + std::to_string(vertex) + " is of loop " +
                       std::to_string(holes[index].loop_id) + ", not loop " + body["hole"].dump());
    if (!editor || editor->hole() != index) {
      editor.reset();
      const int loop = holes[index].loop_id;
      editor = std::make_unique<PatchEditor>(*mesh, *result, index, result->loops.at(loop),
                                             request.options, name);
    }
    editor->grab(vertex);
    dragging = true;
    before_drag = {index, {}, holes[index]};
    before_drag.positions.assign(result->mesh.positions.begin() + holes[index].new_vertices.first,
                                 result->mesh.positions.begin() + holes[index].new_vertices.end);
    nlohmann::json reply = patch_buffer(result->mesh, holes[index].new_vertices);
    reply["hole"] = holes[index].loop_id;
    reply["vertex"] = vertex;
    return reply;
  }

  nlohmann::json move_edit(const nlohmann::json& body) {
    check_editable();
    if (!dragging || !editor)
      throw UsageError("no edit begun: POST /api/edit/begin with a vertex first");
    Vec3 target;
    for (int c = 0; c < 3; ++c) {
      const char* key = c == 0 ? "x" : c == 1 ? "y" : "z";
      if (!body.contains(key) || !body[key].is_number())
        throw UsageError(std::string(key) + ": not given as a number");
      target[c] = body[key].get<double>();
    }
    const DragResult moved = editor->drag(target);
    editor->write(result->mesh);
    nlohmann::json reply = patch_buffer(result->mesh, editor->vertices());
    reply["iterations"] = moved.iterations;
    reply["stop_reason"] = to_string(moved.stop_reason);
    reply["seconds"] = moved.seconds;
    return reply;
  }

  // The hole's figures measured again and the report rebuilt.
  void remeasure(int index) {
    editor->measure(result->mesh, result->report.holes[index]);
    report = report_json(*mesh, *result, request);
  }

  nlohmann::json end_edit() {
    check_editable();
    if (!dragging || !editor) throw UsageError("no edit begun");
    const DragResult settled = editor->settle();
    editor->write(result->mesh);
    editor->release();
    dragging = false;
    remeasure(editor->hole());
    undo.push_back(std::move(before_drag));
    if (undo.size() > kMaxUndo) undo.erase(undo.begin());
    ++edits;
    nlohmann::json reply = patch_buffer(result->mesh, editor->vertices());
    reply["report"] = report;
    reply["undo"] = undo.size();
    reply["edits"] = edits;
    reply["settle_iterations"] = settled.iterations;
    return reply;
  }

  nlohmann::json undo_edit() {
    check_editable();
    if (dragging) throw UsageError("an edit is under way: end it first");
    if (undo.empty()) throw UsageError("nothing to undo");
    Undo last = std::move(undo.back());
    undo.pop_back();
    HoleReport& restored = result->report.holes[last.hole];
    std::copy(last.positions.begin(), last.positions.end(),
              result->mesh.positions.begin() + restored.new_vertices.first);
    restored = last.report;
    if (editor && editor->hole() == last.hole) editor->set_positions(last.positions);
    report = report_json(*mesh, *result, request);
    ++edits;
    nlohmann::json reply = patch_buffer(result->mesh, restored.new_vertices);
    reply["hole"] = restored.loop_id;
    reply["report"] = report;
    reply["undo"] = undo.size();
    reply["edits"] = edits;
    return reply;
  }

  void routes();
};

void Server::State::routes() {
  // Nothing but loopback peers, whatever the address bound.
  http.set_pre_routing_handler([](const httplib::Request& req, httplib::Response& res) {
    if (is_loopback(req.remote_addr)) return httplib::Server::HandlerResponse::Unhandled;
    send_json(res, error_json("refused: not from the loopback interface"), 403);
    return httplib::Server::HandlerResponse::Handled;
  });
  http.Get("/", [](const httplib::Request&, httplib::Response& res) {
    res.set_content(std::string(assets::serve_html()), "text/html; charset=utf-8");
  });
  http.Get("/serve.js", [](const httplib::Request&, httplib::Response& res) {
    res.set_content(std::string(assets::serve_js()), "text/javascript");
  });
  http.Get("/view.css", [](const httplib::Request&, httplib::Response& res) {
    res.set_content(std::string(assets::view_css()), "text/css");
  });
  http.Get("/three.js", [](const httplib::Request&, httplib::Response& res) {
    res.set_content(std::string(assets::three_js()), "text/javascript");
  });
  // The page has no icon; without this the browser logs a 404 for it.
  http.Get("/favicon.ico",
           [](const httplib::Request&, httplib::Response& res) { res.status = 204; });
  http.Get("/api/mesh", [this](const httplib::Request&, httplib::Response& res) {
    std::lock_guard<std::mutex> lock(mutex);
    send_json(res,
              mesh ? mesh_reply : nlohmann::json{{"mesh", nullptr}, {"defaults", defaults_json()}});
  });
  http.Post("/api/mesh", [this](const httplib::Request& req, httplib::Response& res) {
    const std::string file_name = fs::path(req.get_param_value("name")).filename().string();
    if (file_name.empty()) return send_json(res, error_json("no ?name=FILE given"), 400);
    try {
      open(req.body, file_name);
    } catch (const Error& e) {
      return send_json(res, error_json(e.what()), 400);
    }
    std::lock_guard<std::mutex> lock(mutex);
    send_json(res, mesh_reply);
  });
  http.Post("/api/fill", [this](const httplib::Request& req, httplib::Response& res) {
    const nlohmann::json body = req.body.empty() ? nlohmann::json::object()
                                                 : nlohmann::json::parse(req.body, nullptr, false);
    if (body.is_discarded()) return send_json(res, error_json("the request is not JSON"), 400);
    try {
      send_json(res, {{"job", start(body)}});
    } catch (const Error& e) {
      send_json(res, error_json(e.what()), 400);
    }
  });
  http.Get("/api/progress",
           [this](const httplib::Request&, httplib::Response& res) { send_json(res, progress()); });
  http.Post("/api/cancel", [this](const httplib::Request&, httplib::Response& res) {
    std::lock_guard<std::mutex> lock(mutex);
    if (running) cancel = true;
    send_json(res, {{"job", job}, {"cancelled", running}});
  });
  http.Get("/api/result", [this](const httplib::Request&, httplib::Response& res) {
    std::lock_guard<std::mutex> lock(mutex);
    if (!error.empty()) return send_json(res, error_json(error), 400);
    if (!result)
      return send_json(res, error_json(running ? "the fill is running" : "no fill yet"), 404);
    nlohmann::json reply = mesh_buffers(result->mesh);
    reply["job"] = job;
    reply["input_face_count"] = mesh->face_count();
    reply["report"] = report;
    reply["edits"] = edits;
    reply["undo"] = undo.size();
    reply["liepa"] = liepa.has_value();
    send_json(res, reply);
  });
  // The edit tool and the obstacles: JSON in, JSON out, Error(Usage) as 400.
  const auto post = [this](const char* path,
                           std::function<nlohmann::json(State&, const nlohmann::json&)> handle) {
    http.Post(path, [this, handle](const httplib::Request& req, httplib::Response& res) {
      const std::optional<nlohmann::json> body = object_body(req.body);
      if (!body) return send_json(res, error_json("the request is not a JSON object"), 400);
      std::lock_guard<std::mutex> lock(mutex);
      try {
        send_json(res, handle(*this, *body));
      } catch (const Error& e) {
        send_json(res, error_json(e.what()), 400);
      }
    });
  };
  post("/api/edit/begin", [](State& s, const nlohmann::json& body) { return s.begin_edit(body); });
  post("/api/edit/move", [](State& s, const nlohmann::json& body) { return s.move_edit(body); });
  post("/api/edit/end", [](State& s, const nlohmann::json&) { return s.end_edit(); });
  post("/api/undo", [](State& s, const nlohmann::json&) { return s.undo_edit(); });
  http.Get("/api/liepa", [this](const httplib::Request&, httplib::Response& res) {
    std::lock_guard<std::mutex> lock(mutex);
    if (!liepa)
      return send_json(res, error_json("no Liepa fill: fill with compare_liepa set"), 404);
    nlohmann::json reply = mesh_buffers(liepa->mesh);
    reply["job"] = job;
    reply["input_face_count"] = mesh->face_count();
    reply["report"] = liepa_report;
    send_json(res, reply);
  });
  http.Get("/api/obstacles", [this](const httplib::Request&, httplib::Response& res) {
    std::lock_guard<std::mutex> lock(mutex);
    send_json(res, obstacles_reply());
  });
  // Body: the obstacles file as the CLI's --obstacles takes it (empty: none).
  http.Post("/api/obstacles", [this](const httplib::Request& req, httplib::Response& res) {
    std::vector<Obstacle> parsed;
    try {
      const nlohmann::json text = nlohmann::json::parse(req.body, nullptr, false);
      if (!text.is_discarded() && text.is_object() && text.contains("obstacles") &&
          text["obstacles"].is_array())
        for (const nlohmann::json& entry : text["obstacles"])
          if (entry.is_object() && entry.value("type", "") == "mesh")
            throw UsageError(
                "obstacles: a mesh obstacle is given by uploading its file "
                "(POST /api/obstacle-mesh?name=F)");
      if (!req.body.empty()) parsed = parse_obstacles(req.body, "obstacles");
    } catch (const Error& e) {
      return send_json(res, error_json(e.what()), 400);
    }
    std::lock_guard<std::mutex> lock(mutex);
    if (running) return send_json(res, error_json("a fill is running: cancel it first"), 400);
    obstacles = std::move(parsed);
    send_json(res, obstacles_reply());
  });
  // Body: a mesh file, the obstacle (empty: none).
  http.Post("/api/obstacle-mesh", [this](const httplib::Request& req, httplib::Response& res) {
    std::optional<Obstacle> parsed;
    if (!req.body.empty()) {
      const std::string file_name = fs::path(req.get_param_value("name")).filename().string();
      if (file_name.empty()) return send_json(res, error_json("no ?name=FILE given"), 400);
      try {
        parsed = foldfill::mesh_obstacle(
            parse_mesh(req.body, format_from_path(file_name), file_name), file_name);
      } catch (const Error& e) {
        return send_json(res, error_json(e.what()), 400);
      }
    }
    std::lock_guard<std::mutex> lock(mutex);
    if (running) return send_json(res, error_json("a fill is running: cancel it first"), 400);
    mesh_obstacle = std::move(parsed);
    send_json(res, obstacles_reply());
  });
  http.Get("/api/download", [this](const httplib::Request& req, httplib::Response& res) {
    const std::string format = req.has_param("format") ? req.get_param_value("format") : "obj";
    MeshFormat mesh_format;
    try {
      mesh_format = format_from_path("x." + format);
    } catch (const Error&) {
      return send_json(res, error_json("format: '" + format + "' is not obj, ply, off or stl"),
                       400);
    }
    std::lock_guard<std::mutex> lock(mutex);
    if (!result) return send_json(res, error_json("no fill yet"), 404);
    const std::string file = fs::path(name).stem().string() + "_filled." + format;
    res.set_header("Content-Disposition", "attachment; filename=\"" + file + "\"");
    res.set_content(serialize_mesh(result->mesh, mesh_format), "application/octet-stream");
  });
}

Server::Server(size_t max_upload_bytes) : state_(std::make_unique<State>()) {
  state_->http.set_payload_max_length(max_upload_bytes);
  state_->routes();
}

Server::~Server() {
  state_->cancel = true;
  stop();
  if (state_->worker.joinable()) state_->worker.join();
}

void Server::open(const std::string& bytes, const std::string& name) { state_->open(bytes, name); }

int Server::bind(int port) {
  if (port == 0) return state_->http.bind_to_any_port("127.0.0.1");
  return state_->http.bind_to_port("127.0.0.1", port) ? port : -1;
}

bool Server::listen() { return state_->http.listen_after_bind(); }

void Server::stop() { state_->http.stop(); }

bool serve_available() { return view_available(); }

#else  // without cpp-httplib

struct Server::State {};
Server::Server(size_t) {}
Server::~Server() = default;
void Server::open(const std::string&, const std::string&) {}
int Server::bind(int) { return -1; }
bool Server::listen() { return false; }
void Server::stop() {}
bool serve_available() { return false; }

#endif

CLI::App* add_serve_command(CLI::App& app, ServeArgs& args) {
  CLI::App* command = app.add_subcommand(
      "serve", "a local web app (127.0.0.1 only) to open a mesh, pick loops, fill and download");
  command->add_option("mesh", args.mesh, "a mesh to open at the start (or upload one in the page)");
  command->add_option("--port", args.port, "the port on 127.0.0.1 (0: any free port)")
      ->check(CLI::Range(0, 65535));
  return command;
}

int run_serve(const ServeArgs& args) {
  if (!serve_available()) {
    throw UsageError(
        "serve is not available: this foldfill was built without cpp-httplib "
        "(libcpp-httplib-dev) or three.js (bash scripts/setup.sh, then build again)");
  }
  Server server;
  // Named by the path as given, so that its errors read as the CLI's.
  if (!args.mesh.empty()) server.open(read_file(args.mesh), args.mesh);
  const int port = server.bind(args.port);
  if (port < 0) throw UsageError(fmt::format("cannot listen on 127.0.0.1:{}", args.port));
  fmt::print("foldfill serve: http://127.0.0.1:{}/ (Ctrl-C stops it)\n", port);
  std::fflush(stdout);
  if (!server.listen()) throw InternalError("the server stopped on an error");
  return 0;
}

}  // namespace foldfill::cli
