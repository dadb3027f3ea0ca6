// The server of `foldfill serve` (app/serve.h): its endpoints through an
// httplib::Client against a server on a free port, in process.
#include <gtest/gtest.h>

#include <chrono>
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

}  // namespace
