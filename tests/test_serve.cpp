// The server of `foldfill serve` (app/serve.h): its endpoints through an
// httplib::Client against a server on a free port, in process.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <thread>

#include "foldfill/error.h"
#include "foldfill/examples.h"
#include "foldfill/fill.h"
#include "foldfill/io.h"
#include "serve.h"

// After Eigen (through fill.h): <resolv.h>, which httplib.h includes, defines
// `_res`, a name Eigen uses.
#include <httplib.h>

namespace {

using foldfill::cli::Server;
using nlohmann::json;

// The demo's sheet: three folds and a disk hole across them.
std::string sheet_obj() {
  const foldfill::DevelopableMesh sheet = foldfill::make_folded_sheet();
  const foldfill::CutMesh cut = foldfill::cut_disk_hole(sheet, {2.6, 1.5}, 0.7);
  return foldfill::serialize_mesh(cut.cut.mesh, foldfill::MeshFormat::Obj);
}

// A server on a free port of 127.0.0.1, serving in a thread while it lives.
class Served {
 public:
  explicit Served(size_t max_upload = foldfill::cli::kMaxUploadBytes) : server_(max_upload) {
    port_ = server_.bind(0);
    thread_ = std::thread([this] { server_.listen(); });
  }
  ~Served() {
    server_.stop();
    thread_.join();
  }
  int port() const { return port_; }
  httplib::Client client() const {
    httplib::Client c("127.0.0.1", port_);
    c.set_read_timeout(120, 0);
    return c;
  }

 private:
  Server server_;
  int port_ = -1;
  std::thread thread_;
};

json body_of(const httplib::Result& result) { return json::parse(result->body); }

// Waits for the fill to be done; returns its last progress.
json wait_done(httplib::Client& client, double seconds = 300) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < until) {
    const auto result = client.Get("/api/progress");
    if (!result) break;
    json progress = body_of(result);
    if (progress["done"] == true) return progress;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ADD_FAILURE() << "the fill did not end in time";
  return nullptr;
}

// `value` without its times ("seconds", "seconds_total"), which differ from run to run.
json without_times(json value) {
  if (value.is_object()) {
    value.erase("seconds");
    value.erase("seconds_total");
    for (auto& [key, item] : value.items()) item = without_times(item);
  } else if (value.is_array()) {
    for (auto& item : value) item = without_times(item);
  }
  return value;
}

TEST(Serve, LoopbackPredicate) {
  using foldfill::cli::is_loopback;
  EXPECT_TRUE(is_loopback("127.0.0.1"));
  EXPECT_TRUE(is_loopback("127.1.2.3"));
  EXPECT_TRUE(is_loopback("::1"));
  EXPECT_TRUE(is_loopback("::ffff:127.0.0.1"));
  EXPECT_FALSE(is_loopback("192.168.1.20"));
  EXPECT_FALSE(is_loopback("10.0.0.1"));
  EXPECT_FALSE(is_loopback("::ffff:10.0.0.1"));
  EXPECT_FALSE(is_loopback("fe80::1"));
  EXPECT_FALSE(is_loopback("1127.0.0.1"));
  EXPECT_FALSE(is_loopback(""));
}

TEST(Serve, PageAndEmptySession) {
  if (!foldfill::cli::serve_available()) GTEST_SKIP() << "serve is not available in this build";
  Served served;
  ASSERT_GT(served.port(), 0);
  httplib::Client client = served.client();
  const auto page = client.Get("/");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
  EXPECT_NE(page->body.find("/serve.js"), std::string::npos);
  for (const char* asset : {"/serve.js", "/three.js", "/view.css"}) {
    const auto result = client.Get(asset);
    ASSERT_TRUE(result);
    EXPECT_EQ(result->status, 200) << asset;
    EXPECT_FALSE(result->body.empty()) << asset;
  }
  const auto mesh = client.Get("/api/mesh");
  ASSERT_TRUE(mesh);
  EXPECT_TRUE(body_of(mesh)["mesh"].is_null());
  EXPECT_EQ(client.Get("/api/result")->status, 404);
  EXPECT_EQ(client.Get("/api/download?format=obj")->status, 404);
  // A fill before any mesh.
  EXPECT_EQ(client.Post("/api/fill", "{}", "application/json")->status, 400);
}

TEST(Serve, BadRequestsAnswer400WithTheCliMessage) {
  if (!foldfill::cli::serve_available()) GTEST_SKIP() << "serve is not available in this build";
  Served served;
  httplib::Client client = served.client();
  // A face naming a vertex that is not there: the message of parse_mesh.
  const std::string bad = "v 0 0 0\nv 1 0 0\nf 1 2 7\n";
  std::string expected;
  try {
    foldfill::parse_mesh(bad, foldfill::MeshFormat::Obj, "bad.obj");
  } catch (const foldfill::Error& e) {
    expected = e.what();
  }
  ASSERT_FALSE(expected.empty());
  auto result = client.Post("/api/mesh?name=bad.obj", bad, "application/octet-stream");
  ASSERT_TRUE(result);
  EXPECT_EQ(result->status, 400);
  EXPECT_EQ(body_of(result)["error"], expected);
  EXPECT_EQ(expected.rfind("bad.obj: ", 0), 0u) << expected;

  result = client.Post("/api/mesh?name=mesh.xyz", bad, "application/octet-stream");
  EXPECT_EQ(result->status, 400);
  result = client.Post("/api/mesh", bad, "application/octet-stream");
  EXPECT_EQ(result->status, 400);

  ASSERT_EQ(client.Post("/api/mesh?name=sheet.obj", sheet_obj(), "text/plain")->status, 200);
  for (const char* request :
       {"not json", "[1]", R"({"lambda": "a"})", R"({"shrink": 0})", R"({"method": "other"})",
        R"({"holes": "some"})", R"({"holes": [-1]})", R"({"holes": [99]})"}) {
    result = client.Post("/api/fill", request, "application/json");
    ASSERT_TRUE(result);
    if (std::string(request) == R"({"holes": [99]})") {
      // An id that names no loop is refused when the fill starts, as the CLI does.
      if (result->status == 200) {
        const json progress = wait_done(client);
        EXPECT_FALSE(progress["error"].is_null()) << progress.dump();
        EXPECT_EQ(client.Get("/api/result")->status, 400);
      } else {
        EXPECT_EQ(result->status, 400);
      }
      continue;
    }
    EXPECT_EQ(result->status, 400) << request;
    EXPECT_TRUE(body_of(result)["error"].is_string()) << request;
  }
  EXPECT_EQ(client.Get("/api/download?format=xyz")->status, 400);
}

TEST(Serve, OversizedUploadAnswers413) {
  if (!foldfill::cli::serve_available()) GTEST_SKIP() << "serve is not available in this build";
  Served served(1000);
  httplib::Client client = served.client();
  const auto result =
      client.Post("/api/mesh?name=big.obj", std::string(5000, '#'), "application/octet-stream");
  ASSERT_TRUE(result);
  EXPECT_EQ(result->status, 413);
  EXPECT_EQ(client.Post("/api/mesh?name=small.obj", std::string(500, '#'), "text/plain")->status,
            400);
}

TEST(Serve, UploadFillResultAsTheLibrary) {
  if (!foldfill::cli::serve_available()) GTEST_SKIP() << "serve is not available in this build";
  Served served;
  httplib::Client client = served.client();
  const std::string bytes = sheet_obj();
  const auto uploaded = client.Post("/api/mesh?name=sheet.obj", bytes, "text/plain");
  ASSERT_TRUE(uploaded);
  ASSERT_EQ(uploaded->status, 200) << uploaded->body;
  const json mesh = body_of(uploaded);
  const foldfill::Mesh input = foldfill::parse_mesh(bytes, foldfill::MeshFormat::Obj, "sheet.obj");
  EXPECT_EQ(mesh["vertex_count"], input.vertex_count());
  EXPECT_EQ(mesh["face_count"], input.face_count());
  ASSERT_EQ(mesh["loops"].size(), 2u);  // the sheet's outer edge and the hole
  ASSERT_EQ(mesh["default_holes"].size(), 1u);
  const int hole = mesh["default_holes"][0];

  const json request = {
      {"holes", {hole}}, {"lambda", 0.5}, {"shrink", 0.95}, {"method", "foldfill"}};
  const auto started = client.Post("/api/fill", request.dump(), "application/json");
  ASSERT_TRUE(started);
  ASSERT_EQ(started->status, 200) << started->body;
  const json progress = wait_done(client);
  ASSERT_TRUE(progress["error"].is_null()) << progress.dump();
  const auto result = client.Get("/api/result");
  ASSERT_TRUE(result);
  ASSERT_EQ(result->status, 200) << result->body;
  const json reply = body_of(result);

  foldfill::FillRequest same;
  same.source = "sheet.obj";
  same.selection.mode = foldfill::HoleSelection::Mode::Ids;
  same.selection.ids = {hole};
  same.options.energy.lambda = 0.5;
  same.options.arap.shrink = 0.95;
  const foldfill::FillOutput output = foldfill::fill(input, same);
  const json expected = foldfill::report_json(input, output, same);
  EXPECT_EQ(without_times(reply["report"]), without_times(expected));
  EXPECT_EQ(reply["face_count"], output.mesh.face_count());
  EXPECT_EQ(reply["vertex_count"], output.mesh.vertex_count());
  EXPECT_EQ(reply["report"]["holes"][0]["filled"], true);

  const auto download = client.Get("/api/download?format=off");
  ASSERT_TRUE(download);
  EXPECT_EQ(download->status, 200);
  const foldfill::Mesh written =
      foldfill::parse_mesh(download->body, foldfill::MeshFormat::Off, "download.off");
  EXPECT_EQ(written.face_count(), output.mesh.face_count());
}

TEST(Serve, CancelsALongFill) {
  if (!foldfill::cli::serve_available()) GTEST_SKIP() << "serve is not available in this build";
  Served served;
  httplib::Client client = served.client();
  ASSERT_EQ(client.Post("/api/mesh?name=sheet.obj", sheet_obj(), "text/plain")->status, 200);
  // Many times the boundary's density: a fill of many seconds.
  const auto started = client.Post("/api/fill", R"({"density": 12})", "application/json");
  ASSERT_EQ(started->status, 200) << started->body;
  // Once the solver has started on the hole.
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  json progress;
  while (std::chrono::steady_clock::now() < until) {
    progress = body_of(client.Get("/api/progress"));
    if (progress["done"] == true || progress["iteration"].get<int>() > 0) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_FALSE(progress["done"].get<bool>()) << "the fill ended before it could be cancelled";
  // A second fill while one runs is refused.
  EXPECT_EQ(client.Post("/api/fill", "{}", "application/json")->status, 400);
  const auto cancelled = client.Post("/api/cancel", "", "application/json");
  ASSERT_TRUE(cancelled);
  EXPECT_EQ(body_of(cancelled)["cancelled"], true);
  const auto start = std::chrono::steady_clock::now();
  progress = wait_done(client, 60);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(30));
  const json reply = body_of(client.Get("/api/result"));
  EXPECT_EQ(reply["report"]["cancelled"], true) << reply["report"].dump();
  EXPECT_EQ(reply["report"]["holes"][0]["status"], "cancelled");
}

// The float32 positions of a reply's base64 buffer.
std::vector<float> floats(const json& base64_text) {
  const std::string text = base64_text.get<std::string>();
  std::string bytes;
  int bits = 0;
  unsigned value = 0;  // the bits not yet taken, at most 14
  for (char c : text) {
    int d = -1;
    if (c >= 'A' && c <= 'Z') d = c - 'A';
    if (c >= 'a' && c <= 'z') d = c - 'a' + 26;
    if (c >= '0' && c <= '9') d = c - '0' + 52;
    if (c == '+') d = 62;
    if (c == '/') d = 63;
    if (d < 0) continue;
    value = ((value << 6) | static_cast<unsigned>(d)) & 0xffffu;
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      bytes.push_back(static_cast<char>((value >> bits) & 0xff));
    }
  }
  std::vector<float> out(bytes.size() / sizeof(float));
  std::memcpy(out.data(), bytes.data(), out.size() * sizeof(float));
  return out;
}

httplib::Result post_json(httplib::Client& client, const char* path, const json& body) {
  return client.Post(path, body.dump(), "application/json");
}

// Uploads the sheet and fills its hole; returns the result.
json filled_sheet(httplib::Client& client, const json& request = json::object()) {
  EXPECT_EQ(client.Post("/api/mesh?name=sheet.obj", sheet_obj(), "text/plain")->status, 200);
  const auto started = post_json(client, "/api/fill", request);
  EXPECT_EQ(started->status, 200) << started->body;
  const json progress = wait_done(client);
  EXPECT_TRUE(progress["error"].is_null()) << progress.dump();
  const auto result = client.Get("/api/result");
  EXPECT_EQ(result->status, 200);
  return body_of(result);
}

TEST(Serve, EditRefusesWhatItCannotDo) {
  if (!foldfill::cli::serve_available()) GTEST_SKIP() << "serve is not available in this build";
  Served served;
  httplib::Client client = served.client();
  auto answer = post_json(client, "/api/edit/begin", {{"vertex", 0}});
  ASSERT_TRUE(answer);
  EXPECT_EQ(answer->status, 400);
  EXPECT_EQ(body_of(answer)["error"], "no fill yet: fill first, then edit its patches");
  EXPECT_EQ(post_json(client, "/api/undo", json::object())->status, 400);

  const json result = filled_sheet(client);
  const int input_vertices = result["vertex_count"].get<int>() -
                             result["report"]["holes"][0]["patch_vertex_count"].get<int>();
  // An input vertex, one past the end, not a number: not a patch's vertex.
  for (const json& vertex :
       {json(0), json(input_vertices - 1), result["vertex_count"], json("a")}) {
    answer = post_json(client, "/api/edit/begin", {{"vertex", vertex}});
    EXPECT_EQ(answer->status, 400) << vertex;
    EXPECT_TRUE(body_of(answer)["error"].is_string());
  }
  answer = post_json(client, "/api/edit/move", {{"x", 0}, {"y", 0}, {"z", 0}});
  EXPECT_EQ(answer->status, 400);
  EXPECT_EQ(body_of(answer)["error"], "no edit begun: POST /api/edit/begin with a vertex first");
  EXPECT_EQ(post_json(client, "/api/edit/end", json::object())->status, 400);
  EXPECT_EQ(client.Post("/api/edit/begin", "not json", "application/json")->status, 400);
  answer = post_json(client, "/api/undo", json::object());
  EXPECT_EQ(answer->status, 400);
  EXPECT_EQ(body_of(answer)["error"], "nothing to undo");
}

TEST(Serve, EditDragsThePatchAloneAndUndoRestoresIt) {
  if (!foldfill::cli::serve_available()) GTEST_SKIP() << "serve is not available in this build";
  Served served;
  httplib::Client client = served.client();
  const json before = filled_sheet(client);
  const json hole = before["report"]["holes"][0];
  ASSERT_EQ(hole["filled"], true);
  ASSERT_EQ(hole["self_intersections"], 0);
  const int first = hole["new_vertices"][0], end = hole["new_vertices"][1];
  const std::vector<float> start = floats(before["positions"]);
  // The handle: the new vertex nearest the patch's centroid.
  double centre[3] = {0, 0, 0};
  for (int v = first; v < end; ++v)
    for (int c = 0; c < 3; ++c) centre[c] += start[3 * v + c] / (end - first);
  int handle = first;
  double nearest = 1e300;
  for (int v = first; v < end; ++v) {
    double d = 0;
    for (int c = 0; c < 3; ++c)
      d += (start[3 * v + c] - centre[c]) * (start[3 * v + c] - centre[c]);
    if (d < nearest) {
      nearest = d;
      handle = v;
    }
  }
  auto answer =
      post_json(client, "/api/edit/begin", {{"vertex", handle}, {"hole", hole["loop_id"]}});
  ASSERT_EQ(answer->status, 200) << answer->body;
  EXPECT_EQ(body_of(answer)["first"], first);
  EXPECT_EQ(body_of(answer)["count"], end - first);
  // Pulled up by 0.3 (a third of the hole's radius) in steps, as a pointer does.
  const double lift = 0.3;
  const double target[3] = {start[3 * handle], start[3 * handle + 1], start[3 * handle + 2] + lift};
  json moved;
  for (int step = 1; step <= 8; ++step) {
    answer =
        post_json(client, "/api/edit/move",
                  {{"x", target[0]}, {"y", target[1]}, {"z", target[2] - lift + lift * step / 8}});
    ASSERT_EQ(answer->status, 200) << answer->body;
    moved = body_of(answer);
  }
  EXPECT_EQ(moved["first"], first);
  const std::vector<float> patch = floats(moved["positions"]);
  ASSERT_EQ(patch.size(), 3u * (end - first));
  const int h = handle - first;
  EXPECT_GT(patch[3 * h + 2] - start[3 * handle + 2], 0.5 * lift) << "the handle follows";
  int moved_vertices = 0;
  for (int v = 0; v < end - first; ++v)
    moved_vertices += std::abs(patch[3 * v + 2] - start[3 * (first + v) + 2]) > 1e-3;
  EXPECT_GT(moved_vertices, 10) << "the patch follows the handle";

  answer = post_json(client, "/api/edit/end", json::object());
  ASSERT_EQ(answer->status, 200) << answer->body;
  const json ended = body_of(answer);
  EXPECT_EQ(ended["undo"], 1);
  EXPECT_EQ(ended["report"]["holes"][0]["self_intersections"], 0);
  EXPECT_NE(ended["report"]["holes"][0]["energy"], hole["energy"]);

  const json after = body_of(client.Get("/api/result"));
  EXPECT_EQ(after["report"], ended["report"]);
  EXPECT_EQ(after["edits"], 1);
  const std::vector<float> edited = floats(after["positions"]);
  ASSERT_EQ(edited.size(), start.size());
  // No vertex of the input moved, bit for bit.
  EXPECT_TRUE(std::equal(start.begin(), start.begin() + 3 * first, edited.begin()));
  // The release keeps the patch as it settled about the handle's last target.
  const std::vector<float> settled = floats(ended["positions"]);
  ASSERT_EQ(settled.size(), patch.size());
  EXPECT_TRUE(std::equal(settled.begin(), settled.end(), edited.begin() + 3 * first));
  EXPECT_GT(settled[3 * h + 2] - start[3 * handle + 2], 0.5 * lift) << "the handle stays";
  // The download is the edited mesh.
  const foldfill::Mesh written = foldfill::parse_mesh(client.Get("/api/download?format=obj")->body,
                                                      foldfill::MeshFormat::Obj, "d.obj");
  EXPECT_NEAR(written.positions[handle][2], edited[3 * handle + 2], 1e-5);

  answer = post_json(client, "/api/undo", json::object());
  ASSERT_EQ(answer->status, 200) << answer->body;
  EXPECT_EQ(body_of(answer)["undo"], 0);
  const json undone = body_of(client.Get("/api/result"));
  EXPECT_EQ(undone["positions"], before["positions"]);
  EXPECT_EQ(undone["report"], before["report"]);
  EXPECT_EQ(post_json(client, "/api/undo", json::object())->status, 400);
}

TEST(Serve, ObstaclesAreParsedShownAndPassedToTheFill) {
  if (!foldfill::cli::serve_available()) GTEST_SKIP() << "serve is not available in this build";
  Served served;
  httplib::Client client = served.client();
  ASSERT_EQ(client.Post("/api/mesh?name=sheet.obj", sheet_obj(), "text/plain")->status, 200);
  // A plane below the sheet (z in [-0.25, 0.25]).
  const std::string text =
      R"({"obstacles": [{"type": "plane", "point": [0, 0, -1], "normal": [0, 0, 1]}]})";
  auto answer = client.Post("/api/obstacles", text, "application/json");
  ASSERT_EQ(answer->status, 200) << answer->body;
  const json shown = body_of(answer);
  ASSERT_EQ(shown["obstacles"].size(), 1u);
  EXPECT_EQ(shown["obstacles"][0]["type"], "plane");
  EXPECT_GT(shown["obstacles"][0]["face_count"].get<int>(), 0);
  // Bad ones: the CLI's message, and a mesh obstacle is uploaded instead.
  answer =
      client.Post("/api/obstacles", R"({"obstacles": [{"type": "cube"}]})", "application/json");
  EXPECT_EQ(answer->status, 400);
  EXPECT_TRUE(body_of(answer)["error"].is_string());
  answer = client.Post("/api/obstacles", R"({"obstacles": [{"type": "mesh", "file": "a.obj"}]})",
                       "application/json");
  EXPECT_EQ(answer->status, 400);
  // A mesh obstacle by upload: a small closed tetrahedron away from the sheet.
  const std::string tetrahedron =
      "v 10 10 10\nv 11 10 10\nv 10 11 10\nv 10 10 11\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";
  answer = client.Post("/api/obstacle-mesh?name=body.obj", tetrahedron, "text/plain");
  ASSERT_EQ(answer->status, 200) << answer->body;
  EXPECT_EQ(body_of(answer)["obstacles"].size(), 2u);
  EXPECT_EQ(body_of(client.Get("/api/obstacles"))["mesh_obstacle"], true);

  const auto started = post_json(client, "/api/fill", {{"compare_liepa", true}});
  ASSERT_EQ(started->status, 200) << started->body;
  const json progress = wait_done(client, 120);
  ASSERT_TRUE(progress.is_object() && progress["error"].is_null()) << progress.dump();
  const json result = body_of(client.Get("/api/result"));
  EXPECT_EQ(result["report"]["options"]["obstacles"], 2);
  EXPECT_EQ(result["report"]["holes"][0]["self_intersections"], 0);
  EXPECT_EQ(result["liepa"], true);
  // The Liepa fill of the same hole, side by side.
  const json liepa = body_of(client.Get("/api/liepa"));
  EXPECT_EQ(liepa["report"]["options"]["method"], "liepa");
  EXPECT_EQ(liepa["report"]["filled_loops"], result["report"]["filled_loops"]);
  EXPECT_GT(liepa["face_count"].get<int>(), liepa["input_face_count"].get<int>());
  // Cleared.
  ASSERT_EQ(client.Post("/api/obstacles", "", "application/json")->status, 200);
  ASSERT_EQ(client.Post("/api/obstacle-mesh", "", "text/plain")->status, 200);
  EXPECT_EQ(body_of(client.Get("/api/obstacles"))["obstacles"].size(), 0u);
}

}  // namespace
