// The whole fill on exactly developable sheets, where the truth is known.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>

#include "foldfill/error.h"
#include "foldfill/examples.h"
#include "foldfill/holes.h"
#include "foldfill/inpaint.h"
#include "foldfill/metrics.h"
#include "foldfill/vec3.h"
#include "test_geometry.h"

namespace foldfill {
namespace {

// A folded sheet with one disk-shaped hole cut across its folds.
CutMesh folded_sheet_with_hole(double radius = 0.5) {
  return cut_disk_hole(testing::small_folded_sheet(0.08), {1.9, 1.0}, radius);
}

FillResult fill_default(const Mesh& mesh, const FillOptions& options = {}) {
  const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh);
  const HoleChoice choice = select_holes(loops, HoleSelection{});
  return fill_holes(mesh, loops, choice.fill, options);
}

std::vector<Tri> new_faces(const FillResult& result, const Mesh& input) {
  return {result.mesh.faces.begin() + input.face_count(), result.mesh.faces.end()};
}

TEST(Inpaint, KeepsInputVerticesAndFacesBitForBit) {
  const CutMesh cut = folded_sheet_with_hole();
  const FillResult result = fill_default(cut.cut.mesh);
  ASSERT_EQ(result.report.holes.size(), 1u);
  ASSERT_TRUE(result.report.holes[0].filled) << result.report.holes[0].reason;
  const Mesh& in = cut.cut.mesh;
  ASSERT_GT(result.mesh.vertex_count(), in.vertex_count());
  EXPECT_TRUE(std::equal(in.positions.begin(), in.positions.end(), result.mesh.positions.begin()));
  EXPECT_TRUE(std::equal(in.faces.begin(), in.faces.end(), result.mesh.faces.begin()));
  // The hole is closed: only the sheet's outer loop is left.
  const std::vector<BoundaryLoop> loops = find_boundary_loops(result.mesh);
  EXPECT_EQ(loops.size(), 1u);
}

TEST(Inpaint, PutsBackTheMissingClothIsometrically) {
  const CutMesh cut = folded_sheet_with_hole();
  const FillResult result = fill_default(cut.cut.mesh);
  const HoleReport& hole = result.report.holes.at(0);
  ASSERT_TRUE(hole.filled) << hole.reason;
  EXPECT_LT(hole.edge_length_rms_rel_final, 0.01);
  const double patch_area = total_area(result.mesh.positions, new_faces(result, cut.cut.mesh));
  EXPECT_NEAR(patch_area / cut.removed_area, 1.0, 0.01);
  EXPECT_EQ(hole.self_intersections, 0);
  EXPECT_LE(hole.energy_final.total, hole.energy_after_arap.total);
}

TEST(Inpaint, ScalingTheInputScalesTheOutput) {
  const CutMesh cut = folded_sheet_with_hole(0.35);
  Mesh scaled = cut.cut.mesh;
  for (Vec3& p : scaled.positions) {
    for (double& x : p) x *= 1000;
  }
  const FillResult unit = fill_default(cut.cut.mesh), big = fill_default(scaled);
  ASSERT_EQ(unit.mesh.vertex_count(), big.mesh.vertex_count());
  double worst = 0;
  for (int v = cut.cut.mesh.vertex_count(); v < unit.mesh.vertex_count(); ++v) {
    for (int k = 0; k < 3; ++k) {
      worst =
          std::max(worst, std::abs(big.mesh.positions[v][k] / 1000 - unit.mesh.positions[v][k]));
    }
  }
  EXPECT_LT(worst, 1e-6 * unit.report.holes[0].length_scale * 10);
}

// A sphere poking up into the hole from below the sheet, clear of the
// strip: the patch rests on it and goes no deeper into it than the
// obstacle's allowance (the gap of its triangulation), whose faces it never
// crosses.
TEST(Inpaint, KeepsThePatchOutsideAnObstacle) {
  const CutMesh cut = folded_sheet_with_hole();
  const std::vector<BoundaryLoop> loops = find_boundary_loops(cut.cut.mesh);
  const BoundaryLoop& hole = loops.at(select_holes(loops, HoleSelection{}).fill.at(0));
  Obstacle sphere;
  sphere.center = {hole.centroid[0], hole.centroid[1], hole.centroid[2] - 0.2};
  sphere.radius = 0.35;
  FillOptions options;
  options.obstacles = {sphere};
  const FillResult result = fill_default(cut.cut.mesh, options);
  const HoleReport& report = result.report.holes.at(0);
  ASSERT_TRUE(report.filled) << report.reason;
  EXPECT_NE(report.start, StartKind::Unguarded);
  EXPECT_LT(report.obstacle_allowance, 0.05);
  int resting = 0;
  for (int v = cut.cut.mesh.vertex_count(); v < result.mesh.vertex_count(); ++v) {
    const double distance = signed_distance(sphere, result.mesh.positions[v]);
    EXPECT_GE(distance, -report.obstacle_allowance * report.length_scale);
    resting += distance < 0.2 * report.length_scale;
  }
  EXPECT_GT(resting, 5);
  EXPECT_EQ(report.crossings.patch_obstacles, 0);
  EXPECT_EQ(report.self_intersections, 0);
}

TEST(Inpaint, ResultDoesNotDependOnTheThreadCount) {
  // Two holes, filled in parallel or one after the other.
  FoldedSheetOptions options;
  options.edge_length = 0.1;
  const DevelopableMesh sheet = make_folded_sheet(options);
  const CutMesh first = cut_disk_hole(sheet, {1.2, 1.5}, 0.4);
  const CutMesh both = cut_disk_hole(first.cut, {3.6, 1.5}, 0.4);
  omp_set_num_threads(1);
  const FillResult serial = fill_default(both.cut.mesh);
  omp_set_num_threads(2);
  const FillResult parallel = fill_default(both.cut.mesh);
  ASSERT_EQ(serial.report.holes.size(), 2u);
  EXPECT_EQ(serial.mesh.positions, parallel.mesh.positions);
  EXPECT_EQ(serial.mesh.faces, parallel.mesh.faces);
}

// A band one triangle wide along a closed curve that waves up and down
// `waves` times around the unit circle. Its hole's loop is much longer than
// the circle, so the flat patch has more cloth than the frame spans: at a
// small bending weight it crumples, as the reference contour example does.
Mesh wavy_band(int segments, double amplitude, int waves) {
  Mesh band;
  const double width = 2 * M_PI / segments;
  for (double radius : {1.0, 1.0 + width})
    for (int k = 0; k < segments; ++k) {
      const double angle = 2 * M_PI * k / segments;
      band.positions.push_back({radius * std::cos(angle), radius * std::sin(angle),
                                amplitude * std::sin(waves * angle)});
    }
  for (int k = 0; k < segments; ++k) {
    const int a = k, b = (k + 1) % segments, c = segments + b, d = segments + a;
    band.faces.push_back({a, d, c});
    band.faces.push_back({a, c, b});
  }
  return band;
}

// A crumpling band (its patch has far more cloth than the frame spans) is
// minimised once, with the bending weight asked for, and crosses nothing:
// the contact keeps every step clean.
TEST(Inpaint, CrumpledBandsFillWithTheWeightsAskedForAndCrossNothing) {
  const FillOptions options;
  for (int segments : {40, 48, 56})
    for (int waves : {5, 6}) {
      SCOPED_TRACE(std::to_string(segments) + " segments, " + std::to_string(waves) + " waves");
      const Mesh band = wavy_band(segments, 0.5, waves);
      const FillResult result = fill_holes(band, find_boundary_loops(band), {0}, options);
      const HoleReport& hole = result.report.holes.at(0);
      ASSERT_TRUE(hole.filled) << hole.reason;
      EXPECT_NE(hole.start, StartKind::Unguarded);
      EXPECT_EQ(hole.self_intersections, 0);
      EXPECT_EQ(
          count_self_intersections(result.mesh.positions, result.mesh.faces, band.face_count()), 0);
      EXPECT_EQ(hole.lambda, options.energy.lambda);
      EXPECT_EQ(hole.repulsion, options.energy.repulsion);
      EXPECT_TRUE(hole.warning.empty()) << hole.warning;
    }
}

bool starts_with(const std::string& text, const std::string& prefix) {
  return text.rfind(prefix, 0) == 0;
}

FillOptions without_fallback() {
  FillOptions options;
  options.fallback.enabled = false;
  return options;
}

TEST(Inpaint, ReportsAHoleThatCannotBeFilledAndLeavesItOpen) {
  // The fabric method cannot fill the outer edge of a sheet; without the
  // fallback chain the loop stays open with the reason.
  const CutMesh cut = folded_sheet_with_hole();
  const std::vector<BoundaryLoop> loops = find_boundary_loops(cut.cut.mesh);
  const std::vector<int> outer = longest_loops(loops);
  const FillResult result = fill_holes(cut.cut.mesh, loops, outer, without_fallback());
  ASSERT_EQ(result.report.holes.size(), 1u);
  EXPECT_FALSE(result.report.holes[0].filled);
  EXPECT_FALSE(result.report.holes[0].reason.empty());
  EXPECT_EQ(result.mesh.positions, cut.cut.mesh.positions);
  EXPECT_EQ(result.mesh.faces, cut.cut.mesh.faces);
}

// What the fabric method cannot fill, the chain closes, each step passed over
// with its reason; the original vertices and faces stay as they were.
TEST(Inpaint, TheFallbackChainClosesWhatTheFabricMethodCannot) {
  const CutMesh cut = folded_sheet_with_hole();
  const std::vector<BoundaryLoop> loops = find_boundary_loops(cut.cut.mesh);
  const int outer = longest_loops(loops).at(0);
  const FillResult result = fill_holes(cut.cut.mesh, loops, {outer});
  const HoleReport& hole = result.report.holes.at(0);
  ASSERT_TRUE(hole.filled) << hole.reason;
  EXPECT_NE(hole.method, FillMethod::Fabric);
  ASSERT_FALSE(hole.fallback_reasons.empty());
  EXPECT_TRUE(starts_with(hole.fallback_reasons[0], "fabric: ")) << hole.fallback_reasons[0];
  EXPECT_GT(hole.patch_min_angle_deg, 0);
  EXPECT_EQ(std::vector<Vec3>(result.mesh.positions.begin(),
                              result.mesh.positions.begin() + cut.cut.mesh.vertex_count()),
            cut.cut.mesh.positions);
  EXPECT_EQ(std::vector<Tri>(result.mesh.faces.begin(),
                             result.mesh.faces.begin() + cut.cut.mesh.face_count()),
            cut.cut.mesh.faces);
  EXPECT_EQ(find_boundary_loops(result.mesh).size(), loops.size() - 1);
}

// ---- Limits ----------------------------------------------------------------------

// A hole whose patch has about 8,000 vertices (its minimisation takes about
// 0.3 s on the 2-core development machine).
CutMesh big_hole() {
  FoldedSheetOptions options;
  options.width = 3;
  options.height = 2.4;
  options.edge_length = 0.016;
  options.amplitude = 0.15;
  options.folds = 3;
  return cut_disk_hole(make_folded_sheet(options), {1.9, 1.2}, 0.8);
}

TEST(InpaintLimits, TimeLimitBoundsTheMinimisationOfABigPatch) {
  const CutMesh cut = big_hole();
  FillOptions options;
  // A sixth of what the minimisation needs, so that a faster machine (or
  // solver) still runs into it.
  options.solver.time_limit_seconds = 0.05;
  const FillResult result = fill_default(cut.cut.mesh, options);
  const HoleReport& hole = result.report.holes.at(0);
  ASSERT_TRUE(hole.filled) << hole.reason;
  EXPECT_GT(hole.patch_vertex_count, 5000);
  EXPECT_EQ(hole.method, FillMethod::Fabric) << ::testing::PrintToString(hole.fallback_reasons);
  EXPECT_EQ(hole.stop_reason, StopReason::TimeLimit);
  // Loose: the energy's set-up and the final checks run outside the solver's
  // clock, and sanitizer builds or a loaded CI machine run them slower.
  EXPECT_LT(hole.seconds.optimize, 20 * options.solver.time_limit_seconds);
  EXPECT_LE(hole.energy_final.total, hole.energy_after_arap.total);
}

// Several holes, to be filled in parallel.
CutMesh four_holes() {
  FoldedSheetOptions options;
  options.edge_length = 0.1;
  CutMesh cut{make_folded_sheet(options), 0, 0};
  for (const Vec2& centre : {Vec2{1.2, 0.9}, Vec2{3.6, 0.9}, Vec2{1.2, 2.1}, Vec2{3.6, 2.1}})
    cut = cut_disk_hole(cut.cut, centre, 0.4);
  return cut;
}

TEST(InpaintLimits, CancellingFromTheProgressCallbackStopsEveryHole) {
  const Mesh mesh = four_holes().cut.mesh;
  const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh);
  const std::vector<int> holes = select_holes(loops, HoleSelection{}).fill;
  ASSERT_EQ(holes.size(), 4u);
  std::atomic<int> calls{0};
  FillOptions options;
  options.progress = [&](int, const SolverProgress&) {
    ++calls;
    return false;
  };
  const FillResult result = fill_holes(mesh, loops, holes, options, "sheet.obj");
  EXPECT_TRUE(result.report.cancelled);
  // Once one hole has cancelled, no other asks again: at most one call per thread.
  EXPECT_GE(calls.load(), 1);
  EXPECT_LE(calls.load(), omp_get_max_threads());
  for (const HoleReport& hole : result.report.holes) {
    EXPECT_FALSE(hole.filled);
    EXPECT_EQ(hole.reason, "sheet.obj: loop " + std::to_string(hole.loop_id) + ": cancelled");
  }
  EXPECT_EQ(result.mesh.positions, mesh.positions);
  EXPECT_EQ(result.mesh.faces, mesh.faces);
}

// What the user sets is what is used: a fill reads its options and never
// writes them, the user's solver.progress is called alongside
// FillOptions::progress, and a conflict is an error rather than an override.
TEST(InpaintOptions, BothProgressCallbacksAreCalledAndTheOptionsAreLeftAsSet) {
  std::atomic<int> solver_calls{0}, fill_calls{0};
  FillOptions options;
  options.energy.lambda = 0.003;
  options.solver.time_limit_seconds = 60;
  options.solver.progress = [&](const SolverProgress&) {
    ++solver_calls;
    return true;
  };
  options.progress = [&](int, const SolverProgress&) {
    ++fill_calls;
    return true;
  };
  const FillResult result = fill_default(four_holes().cut.mesh, options);
  ASSERT_FALSE(result.report.cancelled);
  ASSERT_EQ(result.report.holes.size(), 4u);
  EXPECT_GT(solver_calls.load(), 0);
  EXPECT_EQ(solver_calls.load(), fill_calls.load());
  for (const HoleReport& hole : result.report.holes) {
    ASSERT_TRUE(hole.filled) << hole.reason;
    EXPECT_EQ(hole.lambda, 0.003);  // the weight asked for is the weight used
  }
  EXPECT_EQ(options.energy.lambda, 0.003);
  EXPECT_EQ(options.solver.time_limit_seconds, 60);
  EXPECT_TRUE(options.solver.progress);
}

TEST(InpaintOptions, PrototypeWeightsTogetherWithOwnWeightsAreAUsageError) {
  FillOptions options;
  options.prototype = PrototypeWeights{};
  options.energy.repulsion = 0.5;
  try {
    fill_default(four_holes().cut.mesh, options);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Usage);
    EXPECT_NE(std::string(e.what()).find("set one or the other"), std::string::npos) << e.what();
  }
}

TEST(InpaintLimits, CancellingLaterKeepsTheHolesAlreadyFilled) {
  const Mesh mesh = four_holes().cut.mesh;
  const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh);
  const std::vector<int> holes = select_holes(loops, HoleSelection{}).fill;
  // The callback cancels when a third hole starts minimising: the holes that
  // had finished by then stay filled, the others are left open.
  std::atomic<int> finished{0};
  FillOptions options;
  options.progress = [&](int, const SolverProgress& p) {
    if (p.iteration == 1) ++finished;
    return finished < 3;
  };
  const FillResult result = fill_holes(mesh, loops, holes, options, "sheet.obj");
  EXPECT_TRUE(result.report.cancelled);
  int filled = 0;
  for (const HoleReport& hole : result.report.holes) {
    filled += hole.filled;
    if (!hole.filled) {
      EXPECT_NE(hole.reason.find("cancelled"), std::string::npos) << hole.reason;
    }
  }
  EXPECT_LT(filled, 4);
  // The result is a valid mesh: the input, and the filled holes closed.
  EXPECT_TRUE(std::equal(mesh.faces.begin(), mesh.faces.end(), result.mesh.faces.begin()));
  std::vector<BoundaryLoop> after;
  ASSERT_NO_THROW(after = find_boundary_loops(result.mesh));
  EXPECT_EQ(after.size(), loops.size() - filled);
}

// Gradient descent with a step that overshoots every time: the step bound
// keeps it from crossing anything, the energy does not go down, and the
// lowest-energy state seen (the start) is kept; a divergence is reported.
TEST(InpaintLimits, AnOvershootingStepKeepsTheBestStateAndCrossesNothing) {
  const CutMesh cut = folded_sheet_with_hole();
  FillOptions options;
  options.solver.kind = SolverKind::GradientDescent;
  options.solver.step = 1e3;
  options.solver.max_iterations = 50;
  const FillResult result = fill_default(cut.cut.mesh, options);
  const HoleReport& hole = result.report.holes.at(0);
  ASSERT_TRUE(hole.filled) << hole.reason;
  EXPECT_LE(hole.energy_final.total, hole.energy_after_arap.total);
  if (hole.stop_reason == StopReason::Diverged) {
    EXPECT_NE(hole.warning.find("diverged"), std::string::npos) << hole.warning;
    EXPECT_TRUE(starts_with(hole.warning, "mesh: loop " + std::to_string(hole.loop_id) + ": "));
  }
  EXPECT_EQ(hole.self_intersections, 0);
  for (int v = cut.cut.mesh.vertex_count(); v < result.mesh.vertex_count(); ++v)
    for (double x : result.mesh.positions[v]) EXPECT_TRUE(std::isfinite(x));
  EXPECT_EQ(find_boundary_loops(result.mesh).size(), 1u);
}

TEST(InpaintLimits, NonFiniteWeightsAreRefusedNotACrash) {
  const CutMesh cut = folded_sheet_with_hole();
  FillOptions options;
  options.energy.lambda = std::nan("");
  const FillResult result = fill_default(cut.cut.mesh, options);
  const HoleReport& hole = result.report.holes.at(0);
  EXPECT_FALSE(hole.filled);
  EXPECT_TRUE(starts_with(hole.reason, "mesh: loop " + std::to_string(hole.loop_id) + ": "))
      << hole.reason;
  EXPECT_EQ(result.mesh.positions, cut.cut.mesh.positions);
  EXPECT_EQ(result.mesh.faces, cut.cut.mesh.faces);
}

// ---- Refusals name the file and the loop ----------------------------------------

using testing::rippled_collar;

TEST(InpaintRefusals, AnUnknownLoopIdThrows) {
  const CutMesh cut = folded_sheet_with_hole();
  const std::vector<BoundaryLoop> loops = find_boundary_loops(cut.cut.mesh);
  EXPECT_THROW(fill_holes(cut.cut.mesh, loops, {0, static_cast<int>(loops.size())}), Error);
  EXPECT_THROW(fill_holes(cut.cut.mesh, loops, {-1}), Error);
}

TEST(InpaintRefusals, AFlatteningThatFailsNamesTheFileAndTheLoop) {
  const Mesh collar = rippled_collar();
  const std::vector<BoundaryLoop> loops = find_boundary_loops(collar, "collar.obj");
  const int inner = loops[0].vertices[0] < 48 ? 0 : 1;
  const FillResult result = fill_holes(collar, loops, {inner}, without_fallback(), "collar.obj");
  const HoleReport& hole = result.report.holes.at(0);
  EXPECT_FALSE(hole.filled);
  EXPECT_EQ(hole.reason, "collar.obj: loop " + std::to_string(inner) +
                             ": the flattened hole outline crosses itself");
  EXPECT_EQ(result.mesh.faces, collar.faces);
}

// The same outline, repaired: walked from the loop's edge lengths and angles,
// blended with a circle's until it is simple, and filled by the fabric
// method from there.
TEST(InpaintRefusals, AnOutlineThatCrossesItselfIsRepaired) {
  const Mesh collar = rippled_collar();
  const std::vector<BoundaryLoop> loops = find_boundary_loops(collar, "collar.obj");
  const int inner = loops[0].vertices[0] < 48 ? 0 : 1;
  const FillResult result = fill_holes(collar, loops, {inner}, {}, "collar.obj");
  const HoleReport& hole = result.report.holes.at(0);
  ASSERT_TRUE(hole.filled) << hole.reason;
  EXPECT_EQ(hole.method, FillMethod::FabricRepaired)
      << ::testing::PrintToString(hole.fallback_reasons);
  ASSERT_FALSE(hole.fallback_reasons.empty());
  EXPECT_EQ(hole.fallback_reasons[0], "fabric: the flattened hole outline crosses itself");
  EXPECT_TRUE(hole.flattening_fit.simple_polygon);
  EXPECT_EQ(hole.flattening_fit.flipped_triangles, 0);
  // The repaired outline keeps the loop's edge lengths up to the closing gap.
  EXPECT_LT(hole.flattening_fit.edge_length_max_rel, 0.2);
  EXPECT_EQ(hole.self_intersections, 0);
}

TEST(InpaintRefusals, AnOuterEdgeIsNotFilled) {
  const CutMesh cut = folded_sheet_with_hole();
  const std::vector<BoundaryLoop> loops = find_boundary_loops(cut.cut.mesh, "sheet.obj");
  const int outer = longest_loops(loops).at(0);
  const FillResult result =
      fill_holes(cut.cut.mesh, loops, {outer}, without_fallback(), "sheet.obj");
  const HoleReport& hole = result.report.holes.at(0);
  EXPECT_FALSE(hole.filled);
  EXPECT_TRUE(starts_with(hole.reason, "sheet.obj: loop " + std::to_string(outer) + ": "))
      << hole.reason;
  EXPECT_NE(hole.reason.find("outer edge"), std::string::npos) << hole.reason;
}

// A time limit that passes before the start is placed: ARAP, the coarse
// levels and the minimisation all stop at once, and the hole is kept as it is
// then (the flat patch on the loop), reported as stopped by the time limit.
TEST(Inpaint, TimeLimitPassingBeforeTheStartStopsEveryStageAndSaysSo) {
  const CutMesh cut = folded_sheet_with_hole(0.7);
  FillOptions options;
  options.solver.time_limit_seconds = 1e-9;
  options.multilevel.min_patch_vertices = 400;
  const FillResult result = fill_default(cut.cut.mesh, options);
  const HoleReport& hole = result.report.holes.at(0);
  ASSERT_TRUE(hole.filled) << hole.reason;
  EXPECT_EQ(hole.stop_reason, StopReason::TimeLimit);
  EXPECT_EQ(hole.iterations, 0);
  EXPECT_NE(hole.warning.find("the time limit stopped the minimisation after 0 iterations"),
            std::string::npos)
      << hole.warning;
  // Without a limit the same hole converges.
  const FillResult unlimited = fill_default(cut.cut.mesh);
  EXPECT_EQ(unlimited.report.holes.at(0).stop_reason, StopReason::Converged);
  EXPECT_GT(unlimited.report.holes.at(0).iterations, 0);
}

// A grid and a triangle that touches one of its corners: the two pieces meet
// at that vertex only, so neither loop through it bounds a disk.
TEST(InpaintRefusals, ALoopThatIsNotADiskNamesTheFileAndTheLoop) {
  Mesh grid;
  const int n = 6;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) grid.positions.push_back({double(i), double(j), 0});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
      grid.faces.push_back({a, b, c});
      grid.faces.push_back({a, c, d});
    }
  const int corner = 0, first = grid.vertex_count();
  grid.positions.push_back({-1, 0, 0});
  grid.positions.push_back({0, -1, 0});
  grid.faces.push_back({corner, first, first + 1});
  const std::vector<BoundaryLoop> loops = find_boundary_loops(grid, "grid.obj");
  ASSERT_EQ(loops.size(), 2u);
  std::vector<int> pinched;
  for (const BoundaryLoop& loop : loops)
    if (!loop.is_disk) pinched.push_back(loop.id);
  ASSERT_EQ(pinched.size(), 2u);
  const FillResult result = fill_holes(grid, loops, pinched, {}, "grid.obj");
  for (const HoleReport& hole : result.report.holes) {
    EXPECT_FALSE(hole.filled);
    EXPECT_TRUE(
        starts_with(hole.reason, "grid.obj: loop " + std::to_string(hole.loop_id) + ": touches "))
        << hole.reason;
  }
  EXPECT_EQ(result.mesh.faces, grid.faces);
}

// Two missing squares of a waved grid that share a corner: the boundary passes
// it twice and is split there; both holes are filled, and the output is a
// manifold whose only loop is the outer one.
TEST(Inpaint, TwoHolesMeetingAtACornerAreBothFilled) {
  Mesh grid;
  const int n = 8;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      grid.positions.push_back({double(i), double(j), 0.3 * std::sin(0.7 * i) * std::cos(0.5 * j)});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if ((i >= 2 && i < 4 && j >= 2 && j < 4) || (i >= 4 && i < 6 && j >= 4 && j < 6)) continue;
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
      grid.faces.push_back({a, b, c});
      grid.faces.push_back({a, c, d});
    }
  const std::vector<BoundaryLoop> loops = find_boundary_loops(grid, "grid.obj");
  ASSERT_EQ(loops.size(), 3u);
  const HoleChoice choice = select_holes(loops, {});
  ASSERT_EQ(choice.fill.size(), 2u);
  const FillResult result = fill_holes(grid, loops, choice.fill, {}, "grid.obj");
  for (const HoleReport& hole : result.report.holes) EXPECT_TRUE(hole.filled) << hole.reason;
  EXPECT_TRUE(std::equal(grid.faces.begin(), grid.faces.end(), result.mesh.faces.begin()));
  const std::vector<BoundaryLoop> after = find_boundary_loops(result.mesh, "filled.obj");
  ASSERT_EQ(after.size(), 1u);
  EXPECT_EQ(after[0].vertices.size(), 4u * n);
  EXPECT_TRUE(after[0].split_at.empty());
  EXPECT_EQ(count_self_intersections(result.mesh.positions, result.mesh.faces, grid.face_count()),
            0);
}

// A flat sheet with a hole and, as another part of the same mesh, a closed
// spike whose tip pokes up through the hole: every taut surface spanning the
// loop passes through the spike, so the start is untangled (untangle.h) and
// the fill goes over the tip, crossing nothing; the same at 1000 times the size.
Mesh sheet_over_a_spike(double scale) {
  std::vector<Vec2> profile;
  for (int k = 0; k <= 40; ++k) profile.push_back({0.1 * k, 0});
  const CutMesh sheet = cut_disk_hole(make_profile_sheet(profile, 4, 0.1), {2, 2}, 0.5);
  Mesh mesh = sheet.cut.mesh;
  const int first = mesh.vertex_count();
  const double r = 0.15;
  mesh.positions.insert(mesh.positions.end(), {{2, 2, 0.3},
                                               {2 - r, 2 - r, -1},
                                               {2 + r, 2 - r, -1},
                                               {2 + r, 2 + r, -1},
                                               {2 - r, 2 + r, -1}});
  for (int k = 0; k < 4; ++k) mesh.faces.push_back({first, first + 1 + k, first + 1 + (k + 1) % 4});
  mesh.faces.push_back({first + 1, first + 3, first + 2});
  mesh.faces.push_back({first + 1, first + 4, first + 3});
  for (Vec3& p : mesh.positions) p = scaled(p, scale);
  return mesh;
}

// The spike mesh's hole (the shorter of its two loops).
int spike_hole(const std::vector<BoundaryLoop>& loops) {
  return loops[0].vertices.size() < loops[1].vertices.size() ? loops[0].id : loops[1].id;
}

// The fill of the spike mesh crosses nothing and goes over the tip.
void expect_over_the_spike(const Mesh& mesh, const FillResult& result, double scale) {
  EXPECT_EQ(result.report.holes.at(0).crossings.total(), 0);
  EXPECT_EQ(count_self_intersections(result.mesh.positions, result.mesh.faces, mesh.face_count()),
            0);
  double top = -1e9;
  for (size_t v = mesh.positions.size(); v < result.mesh.positions.size(); ++v)
    top = std::max(top, result.mesh.positions[v][2]);
  EXPECT_GT(top, 0.3 * scale);  // over the tip
}

TEST(Inpaint, ASpikeThroughTheHoleIsGoneOverFromAnUntangledStart) {
  for (double scale : {1.0, 1000.0}) {
    SCOPED_TRACE("scale " + std::to_string(scale));
    const Mesh mesh = sheet_over_a_spike(scale);
    const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh);
    ASSERT_EQ(loops.size(), 2u);
    const FillResult result = fill_holes(mesh, loops, {spike_hole(loops)}, without_fallback());
    const HoleReport& report = result.report.holes.at(0);
    ASSERT_TRUE(report.filled) << report.reason;
    EXPECT_EQ(report.start, StartKind::Untangled);
    expect_over_the_spike(mesh, result, scale);
  }
}

// The same spike under a patch large enough for coarser levels: the
// coarsest level's ARAP start and membrane pass through the spike, that start
// is untangled, and the coarse levels lead the patch over the tip. The tip is
// a sharp point: the finer triangles' chords over it cut deeper into the
// coarse surface than the default interpolation clearance allows for (the
// patch then starts again from its own ARAP start, untangled), so the coarse
// levels keep half a finer edge more.
TEST(Inpaint, ASpikeThroughALargeHoleIsGoneOverFromAnUntangledCoarsestLevel) {
  const Mesh mesh = sheet_over_a_spike(1);
  const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh);
  FillOptions options = without_fallback();
  options.triangulate.density = 3;
  options.multilevel.min_patch_vertices = 400;
  options.multilevel.interpolation_clearance = 0.5;
  const FillResult result = fill_holes(mesh, loops, {spike_hole(loops)}, options);
  const HoleReport& report = result.report.holes.at(0);
  ASSERT_TRUE(report.filled) << report.reason;
  ASSERT_GE(report.patch_vertex_count, options.multilevel.min_patch_vertices);
  EXPECT_EQ(report.start, StartKind::CoarseLevelsUntangled);
  EXPECT_STREQ(to_string(report.start), "coarse_levels_untangled");
  // Over the tip the coarsest level comes near the spike: it is guarded.
  EXPECT_EQ(report.unguarded_coarse_levels, 0);
  expect_over_the_spike(mesh, result, 1);
}

// Both fills filled, by the same number of iterations, to the same output
// positions, crossing nothing.
void expect_the_same_fill(const FillResult& fast, const FillResult& slow) {
  const HoleReport& fast_hole = fast.report.holes.at(0);
  const HoleReport& slow_hole = slow.report.holes.at(0);
  ASSERT_TRUE(fast_hole.filled) << fast_hole.reason;
  ASSERT_TRUE(slow_hole.filled) << slow_hole.reason;
  EXPECT_EQ(fast_hole.iterations, slow_hole.iterations);
  EXPECT_EQ(fast.mesh.positions, slow.mesh.positions);
  EXPECT_EQ(fast_hole.crossings.total(), 0);
}

// The folds-first pass runs without the contact first. Far from everything
// its end is a clean start, and the fill is the one the guarded pass gives,
// bit for bit (the barrier never acts and no step is bounded on the way).
TEST(Inpaint, AFoldsFirstPassFarFromEverythingRunsUnguardedToTheSameFill) {
  const CutMesh cut = folded_sheet_with_hole();
  FillOptions guarded;
  guarded.unguarded_folds_first = false;
  const FillResult fast = fill_default(cut.cut.mesh);
  const FillResult slow = fill_default(cut.cut.mesh, guarded);
  expect_the_same_fill(fast, slow);
  EXPECT_EQ(fast.report.holes.at(0).folds_first, FoldsFirstPass::Unguarded);
  EXPECT_EQ(slow.report.holes.at(0).folds_first, FoldsFirstPass::Guarded);
  EXPECT_STREQ(to_string(fast.report.holes.at(0).folds_first), "unguarded");
  EXPECT_EQ(fast.mesh.faces, slow.mesh.faces);
}

// Coarse levels far from everything are minimised with the analytic
// obstacles only, each one's end kept (it keeps the level's thickness from
// everything): the fill is the guarded one, bit for bit.
TEST(Inpaint, CoarseLevelsFarFromEverythingRunUnguardedToTheSameFill) {
  const CutMesh cut = folded_sheet_with_hole(0.6);
  FillOptions options;
  options.triangulate.density = 2;
  options.multilevel.min_patch_vertices = 60;
  FillOptions guarded = options;
  guarded.multilevel.unguarded_first = false;
  const FillResult fast = fill_default(cut.cut.mesh, options);
  const FillResult slow = fill_default(cut.cut.mesh, guarded);
  expect_the_same_fill(fast, slow);
  ASSERT_EQ(fast.report.holes.at(0).start, StartKind::CoarseLevels);
  EXPECT_GE(fast.report.holes.at(0).unguarded_coarse_levels, 2);
  EXPECT_EQ(slow.report.holes.at(0).unguarded_coarse_levels, 0);
}

// Over the spike the stiff pass, unguarded, would pull the untangled start
// back through the tip: its end crosses the spike, so the pass runs again
// guarded and the fill stays over the tip.
TEST(Inpaint, AnUnguardedFoldsFirstPassThatEndsCrossingIsRunAgainGuarded) {
  const Mesh mesh = sheet_over_a_spike(1);
  const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh);
  const FillResult result = fill_holes(mesh, loops, {spike_hole(loops)}, without_fallback());
  const HoleReport& report = result.report.holes.at(0);
  ASSERT_TRUE(report.filled) << report.reason;
  EXPECT_EQ(report.start, StartKind::Untangled);
  EXPECT_EQ(report.folds_first, FoldsFirstPass::Guarded);
  expect_over_the_spike(mesh, result, 1);
}

// Without untangling rounds the spike's start stays unguarded (so the test
// above tests the untangling); start options out of range are usage errors.
TEST(Inpaint, StartOptionsAreUsedAndChecked) {
  const Mesh mesh = sheet_over_a_spike(1);
  const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh);
  FillOptions options;
  options.fallback.enabled = false;
  options.start.untangle.rounds = 0;
  const FillResult result = fill_holes(mesh, loops, {spike_hole(loops)}, options);
  EXPECT_EQ(result.report.holes.at(0).start, StartKind::Unguarded);
  EXPECT_GT(result.report.holes.at(0).crossings.total(), 0);
  EXPECT_NE(result.report.holes.at(0).warning.find("untangling did not clear them"),
            std::string::npos)
      << result.report.holes.at(0).warning;
  for (int k = 0; k < 5; ++k) {
    FillOptions bad;
    if (k == 0) bad.start.obstacle_clearance = 0;
    if (k == 1) bad.start.membrane_bisections = -1;
    if (k == 2) bad.start.untangle.rounds = -1;
    if (k == 3) bad.start.untangle.iterations_per_round = 0;
    if (k == 4) bad.start.untangle.weights[1] = -1;
    EXPECT_THROW(fill_holes(mesh, loops, {spike_hole(loops)}, bad), UsageError) << k;
  }
}

// A time limit that passes before the spike's start is untangled leaves it
// unguarded, and the warning and the fallback's reason say that the time
// limit, not the untangling, is why: with the fallback chain the unguarded
// fabric fill is still the one kept (every other step's patch crosses too).
TEST(Inpaint, ATimeLimitThatEndsTheSearchForACleanStartIsNamed) {
  const Mesh mesh = sheet_over_a_spike(1);
  const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh);
  for (bool fallback : {false, true}) {
    SCOPED_TRACE(fallback ? "with the fallback chain" : "without");
    FillOptions options;
    options.fallback.enabled = fallback;
    options.solver.time_limit_seconds = 1e-9;
    const HoleReport report =
        fill_holes(mesh, loops, {spike_hole(loops)}, options).report.holes.at(0);
    ASSERT_TRUE(report.filled) << report.reason;
    EXPECT_EQ(report.start, StartKind::Unguarded);
    const std::string named = "the time limit passed before a start that crosses nothing";
    EXPECT_NE(report.warning.find(named), std::string::npos) << report.warning;
    EXPECT_EQ(report.warning.find("untangling did not clear them"), std::string::npos)
        << report.warning;
    if (fallback) {
      ASSERT_FALSE(report.fallback_reasons.empty());
      EXPECT_NE(report.fallback_reasons.front().find(named), std::string::npos)
          << report.fallback_reasons.front();
    }
  }
}

// Closing a flat flap of cloth (hanging through a sheet's hole) by its
// outer edge, asked for explicitly, puts the patch onto the flap itself: a
// start that lies on what it must not cross touches it, and is no start that
// crosses nothing. Whatever start the fill reports as clean, its output
// crosses nothing.
TEST(Inpaint, AStartLyingOnTheClothIsNotClean) {
  Mesh mesh = sheet_over_a_spike(1);
  mesh.faces.resize(mesh.faces.size() - 6);  // the spike's faces
  mesh.positions.resize(mesh.positions.size() - 5);
  const int first = mesh.vertex_count(), columns = 6, rows = 12;
  for (int r = 0; r <= rows; ++r)
    for (int c = 0; c <= columns; ++c)
      mesh.positions.push_back({1.7 + 0.6 * c / columns, 2.0, -0.2 + 2.2 * r / rows});
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < columns; ++c) {
      const int a = first + r * (columns + 1) + c, b = a + 1, d = a + columns + 1, e = d + 1;
      mesh.faces.push_back({a, b, e});
      mesh.faces.push_back({a, e, d});
    }
  const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh);
  ASSERT_EQ(loops.size(), 3u);
  int flap = -1;
  for (const BoundaryLoop& loop : loops)
    if (loop.vertices.front() >= first) flap = loop.id;
  ASSERT_GE(flap, 0);
  const FillResult result = fill_holes(mesh, loops, {flap}, FillOptions{});
  const HoleReport& report = result.report.holes.at(0);
  ASSERT_TRUE(report.filled) << report.reason;
  if (report.start != StartKind::Unguarded && report.method != FillMethod::Smooth &&
      report.method != FillMethod::Liepa && report.method != FillMethod::Triangulation) {
    EXPECT_EQ(report.crossings.total(), 0) << to_string(report.start);
  }
}

// Where no start crosses nothing and every fallback crosses something too,
// the fabric fill is minimised unguarded from the start its first attempt
// found: the same patch as with the fallbacks off.
TEST(Inpaint, AFabricFillDeferredPastTheFallbacksIsTheUnguardedOne) {
  const Mesh mesh = sheet_over_a_spike(1);
  const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh);
  FillOptions options;
  options.start.untangle.rounds = 0;
  const FillResult deferred = fill_holes(mesh, loops, {spike_hole(loops)}, options);
  options.fallback.enabled = false;
  const FillResult direct = fill_holes(mesh, loops, {spike_hole(loops)}, options);
  const HoleReport& report = deferred.report.holes.at(0);
  EXPECT_EQ(report.method, FillMethod::Fabric);
  EXPECT_EQ(report.start, StartKind::Unguarded);
  EXPECT_EQ(report.fallback_reasons.size(), 4u);
  EXPECT_TRUE(deferred.mesh.positions == direct.mesh.positions);
  EXPECT_TRUE(deferred.mesh.faces == direct.mesh.faces);
}

}  // namespace
}  // namespace foldfill
