// As-rigid-as-possible initialisation (Sorkine & Alexa 2007) of the patch with
// a shrunk rest shape, as in section 3.3 of Gisbert et al. 2023.
#pragma once

#include <vector>

#include "foldfill/budget.h"
#include "foldfill/domain.h"

namespace foldfill {

struct ArapOptions {
  double shrink = 0.5;  // c: the rest shape is the flat state scaled by c
  int iterations = 30;  // at most
  // Stop once no free vertex moved more than this many mean rest edge lengths
  // in one iteration. The result only starts the minimisation: a tighter
  // value costs iterations and leaves the final energies as they are, while a
  // looser one lets curved patches (sphere caps) settle in higher minima
  // (docs/benchmarks.md, "Figures behind the code's choices"). Any change of
  // the start moves some folded patches to another minimum of about the same
  // energy, so this value is part of the results.
  double tolerance = 3e-4;
};

// Returns positions (normalised, as in the domain) of all domain vertices;
// fixed vertices keep their positions. Starts from the flat patch mapped by
// the best-fitting similarity of the flat loop onto its 3D positions. The
// cotan system is factored once; iterates until the tolerance or the cap, or
// until `budget` is spent (looked at before each iteration; the positions
// reached are returned).
std::vector<Vec3> arap_embed(const EmbedDomain& domain, const ArapOptions& options = {},
                             const Budget& budget = {});

// The taut membrane over the strip: the free vertices where the cotan
// Laplacian of the flat rest state vanishes (each at the weighted mean of its
// neighbours), the fixed ones in place. It lies within the convex hull of the
// strip and, spanning the loop like a soap film, rarely crosses anything:
// the fill falls back to it when its start does (see fill_holes).
std::vector<Vec3> membrane_embed(const EmbedDomain& domain);

}  // namespace foldfill
