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

// The ARAP start of the embedding (paper section 3.3; METHOD.md 2a): returns
// positions (normalised, as in the domain) of all domain vertices; fixed
// vertices keep their positions. Starts from the flat patch mapped by the
// best-fitting similarity of the flat loop onto its 3D positions. The cotan
// system is factored once; iterates until the tolerance or the cap, or until
// `budget` is spent (looked at before each iteration; the positions reached
// are returned). Precondition: `domain` from make_embed_domain. Throws
// UsageError for a shrink factor that is not positive or a negative
// tolerance, NonFiniteCoordinateError for a fixed position that is not
// finite, FillFailedError when the solve gives non-finite positions, and
// InternalError for a domain whose parts do not match.
std::vector<Vec3> arap_embed(const EmbedDomain& domain, const ArapOptions& options = {},
                             const Budget& budget = {});

// The taut membrane over the strip: the free vertices where the cotan
// Laplacian of the flat rest state vanishes (each at the weighted mean of its
// neighbours), the fixed ones in place. It lies within the convex hull of the
// strip and, spanning the loop like a soap film, rarely crosses anything:
// the fill falls back to it when its start does (see fill_holes). Not in the
// paper. Precondition and throws: as arap_embed.
std::vector<Vec3> membrane_embed(const EmbedDomain& domain);

}  // namespace foldfill
