// The fill report as JSON, the form scripts rely on: every key, its unit and
// its meaning are in docs/report.md.
#pragma once

#include <nlohmann/json.hpp>
#include <vector>

#include "foldfill/holes.h"
#include "foldfill/inpaint.h"

namespace foldfill {

// foldfill's version, the project version of CMakeLists.txt ("0.1.0").
const char* version();

// A hole's figures (the paper's quality measures among them, section 4;
// METHOD.md 3); those its method does not measure (the fabric method's
// for the others, all of them for a hole left open) are null.
nlohmann::json to_json(const HoleReport& hole);
nlohmann::json to_json(const FillReport& report);

// The fabric method's parameters in `options`, after the prototype's mapping
// (apply_prototype_weights): a weight that depends on the hole's length scale
// (the prototype's quadratic bending weight) is null, each hole's `lambda`
// being the one used; those the solver does not use (the descent step with
// the fast solver, the coarse start with gradient descent) are null too.
nlohmann::json to_json(const FillOptions& options);

// "quadratic", "two-ring" (as the command line spells them).
const char* to_string(BendingModel bending);
// "fast", "gd".
const char* to_string(SolverKind kind);

// The loops that `report` filled, ascending.
std::vector<int> filled_loops(const FillReport& report);

// Every loop of `loops` left open, ascending: those `choice` left open and
// those it chose that were not filled, each {"loop_id", "kind" (json_name of
// its LoopKind), "reason"}: the choice's reason (json_name of ChoiceReason),
// or "failed" or "cancelled" (HoleStatus) for a chosen loop.
nlohmann::json left_open_loops(const std::vector<BoundaryLoop>& loops, const HoleChoice& choice,
                               const FillReport& report);

}  // namespace foldfill
