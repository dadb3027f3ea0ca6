// The entry points of the fuzz targets, shared with tests/test_fuzz_regressions.cpp
// so that every kept input replays exactly as the fuzzer ran it.
//
// Contract checked: bad input ends in a foldfill::Error and nothing else. Any
// other exception (a FuzzCheckFailure when an invariant below is broken, or a
// standard library exception) is a bug; the fuzz targets let it escape so that
// libFuzzer records the input.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "foldfill/error.h"
#include "foldfill/holes.h"
#include "foldfill/inpaint.h"
#include "foldfill/io.h"
#include "foldfill/mesh.h"

namespace foldfill::fuzz {

// A broken invariant: the library accepted an input but misbehaved on it.
class FuzzCheckFailure : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

inline void check(bool condition, const std::string& what) {
  if (!condition) throw FuzzCheckFailure("fuzz check failed: " + what);
}

inline bool same_positions(const std::vector<Vec3>& a, const std::vector<Vec3>& b, size_t count) {
  return a.size() >= count && b.size() >= count &&
         std::memcmp(a.data(), b.data(), count * sizeof(Vec3)) == 0;
}

// Parses `bytes` as `format`; returns whether the reader accepted them. A mesh
// the reader accepts must also write and read back to the same positions (bit
// for bit) and faces: the writers promise round-trip precision, and STL
// positions are float32 values already.
inline bool read_mesh_bytes(std::string_view bytes, MeshFormat format) {
  Mesh mesh;
  try {
    mesh = parse_mesh(bytes, format, "fuzz");
  } catch (const Error&) {
    return false;  // rejected cleanly
  }
  for (bool binary : {true, false}) {
    Mesh again;
    try {
      again = parse_mesh(serialize_mesh(mesh, format, {binary}), format, "round trip");
    } catch (const Error& e) {
      check(false, std::string("an accepted mesh does not read back: ") + e.what());
    }
    check(again.faces == mesh.faces, "faces change in a write/read round trip");
    check(again.positions.size() == mesh.positions.size() &&
              same_positions(again.positions, mesh.positions, mesh.positions.size()),
          "positions change in a write/read round trip");
  }
  return true;
}

// Limits that keep one fill well under a second in a sanitizer build.
struct FillLimits {
  int max_faces = 2000;
  int max_loop_vertices = 200;
  int max_iterations = 50;
  double time_limit_seconds = 0.5;
};

// fill_holes turns every exception of a hole into that hole's reason, so a
// standard library or CGAL exception is told apart by its message: foldfill's
// errors are one line, "SOURCE: problem".
inline bool is_foldfill_message(const std::string& reason) {
  constexpr const char* kLibraryPrefixes[] = {
      "std::",   "vector::",     "basic_string", "CGAL", "cannot create std::",
      "map::at", "_Map_base::at"};
  if (reason.empty() || reason.find('\n') != std::string::npos) return false;
  return std::none_of(std::begin(kLibraryPrefixes), std::end(kLibraryPrefixes),
                      [&](const char* prefix) { return reason.rfind(prefix, 0) == 0; });
}

// The output keeps the input's vertices and faces unchanged and in order,
// appends only valid faces and finite positions, and reports every hole.
inline void check_fill_result(const Mesh& input, const std::vector<int>& fill_ids,
                              const FillResult& result) {
  const Mesh& output = result.mesh;
  check(same_positions(output.positions, input.positions, input.positions.size()),
        "input positions are not kept bit for bit");
  check(output.faces.size() >= input.faces.size() &&
            std::equal(input.faces.begin(), input.faces.end(), output.faces.begin()),
        "input faces are not kept in order");
  try {
    serialize_mesh(output, MeshFormat::Obj);  // validates finiteness and face indices
  } catch (const Error& e) {
    check(false, std::string("the filled mesh is invalid: ") + e.what());
  }
  check(result.report.holes.size() == fill_ids.size(), "a selected hole has no report");
  for (const HoleReport& hole : result.report.holes) {
    check(hole.filled || is_foldfill_message(hole.reason),
          "loop " + std::to_string(hole.loop_id) + " failed with a non-foldfill exception: '" +
              hole.reason + "'");
  }
}

// The whole fill on a small OBJ mesh: boundary loops, the default selection,
// then fill_holes with few iterations. Larger inputs are skipped, not failed.
// Returns the number of holes filled.
inline int fill_mesh_bytes(std::string_view bytes, const FillLimits& limits = {}) {
  try {
    const Mesh mesh = parse_mesh(bytes, MeshFormat::Obj, "fuzz");
    if (mesh.face_count() > limits.max_faces) return 0;
    const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh, "fuzz");
    std::vector<int> fill_ids = select_holes(loops, HoleSelection{}, "fuzz").fill;
    fill_ids.erase(std::remove_if(fill_ids.begin(), fill_ids.end(),
                                  [&](int id) {
                                    return static_cast<int>(loops.at(id).vertices.size()) >
                                           limits.max_loop_vertices;
                                  }),
                   fill_ids.end());
    FillOptions options;
    options.solver.max_iterations = limits.max_iterations;
    options.solver.time_limit_seconds = limits.time_limit_seconds;
    const FillResult result = fill_holes(mesh, loops, fill_ids, options, "fuzz");
    check_fill_result(mesh, fill_ids, result);
    return static_cast<int>(std::count_if(result.report.holes.begin(), result.report.holes.end(),
                                          [](const HoleReport& hole) { return hole.filled; }));
  } catch (const Error&) {
    return 0;  // rejected cleanly
  }
}

}  // namespace foldfill::fuzz
