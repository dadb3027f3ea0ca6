// `foldfill serve [MESH] [--port 8080]`: a local web app in which one opens a
// mesh, picks its loops, sets the parameters, fills with progress and cancel,
// looks at the result and its report and downloads it. The server (cpp-httplib)
// calls the library directly and listens on 127.0.0.1 only.
#pragma once

#include <CLI/CLI.hpp>
#include <cstddef>
#include <memory>
#include <string>

namespace foldfill::cli {

struct ServeArgs {
  std::string mesh;  // opened at the start when given
  int port = 8080;
};

// Adds the `serve` subcommand, its options into `args`.
CLI::App* add_serve_command(CLI::App& app, ServeArgs& args);

// Opens the mesh, then serves until the process is interrupted. Returns the
// exit code.
int run_serve(const ServeArgs& args);

// Whether this build has the server (cpp-httplib) and its page (three.js).
bool serve_available();

// Whether `address`, a peer's numeric address, is on the loopback interface:
// 127.0.0.0/8, ::1 or an IPv4-mapped 127.x address.
bool is_loopback(const std::string& address);

// The largest upload taken (bytes); a larger one is refused with 413.
inline constexpr size_t kMaxUploadBytes = size_t{256} << 20;

// The web app's server: one session (one mesh, its obstacles, its latest fill
// and the edits of it) at a time.
// Endpoints (JSON unless said):
//   GET  /                      the page (and /serve.js, /view.css, /three.js)
//   GET  /api/mesh              the session's mesh, or {"mesh": null}
//   POST /api/mesh?name=F.obj   body: the file's bytes; parsed (format from the
//                               name), kept, its loops and buffers returned
//   POST /api/fill              body: {"holes": "default" or [ids], "lambda",
//                               "shrink", "density", "repulsion", "bending",
//                               "method"}: starts the fill in a worker thread
//   GET  /api/progress          {"job", "hole", "iteration", "energy", "done", ...}
//   POST /api/cancel            cancels the running fill
//   GET  /api/result            the filled mesh's buffers and the report
//   GET  /api/download?format=  the filled mesh as obj, ply, off or stl
//   GET  /api/liepa             with "compare_liepa": true in the fill, CGAL's
//                               Liepa fill of the same holes (buffers, report)
//   POST /api/edit/begin        {"vertex": V}: a new vertex of a fabric patch
//                               becomes the handle (PatchEditor, edit.h)
//   POST /api/edit/move         {"x", "y", "z"}: the handle pulled there, the
//                               patch minimised; its positions come back
//                               ({"first", "count", "positions": base64 float32})
//   POST /api/edit/end          the patch settles and is kept, its report
//                               measured again (crossings with exact predicates)
//   POST /api/undo              the patch and report before the last edit
//   GET  /api/obstacles         the obstacles of the next fills, as triangles
//   POST /api/obstacles         body: obstacles JSON as --obstacles reads (empty: none)
//   POST /api/obstacle-mesh?name=F.obj  body: a mesh obstacle's file (empty: none)
// Errors answer {"error": "one line"}: 400 for a bad request or upload (its
// message as the CLI gives it, "FILE: problem") or while a fill runs, 403 for
// a peer not on loopback, 404 for nothing to give, 413 for an upload over the
// limit.
class Server {
 public:
  explicit Server(size_t max_upload_bytes = kMaxUploadBytes);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  // Parses `bytes` as the file `name` and makes it the session's mesh. Throws
  // foldfill::Error as parse_mesh and find_boundary_loops do.
  void open(const std::string& bytes, const std::string& name);
  // Binds 127.0.0.1:`port` (0: a free port). Returns the port, or -1 when it
  // cannot be bound.
  int bind(int port);
  // Serves on the bound port until stop(). Returns false on failure.
  bool listen();
  void stop();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace foldfill::cli
