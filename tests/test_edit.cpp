// PatchEditor (edit.h): a filled patch dragged by one vertex moves nothing
// but its own new vertices, crosses nothing, follows the handle, gives the
// same result twice and refuses what it cannot edit.
#include <gtest/gtest.h>

#include "foldfill/edit.h"
#include "foldfill/error.h"
#include "foldfill/examples.h"
#include "foldfill/fill.h"

namespace {

using namespace foldfill;

struct Filled {
  Mesh input;
  FillRequest request;
  FillOutput output;
};

Filled filled_sheet(FillAlgorithm algorithm = FillAlgorithm::Fabric) {
  Filled f;
  f.input = cut_disk_hole(make_folded_sheet(), {2.6, 1.5}, 0.7).cut.mesh;
  f.request.algorithm = algorithm;
  f.output = fill(f.input, f.request);
  return f;
}

// Drags the new vertex in the middle of the range up by `lift` in steps,
// then settles; returns the output mesh as left.
Mesh dragged(const Filled& f, double lift, int* handle = nullptr) {
  const HoleReport& hole = f.output.report.holes.at(0);
  PatchEditor editor(f.input, f.output, 0, f.output.loops.at(hole.loop_id), f.request.options);
  const int v = hole.new_vertices.first + hole.new_vertices.size() / 2;
  if (handle) *handle = v;
  editor.grab(v);
  const Vec3 p = f.output.mesh.positions[v];
  for (int k = 1; k <= 6; ++k) editor.drag({p[0], p[1], p[2] + lift * k / 6});
  editor.settle();
  Mesh mesh = f.output.mesh;
  editor.write(mesh);
  HoleReport measured = hole;
  editor.measure(mesh, measured);
  EXPECT_EQ(measured.self_intersections, 0);
  EXPECT_LT(measured.edge_length_rms_rel_final, 0.2);
  return mesh;
}

TEST(Edit, MovesThePatchAloneAndIsDeterministic) {
  const Filled f = filled_sheet();
  ASSERT_TRUE(f.output.report.holes.at(0).filled);
  int handle = -1;
  const Mesh once = dragged(f, 0.3, &handle);
  const int first = f.output.report.holes[0].new_vertices.first;
  for (int v = 0; v < first; ++v) ASSERT_EQ(once.positions[v], f.output.mesh.positions[v]) << v;
  EXPECT_GT(once.positions[handle][2] - f.output.mesh.positions[handle][2], 0.15);
  EXPECT_EQ(dragged(f, 0.3).positions, once.positions);
}

TEST(Edit, RefusesWhatItCannotEdit) {
  const Filled f = filled_sheet();
  const HoleReport& hole = f.output.report.holes.at(0);
  PatchEditor editor(f.input, f.output, 0, f.output.loops.at(hole.loop_id), f.request.options);
  EXPECT_THROW(editor.grab(0), Error);
  EXPECT_THROW(editor.grab(hole.new_vertices.end), Error);
  EXPECT_THROW(editor.drag({0, 0, 0}), Error);  // nothing grabbed
  EXPECT_EQ(editor.settle().iterations, 0);
  EXPECT_THROW(
      PatchEditor(f.input, f.output, 1, f.output.loops.at(hole.loop_id), f.request.options), Error);
  // A Liepa patch has no rest shape.
  const Filled smooth = filled_sheet(FillAlgorithm::Liepa);
  EXPECT_THROW(PatchEditor(smooth.input, smooth.output, 0, smooth.output.loops.at(hole.loop_id),
                           smooth.request.options),
               Error);
}

}  // namespace
